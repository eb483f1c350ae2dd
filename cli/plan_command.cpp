// probefilter plan SCENE.json: the passes a scene calls for, and why.
#include <fmt/format.h>

#include "commands.h"
#include "probe/plan.h"
#include "scene_taps.h"

namespace probefilter {

void addPlanCommand(CLI::App& app) {
    auto scenePath = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("plan", "Print the passes a scene calls for and why (computes nothing)");
    cmd->add_option("scene", *scenePath, "Scene file (JSON)")->required();
    cmd->callback([scenePath] {
        const probe::Scene scene = probe::readScene(*scenePath);
        const probe::Plan plan = probe::makePlan(
            scene, [&](const probe::SceneProbe& p) { return sceneProbeTaps(scene, p); }, hasCharlieTable);
        for (const std::string& line : plan.explain()) fmt::print("{}\n", line);
        if (plan.passes().empty()) fmt::print("nothing to compute: no material reads any probe\n");
    });
}

} // namespace probefilter
