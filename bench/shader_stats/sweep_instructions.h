// Instructions per output texel for every method of a sweep (probefilter sweep's report.json): the
// filter shader that runs the method, the cost of its code outside the loop and of a tap or sample
// (LoopCost), and the taps or samples per texel that the sweep counted for that shader. A static cost
// on the statistics device, not a time. The cube methods are costed with hardware sampling, which a
// GPU runs; FIS on the dual-paraboloid map with its one path, exact reads of a buffer.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shader_stats.h"

namespace probe::stats {

// The loop (a loopVariants() name) that filters a sweep method of this family ("table", "fis",
// "fis-mix" or "fis-paraboloid") and, for a table, form ("quad" or "const"). Throws ProbeError for
// any other.
std::string sweepMethodLoop(const std::string& family, const std::string& form);

// instructions.json: the device, and per method of the report (its "methods": method, family, form,
// shader_taps_per_texel) the loop and the instructions per output texel. `costs` holds every loop
// that a method needs. Throws ProbeError naming the method where the report lacks a field.
nlohmann::json sweepInstructions(const nlohmann::json& report, const std::vector<LoopCost>& costs, const std::string& device,
                                 const std::string& driver);

} // namespace probe::stats
