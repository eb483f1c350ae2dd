// The Lambertian irradiance a filter command writes beside the GGX levels when asked
// (--irradiance): the 9-coefficient SH projected on the device, the exact cosine convolution as a
// small cube on the CPU (probe/irradiance.h), or both, with SH measured against the cube.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "probe/cube_image.h"
#include "probe/runtime.h"
#include "probe/sh.h"
#include "probe/staged_output.h"

namespace probefilter {

enum class IrradianceOutput { none, sh, cube, both };
// "none", "sh", "cube" or "both" (ProbeError naming --irradiance otherwise).
IrradianceOutput parseIrradianceOutput(const std::string& name);

struct IrradianceResult {
    nlohmann::json report;      // the report's "irradiance" entry
    probe::ShCoefficients sh{}; // the SH irradiance, where computed (the spheres shade with it)
    std::vector<probe::gpu::Dispatch> shDispatches;
};

// Into `folder` (empty, or ending in '/') of the output: sh: irradiance_sh.exr (the SH irradiance
// evaluated on a probe::kIrradianceCubeSize cube) and the coefficients; cube: irradiance.exr; both:
// both, and "sh_against_cube".
IrradianceResult writeIrradiance(probe::StagedOutput& output, const std::string& folder, IrradianceOutput which,
                                 const probe::gpu::Device& device, const probe::CubeImage& source);

} // namespace probefilter
