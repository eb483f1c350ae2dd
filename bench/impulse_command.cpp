// probebench impulse: the impulse-response L1 per level of tap tables and FIS settings at the tables'
// face size, on the CPU alone: no device and no reference images (the sweep's exact reference is
// quadratic in the texel count, days at 1024^2), so a table meets FIS at any size it is fitted for.
// Against the tables' lobe; for Charlie (sheen) also the cheap stand-in engines use, the exact GGX
// levels read at the sheen roughness. A table's taps are measured as fitted, at the levels it hands to
// FIS too (the FIS rows measure those). Prints a Markdown table: per method, the mean L1 over the
// stratified texels of each level.
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "bench_commands.h"
#include "probe/error.h"
#include "probe/fis.h"
#include "probe/impulse_error.h"
#include "probe/limits.h"
#include "probe/reference.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"

namespace probefilter {

namespace {

struct ImpulseOptions {
    std::vector<std::string> tables;
    std::vector<int> samples{32};
    std::vector<double> biases{0.0, 0.5, 1.0};
    int texelBudget = 128;
};

struct ImpulseMethod {
    std::string name;
    probe::TapGenerator taps;
    probe::PyramidSettings pyramid;
    probe::ImpulseResponse response; // instead of taps
};

void runImpulse(const ImpulseOptions& o) {
    for (int samples : o.samples)
        if (samples < 1 || samples > probe::kMaxSamples)
            throw probe::ProbeError(fmt::format("--samples {}: must be 1 to {}", samples, probe::kMaxSamples));
    std::vector<probe::TapTable> tables;
    for (const std::string& path : o.tables) {
        tables.push_back(probe::readTable(path));
        const probe::TapTable& t = tables.back();
        const probe::TapTable& first = tables.front();
        if (t.faceSize != first.faceSize || t.levelCount != first.levelCount || !(t.mapping == first.mapping) || t.lobe != first.lobe)
            throw probe::ProbeError(
                fmt::format("{}: face size {}, {} levels, its mapping or its lobe differ from {}'s (size {}, {} levels)", path, t.faceSize,
                            t.levelCount, o.tables.front(), first.faceSize, first.levelCount));
    }
    const probe::TapTable& shape = tables.front();
    std::vector<ImpulseMethod> methods;
    for (std::size_t k = 0; k < tables.size(); ++k)
        methods.push_back({std::filesystem::path(o.tables[k]).stem().string(), probe::tableTapGenerator(tables[k]), tables[k].pyramid, {}});
    for (int samples : o.samples)
        for (double bias : o.biases) {
            probe::FisSettings fis;
            fis.samples = samples;
            fis.bias = bias;
            methods.push_back({fmt::format("fis{}-bias{}", samples, bias),
                               probe::fisTapGenerator(shape.faceSize, shape.levelCount, shape.mapping, fis, shape.lobe),
                               fis.pyramid,
                               {}});
        }
    // Filament's sheen: the GGX levels, whose roughness is the sheen roughness (exact, so that what
    // shows is the lobe's difference alone).
    const probe::CubeGeometry geometry(shape.faceSize);
    int level = 0;
    if (shape.lobe == probe::Lobe::charlie)
        methods.push_back({"ggx-levels", {}, {}, [&](const probe::Texel& texel) {
                               const probe::LevelLobe ggx{probe::Lobe::ggx, probe::levelAlpha(shape.mapping, level, shape.levelCount)};
                               return probe::referenceKernel(probe::texelDirection(texel, shape.faceSize >> level), geometry, ggx);
                           }});

    std::vector<int> levels;
    for (int m = 0; m < shape.levelCount; ++m)
        if (probe::tableLevelAlpha(shape, m) > 0.0) levels.push_back(m);
    fmt::print(
        "Impulse-response L1 against the {} lobe at {}^2, {} levels, mean over {} stratified texels per level (probebench impulse)\n\n",
        probe::lobeName(shape.lobe), shape.faceSize, shape.levelCount, o.texelBudget);
    std::string header = "| method |", rule = "|---|";
    for (const int m : levels) {
        header += fmt::format(" level {} |", m);
        rule += "---|";
    }
    fmt::print("{}\n{}\n", header, rule);
    for (const ImpulseMethod& method : methods) {
        const std::vector<probe::DownsampleOperator> operators = probe::pyramidOperators(shape.faceSize, method.pyramid);
        std::vector<std::string> cells;
        for (const int m : levels) {
            level = m;
            const std::vector<probe::WeightedTexel> texels = probe::stratifiedTexels(shape.faceSize >> m, o.texelBudget);
            const probe::ImpulseError e =
                method.response
                    ? probe::impulseError(method.response, shape.faceSize, shape.levelCount, shape.mapping, shape.lobe, m, texels)
                    : probe::impulseError(method.taps, operators, shape.faceSize, shape.levelCount, shape.mapping, shape.lobe, m, texels);
            cells.push_back(fmt::format("{:.4f}", e.mean));
            probe::printToStderr(fmt::format("impulse: {} level {}: {:.4f}\n", method.name, m, e.mean));
        }
        fmt::print("| {} | {} |\n", method.name, fmt::join(cells, " | "));
    }
}

} // namespace

void addImpulseCommand(CLI::App& app) {
    auto o = std::make_shared<ImpulseOptions>();
    CLI::App* cmd = app.add_subcommand("impulse", "Impulse-response L1 per level of tables and FIS at the tables' size, on the CPU alone");
    cmd->add_option("tables", o->tables, "Table files (*.json) of one face size, level count and mapping; FIS follows them")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--samples", o->samples, fmt::format("FIS sample counts (each 1 to {})", probe::kMaxSamples))->capture_default_str();
    cmd->add_option("--fis-bias", o->biases, "FIS level biases")->capture_default_str();
    cmd->add_option("--texels", o->texelBudget, "Stratified output texels per level (a level with fewer measures all)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1 << 20));
    cmd->callback([o] { runImpulse(*o); });
}

} // namespace probefilter
