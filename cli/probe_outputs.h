// The files every filtering command writes for a filtered probe: level EXRs, optional KTX2, the
// preview picture; what was written goes into the report.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "probe/cube_image.h"
#include "probe/ktx2.h"
#include "probe/probe_io.h"
#include "probe/roughness.h"
#include "probe/runtime.h"
#include "probe/staged_output.h"

namespace probefilter {

// --ktx2 FORMAT ("none", "rgba16f", "rgba32f", "rgb9e5" or "bc6h") and --ktx2-zstd (which needs a format);
// ProbeError otherwise.
std::optional<probe::Ktx2Settings> ktx2Options(const std::string& format, bool zstd);

// Writes `name` (a KTX2 cube of every level; a level not computed, empty in `levels`, is black and
// the metadata key probefilter.computed_levels lists the others) and returns its report entry.
// Clamping to the format's range is counted and warned about on stderr. BC6H is encoded on `device`
// (without one, on the default device).
nlohmann::json writeProbeKtx2(probe::StagedOutput& output, const std::string& name, const probe::CubeLevels& levels,
                              probe::RoughnessMapping mapping, probe::Ktx2Settings settings, const probe::gpu::Device* device);

// Into `folder` (empty, or ending in '/') of the output: level_<m>.exr for every level, probe.ktx2
// when asked (clamping to the format's range is counted in the report and warned about on stderr),
// preview.png.
void writeFilteredProbe(probe::StagedOutput& output, const std::string& folder, const probe::CubeLevels& levels,
                        const probe::RoughnessMapping& mapping, std::optional<probe::Ktx2Settings> ktx2, const probe::gpu::Device* device,
                        nlohmann::json& report);

} // namespace probefilter
