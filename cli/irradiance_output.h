// The Lambertian irradiance a filter command writes beside the GGX levels when asked
// (--irradiance): the 9-coefficient SH projected on the device, the exact cosine convolution as a
// small cube on the CPU (probe/irradiance.h), or both, with SH measured against the cube.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "probe/cube_image.h"
#include "probe/runtime.h"
#include "probe/staged_output.h"

namespace probefilter {

enum class IrradianceOutput { none, sh, cube, both };
// "none", "sh", "cube" or "both" (ProbeError naming --irradiance otherwise).
IrradianceOutput parseIrradianceOutput(const std::string& name);

// sh: irradiance_sh.exr (the SH irradiance evaluated on a probe::kIrradianceCubeSize cube) and the
// coefficients; cube: irradiance.exr; both: both, and "sh_against_cube". Returns the report's
// "irradiance" entry.
nlohmann::json writeIrradiance(probe::StagedOutput& output, IrradianceOutput which, const probe::gpu::Device& device,
                               const probe::CubeImage& source);

} // namespace probefilter
