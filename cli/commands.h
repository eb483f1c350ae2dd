// The probefilter subcommands (each registers its options and runs when chosen), and the help that
// they and probebench's share.
#pragma once

#include <CLI/CLI.hpp>

#include "probe/limits.h"

namespace probefilter {

// The help of the options that every command running on a Vulkan device shares.
inline constexpr const char* kDeviceHelp =
    "Vulkan device: index or part of its name (default: a discrete GPU, else integrated, else virtual, else a CPU device such as lavapipe)";
inline constexpr const char* kSamplingHelp =
    "How the GPU reads the pyramid: hardware (a cube image through the seamless sampler), exact "
    "(the CPU model's arithmetic over a buffer) or automatic (hardware on GPUs, exact on CPU devices)";

inline constexpr const char* kLevelsHelp = "Output level count M (default: one per --roughness value, else max(1, log2 S_0))";
inline constexpr const char* kLobeHelp =
    "The lobe filtered with: ggx (specular) or charlie (the sheen of KHR_materials_sheen; no level is a copy); a table must be fitted "
    "for it";
inline constexpr const char* kMappingHelp = "Roughness per level: gltf (the default), authors, filament or unity";
inline constexpr const char* kRoughnessHelp =
    "Roughness per level instead of a named mapping: a comma-separated list, level 0 first, increasing, in [0, 1] (e.g. "
    "0,0.2,0.4,0.6,0.8,1); a table for it is fitted with probefit fit --roughness";

inline constexpr const char* kForceHelp =
    "Replace --out even when it is a non-empty folder that probefilter did not write (the root folder and a folder holding an input "
    "are refused still)";

// The GPU commands' face size: the stated limit, and the device's own, checked before the work.
static_assert(probe::kMaxFaceSize == 2048, "kGpuSizeHelp states the face-size limit");
inline constexpr const char* kGpuSizeHelp =
    "Output face size S_0, a power of two, at most 2048; exact sampling (and the box pyramid) reads per-texel buffers of every "
    "pyramid level as texel buffers, which the device's maxTexelBufferElements must hold (33.6 million texels at 2048^2, 70.0 "
    "million for FIS on the paraboloid map; lavapipe and the common GPUs hold 2^27), hardware sampling none; the reference's sums "
    "need a storage buffer of every output level "
    "(512 MiB at 2048^2); refused up front otherwise";

inline constexpr const char* kAllowLongHelp =
    "Run the CPU reference even when its estimate (printed up front) is over an hour; it is quadratic in the face size (days at 2048)";

void addReferenceCommand(CLI::App& app);
void addSynthCommand(CLI::App& app);
void addFilterCommand(CLI::App& app);
void addPlanCommand(CLI::App& app);
void addRunCommand(CLI::App& app);

} // namespace probefilter
