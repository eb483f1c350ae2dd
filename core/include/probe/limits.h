// The largest inputs probefilter and probefit accept, in one place. Each is checked before the work
// or the memory it bounds is taken, and the command lines' --help states the ones they expose.
#pragma once

#include <cstdint>
#include <string>

#include "probe/shared_constants.h"

namespace probe {

// Output face size S_0: a 2048^2 cube of float RGB is 288 MiB per level.
inline constexpr int kMaxFaceSize = 2048;
// Output levels: log2(kMaxFaceSize) + 1, down to 1x1.
inline constexpr int kMaxLevels = 12;
static_assert(kMaxLevels == PROBE_MAX_GROUP_LEVELS, "the GPU runtime's level groups hold every level");
// probefit's base face size: a fit keeps the pyramid's operators and per-thread workspaces of every
// level (about 2.3 GiB at 1024^2, docs/optimizer.md).
inline constexpr int kMaxFitFaceSize = 1024;
// Taps per frame in a tap table (committed tables use 4 to 32).
inline constexpr int kMaxTaps = 64;
// Tap table coefficients, in magnitude (fitted tables stay under 20): far from float32 overflow in the
// polynomials and weight sums the shaders evaluate.
inline constexpr double kMaxTableCoefficient = 1e4;
// Filtered importance sampling: samples per output texel.
inline constexpr int kMaxSamples = 65536;
// Filtered importance sampling: the level bias (a pyramid has at most 12 levels).
inline constexpr double kMaxFisBias = 16.0;
// A scene's probes and materials (each material may become a rendered sphere).
inline constexpr int kMaxSceneProbes = 64;
inline constexpr int kMaxSceneMaterials = 1024;
// The comparison sheet: spheres per row and pixels per sphere.
inline constexpr int kMaxSheetSpheres = 32;
inline constexpr int kMaxSheetCell = 1024;
// Timed repetitions of a run.
inline constexpr int kMaxRepeat = 1000;
// Input images: width x height (16384 x 8192, 1.5 GiB as float RGB) and either side.
inline constexpr std::int64_t kMaxImagePixels = std::int64_t{16384} * 8192;
inline constexpr int kMaxImageSide = 65536;
// EXR channels: OpenEXR decodes every channel of a chunk, whichever are read (a probe needs 3 or 4).
inline constexpr int kMaxExrChannels = 64;
// Table, scene and published-text files are read whole; none needs more.
inline constexpr std::uintmax_t kMaxTextFileBytes = 64u << 20;
// JSON nesting: tables and scenes need 4 levels.
inline constexpr int kMaxJsonDepth = 32;
// JSON values in one document (a 64-tap 12-level table holds under 40000): bounds its tree's memory.
inline constexpr std::int64_t kMaxJsonValues = std::int64_t{1} << 20;

// What is wrong with a probe image of this size, as an image file's header declares it, or empty:
// a size within kMaxImagePixels and kMaxImageSide, and a probe's shape (probe_io.h's layoutOfShape), so that a large
// image of another shape is refused before its pixels are read.
std::string imageSizeProblem(std::int64_t width, std::int64_t height);

// Throws ParameterError("repeat", ...) unless 1 <= repeat <= kMaxRepeat.
void checkRepeat(int repeat);

} // namespace probe
