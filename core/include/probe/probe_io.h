// Probes in and out: EXR, Radiance HDR and KTX2 reading, pixel validation, conversion to a cube of a
// chosen face size, EXR writing.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "probe/cube_image.h"

namespace probe {

// What a probe image may be, for the tools' help.
inline constexpr const char* kProbeImageKinds =
    "EXR, Radiance HDR or KTX2 (a float cube or image), equirectangular (2:1), faces in a 6:1 strip or 1:6 column, or a 4:3 or 3:4 cross";

// Reads an OpenEXR (RGB or RGBA, a layer's RGB or luminance; any pixel type and compression OpenEXR
// reads), Radiance .hdr or KTX2 image (level 0 of a float cube, its faces in a 1:6 column, or of a 2D
// image; probe/ktx2_image.h). Throws ProbeError naming the file and the problem.
Image readImage(const std::filesystem::path& path);

// What to do with NaN and Inf pixels: refuse the file, or set them to 0.
enum class BadPixelPolicy { refuse, repair };

// The pixels checkPixels set to 0. Negative pixels are clamped under either policy: lossy EXR
// compression (DWA) leaves small negatives around bright sources in ordinary HDRIs.
struct PixelRepairs {
    std::size_t negative = 0;  // pixels with a negative channel, clamped to 0
    std::size_t nonFinite = 0; // pixels with a NaN or Inf channel, set to 0 (repair only)
};

// Checks every channel of every pixel and clamps negatives to 0. NaN and Inf: with `refuse`,
// throws ProbeError with the count and the first position; with `repair`, sets them to 0.
PixelRepairs checkPixels(Image& image, const std::filesystem::path& path, BadPixelPolicy policy);

// The layout of the image's shape. Throws ProbeError for any other shape.
ProbeLayout detectLayout(const Image& image, const std::filesystem::path& path);

// Resamples a probe image to a cube of `faceSize`. Each output texel integrates the source over
// its own footprint (solid-angle weighted supersampling at or above the source resolution), so
// energy is kept when shrinking and a small bright source does not alias away.
// Equirectangular convention (glTF-IBL-Sampler's): +Y up, row 0 at +Y, column u = 0.5 + atan2(z, x) / (2 pi).
CubeImage imageToCube(const Image& image, ProbeLayout layout, int faceSize);

// Reads, validates and resamples in one step; `repairs` receives what checkPixels set to 0.
CubeImage loadProbe(const std::filesystem::path& path, int faceSize, BadPixelPolicy policy, PixelRepairs& repairs);

// Writes float32 RGB EXR (ZIP compressed). Throws ProbeError on failure.
void writeExr(const std::filesystem::path& path, const Image& image);

// Output file name of level m: level_<m>.exr.
std::string levelFileName(int level);

} // namespace probe
