// The files every filtering command writes for a filtered probe: level EXRs, optional KTX2, the
// preview picture; what was written goes into the report.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "probe/cube_image.h"
#include "probe/ktx2.h"
#include "probe/probe_io.h"
#include "probe/roughness.h"
#include "probe/staged_output.h"

namespace probefilter {

// "none", "rgba16f" or "rgba32f" (ProbeError otherwise).
std::optional<probe::Ktx2PixelFormat> parseKtx2Option(const std::string& name);

// Writes `name` (a KTX2 cube of every level; a level not computed, empty in `levels`, is black and
// the metadata key probefilter.computed_levels lists the others) and returns its report entry.
// Clamping to the half range is counted and warned about on stderr.
nlohmann::json writeProbeKtx2(probe::StagedOutput& output, const std::string& name, const probe::CubeLevels& levels,
                              probe::RoughnessMapping mapping, probe::Ktx2PixelFormat format);

// level_<m>.exr for every level, probe.ktx2 when asked (clamping to the half range is counted in
// the report and warned about on stderr), preview.png.
void writeFilteredProbe(probe::StagedOutput& output, const probe::CubeLevels& levels, const probe::RoughnessMapping& mapping,
                        std::optional<probe::Ktx2PixelFormat> ktx2, nlohmann::json& report);

} // namespace probefilter
