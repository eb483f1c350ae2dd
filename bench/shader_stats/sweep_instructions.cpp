#include "sweep_instructions.h"

#include <algorithm>

#include <fmt/format.h>

#include "probe/error.h"

namespace probe::stats {

std::string sweepMethodLoop(const std::string& family, const std::string& form) {
    // A Charlie sweep's GGX levels are a GGX table's, filtered by the same shader.
    if ((family == "table" || family == "ggx-levels") && (form == "quad" || form == "const"))
        return "table_filter_hardware_rgba32f " + form;
    if (family == "fis" || family == "fis-mix") return "fis_hardware_rgba32f";
    if (family == "fis-paraboloid") return "fis_paraboloid_rgba32f";
    throw ProbeError(fmt::format("a sweep method of family '{}' and form '{}': no filter shader costs it", family, form));
}

nlohmann::json sweepInstructions(const nlohmann::json& report, const std::vector<LoopCost>& costs, const std::string& device,
                                 const std::string& driver) {
    nlohmann::json methods = nlohmann::json::array();
    for (const nlohmann::json& m : report.at("methods")) {
        const std::string name = m.at("method").get<std::string>();
        std::string loop;
        double taps = 0.0;
        try {
            loop = sweepMethodLoop(m.at("family").get<std::string>(), m.at("form").get<std::string>());
            taps = m.at("shader_taps_per_texel").get<double>();
        } catch (const nlohmann::json::exception& e) {
            throw ProbeError(fmt::format("method {}: {}", name, e.what()));
        }
        const auto cost = std::find_if(costs.begin(), costs.end(), [&](const LoopCost& c) { return c.loop.name == loop; });
        if (cost == costs.end()) throw ProbeError(fmt::format("method {}: the loop {} was not measured", name, loop));
        // A table's levels handed to FIS count at the table's loop, a tap per sample: above FIS's own cost
        // (on RDNA2 55 instructions a quadratic tap, 41 a sample).
        methods.push_back({{"method", name},
                           {"loop", loop},
                           {"shader_taps_per_texel", taps},
                           {"instructions_per_texel", cost->instructionsPerTexel(taps)}});
    }
    nlohmann::json loops = nlohmann::json::object();
    for (const LoopCost& c : costs)
        loops[c.loop.name] = {{"outside_the_loop", c.fixedInstructions()}, {"per_" + c.loop.unit, c.runtimeInstructionsPerUnit()}};
    return {{"device", {{"name", device}, {"driver", driver}}},
            {"sampling", "hardware; fis-paraboloid exact (its only path)"},
            {"loops", loops},
            {"methods", methods}};
}

} // namespace probe::stats
