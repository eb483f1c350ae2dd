// shader_stats: the static GPU cost of every compute pipeline of the runtime, from the Vulkan driver's
// pipeline statistics, as Markdown tables (bench/scripts/shader-stats runs it on RADV's null device); with
// --sweep DIR, the instructions per output texel of every method of the sweep in DIR, written to
// DIR/instructions.json. Exit codes: 0 success, 2 bad input or failure.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "probe/error.h"
#include "shader_stats.h"
#include "sweep_instructions.h"

namespace {

using probe::stats::LoopCost;
using probe::stats::PipelineStatistics;

std::string value(int64_t v) { return v < 0 ? "n/a" : std::to_string(v); }

void printPipelines(const probe::stats::StatisticsDevice& device) {
    fmt::print("| pipeline | instructions | vector memory | VGPRs | SGPRs | spilled VGPRs | spilled SGPRs | latency (cycles) | "
               "inverse throughput |\n");
    fmt::print("|---|---|---|---|---|---|---|---|---|\n");
    for (const probe::stats::ShaderVariant& v : probe::stats::runtimeVariants()) {
        const PipelineStatistics s = device.compile(v.spirv, v.specialization);
        fmt::print("| `{}` | {} | {} | {} | {} | {} | {} | {} | {} |\n", v.name, value(s.instructions), value(s.vectorMemory),
                   value(s.vgprs), value(s.sgprs), value(s.spilledVgprs), value(s.spilledSgprs), value(s.latency),
                   value(s.inverseThroughput));
    }
}

// The cost of the table with N taps per frame and FIS with S samples per output texel.
void printPerTexel(const std::vector<LoopCost>& costs, const std::vector<int>& taps, const std::vector<int>& samples) {
    const double frames = probe::stats::tableFramesPerTexel();
    fmt::print("\nInstructions per output texel: the instructions outside the loops, plus {:.4g} frames x N taps (table) or S samples "
               "(FIS) times the runtime loop's instructions per tap or sample.\n\n",
               frames);
    fmt::print("| pipeline | count | instructions per texel |\n|---|---|---|\n");
    for (const LoopCost& cost : costs) {
        const bool table = cost.loop.unit == "tap";
        for (int count : table ? taps : samples) {
            const double units = table ? frames * count : count;
            fmt::print("| `{}` | {} {} | {:.0f} |\n", cost.loop.name, table ? "N =" : "S =", count, cost.instructionsPerTexel(units));
        }
    }
}

int run(const std::vector<int>& taps, const std::vector<int>& samples) {
    const probe::stats::StatisticsDevice device;
    fmt::print("Device: {}, {}. Static statistics of the compiled code: instructions and registers, not a time.\n\n", device.name(),
               device.driver());
    printPipelines(device);

    std::vector<LoopCost> costs;
    fmt::print("\nPer tap (table) and per sample (FIS): the loop body is the difference between two compilations with fixed, unrolled "
               "counts; the runtime's loop adds its counting and branching (its pipeline's instructions beyond those outside the "
               "loop). Vector memory: the body's vector memory instructions (reads through the texture units) per tap or sample.\n\n");
    fmt::print("| pipeline | loop body | runtime loop | vector memory | outside the loop | taps or samples in the code | instructions | "
               "VGPRs |\n"
               "|---|---|---|---|---|---|---|---|\n");
    for (const probe::stats::LoopVariant& loop : probe::stats::loopVariants()) {
        const LoopCost& cost = costs.emplace_back(probe::stats::measureLoop(device, loop));
        fmt::print("| `{}` | {:.1f} per {} | {:.1f} per {} | {:.2f} | {:.0f} | {} / {} | {} / {} | {} / {} |\n", loop.name,
                   cost.instructionsPerUnit(), loop.unit, cost.runtimeInstructionsPerUnit(), loop.unit, cost.vectorMemoryPerUnit(),
                   cost.fixedInstructions(), loop.unitsA, loop.unitsB, cost.a.instructions, cost.b.instructions, value(cost.a.vgprs),
                   value(cost.b.vgprs));
    }
    printPerTexel(costs, taps, samples);
    return 0;
}

// DIR/report.json's methods costed into DIR/instructions.json; nothing is written unless every method is.
int runSweep(const std::filesystem::path& dir) {
    const std::filesystem::path reportPath = dir / "report.json", outPath = dir / "instructions.json";
    nlohmann::json report;
    try {
        std::ifstream in(reportPath);
        if (!in) throw probe::ProbeError(fmt::format("{}: cannot read", reportPath.string()));
        report = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw probe::ProbeError(fmt::format("{}: not a sweep report ({})", reportPath.string(), e.what()));
    }
    const probe::stats::StatisticsDevice device;
    std::vector<LoopCost> costs;
    for (const probe::stats::LoopVariant& loop : probe::stats::loopVariants()) costs.push_back(probe::stats::measureLoop(device, loop));
    nlohmann::json instructions;
    try {
        instructions = probe::stats::sweepInstructions(report, costs, device.name(), device.driver());
    } catch (const std::exception& e) {
        throw probe::ProbeError(fmt::format("{}: {}", reportPath.string(), e.what()));
    }
    std::ofstream out(outPath);
    out << instructions.dump(2) << "\n";
    if (!out) throw probe::ProbeError(fmt::format("{}: cannot write", outPath.string()));
    fmt::print("shader_stats: wrote {} ({} methods, {})\n", outPath.string(), instructions["methods"].size(), device.name());
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"shader_stats: static GPU cost (instructions, registers) of the runtime's compute pipelines"};
    std::vector<int> taps{4, 8, 16, 32};
    std::vector<int> samples{32, 128, 256, 1024};
    app.add_option("--taps", taps, "table taps per frame N for the per-texel costs")->delimiter(',')->check(CLI::Range(1, 1 << 16));
    app.add_option("--samples", samples, "FIS samples S for the per-texel costs")->delimiter(',')->check(CLI::Range(1, 1 << 16));
    std::string sweep;
    app.add_option("--sweep", sweep,
                   "A probefilter sweep's output folder: write instructions.json there, the instructions per output texel of its "
                   "methods, instead of the tables");
    try {
        app.parse(argc, argv);
        return sweep.empty() ? run(taps, samples) : runSweep(sweep);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        fmt::print(stderr, "shader_stats: error: {}\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        fmt::print(stderr, "shader_stats: error: {}\n", e.what());
        return 2;
    }
}
