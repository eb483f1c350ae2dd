// probefit: fits tap tables (Manson & Sloan) for a base face size, level count and tap count, and
// evaluates tables. Bad input: one line naming the option or file, exit code 2, nothing written.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>

#include "evaluate.h"
#include "fit.h"
#include "fit_estimate.h"
#include "initial_layout.h"
#include "probe/committed_tables.h"
#include "probe/error.h"
#include "probe/interrupt.h"
#include "probe/limits.h"
#include "probe/output_file.h"
#include "probe/staged_output.h"
#include "probe/table_io.h"
#include "seam_select.h"
#include "table_mix.h"
#include "table_outputs.h"
#include "tail_check.h"

namespace {

using namespace probe;
using probefit::TexelSet;

template <typename Parse>
auto parseOption(std::string_view option, const std::string& value, Parse parse) {
    try {
        return parse(value);
    } catch (const ParameterError& e) {
        // "<flag> <value>: <problem>" names the option already.
        if (parameterFlag(e.parameter) == option) throw ProbeError(messageWithFlag(e));
        throw ProbeError(fmt::format("{}: {}", option, e.what()));
    } catch (const ProbeError& e) {
        throw ProbeError(fmt::format("{}: {}", option, e.what()));
    }
}

// Counts a fit takes: bounded, so that no setting runs for years or overflows the estimate.
constexpr int kMaxIterations = 100000;
constexpr int kMaxStarts = 64;
constexpr int kMaxHops = 64;
constexpr int kMaxTexelBudget = 1 << 20;

void checkCount(std::string_view option, int value, int lowest, int highest) {
    if (value < lowest || value > highest)
        throw ProbeError(fmt::format("{}: {} is not a count from {} to {}", option, value, lowest, highest));
}

probefit::Measure parseMeasure(const std::string& name) {
    if (name == "cells") return probefit::Measure::cells;
    if (name == "exact") return probefit::Measure::exact;
    throw ProbeError(fmt::format("'{}' is neither cells nor exact", name));
}

// A level number or count: digits only (no sign, nothing empty), at most 3 of them.
bool isLevelNumber(const std::string& text) {
    return !text.empty() && text.size() <= 3 && text.find_first_not_of("0123456789") == std::string::npos;
}

int parseLevelCount(const std::string& text) {
    if (!isLevelNumber(text)) throw ProbeError(fmt::format("'{}' is not a level count", text));
    return std::stoi(text);
}

// A comma-separated list of level numbers, none empty.
std::vector<int> parseLevelList(const std::string& text) {
    std::vector<int> levels;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = std::min(text.find(',', start), text.size());
        const std::string entry = text.substr(start, end - start);
        if (!isLevelNumber(entry)) throw ProbeError(fmt::format("'{}' is not a comma-separated list of level numbers", text));
        levels.push_back(std::stoi(entry));
        if (end == text.size()) return levels;
        start = end + 1;
    }
}

// The bank's tables with the fit's taps, pyramid and lobe, by name.
std::vector<probefit::FitSettings::BankTable> readBank(const std::string& folder, const probefit::FitSettings& settings) {
    std::vector<probefit::FitSettings::BankTable> bank;
    if (folder == "none") return bank;
    const std::filesystem::path path = folder.empty() ? committedTablesFolder() : std::filesystem::path(folder);
    std::error_code error;
    if (!std::filesystem::is_directory(path, error)) throw ProbeError(fmt::format("--bank {}: not a folder", path.string()));
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(path, error))
        if (entry.path().extension() == ".json" && entry.is_regular_file(error)) files.push_back(entry.path());
    if (error) throw ProbeError(fmt::format("--bank {}: {}", path.string(), error.message()));
    std::ranges::sort(files);
    for (const std::filesystem::path& file : files) {
        TapTable table = readTable(file.string());
        if (table.taps == settings.taps && table.pyramid == settings.pyramid && table.lobe == settings.lobe)
            bank.push_back({file.stem().string(), std::move(table)});
    }
    return bank;
}

int runFit(probefit::FitSettings settings, const std::string& form, const std::string& pyramid, const std::string& weighting,
           const std::string& solver, const std::string& measure, const std::optional<std::string>& fitLevels,
           const std::vector<std::string>& init, const std::string& bank, const std::string& out, bool estimateOnly, bool resume,
           std::optional<int> levels) {
    settings.form = parseOption("--form", form, parseTableForm);
    settings.measure = parseOption("--measure", measure, parseMeasure);
    if (fitLevels) settings.fitLevels = parseOption("--fit-levels", *fitLevels, parseLevelList);
    settings.solver = parseOption("--solver", solver, probefit::parseFitSolver);
    settings.pyramid = {parseOption("--pyramid", pyramid, parsePyramidKind),
                        parseOption("--pyramid-weighting", weighting, parsePyramidWeighting)};
    if (log2Exact(settings.faceSize) < 1 || settings.faceSize > kMaxFitFaceSize)
        throw ProbeError(fmt::format("--size: face size {} is not a power of two from 2 to {}", settings.faceSize, kMaxFitFaceSize));
    // The level count: --levels, else one per --roughness value, else the size's default (core's rule).
    try {
        settings.levelCount = chooseLevelCount(settings.faceSize, levels, settings.mapping);
    } catch (const ParameterError& e) {
        throw ProbeError(messageWithFlag(e));
    } catch (const ProbeError& e) {
        throw ProbeError(fmt::format("--levels: {}", e.what()));
    }
    if (settings.taps < 4 || settings.taps % 4 != 0 || settings.taps > kMaxTaps)
        throw ProbeError(fmt::format("--taps: {} is not a multiple of 4 from 4 to {}", settings.taps, kMaxTaps));
    checkCount("--iterations", settings.maxIterations, 1, kMaxIterations);
    checkCount("--lm-iterations", settings.lmIterations, 0, kMaxIterations);
    checkCount("--rough-factor", settings.roughIterationFactor, 1, 64);
    if (settings.seamWeight < 0.0 || !std::isfinite(settings.seamWeight))
        throw ProbeError(fmt::format("--seam-weight: {} is not a weight >= 0", settings.seamWeight));
    if (settings.tailWeight < 0.0 || !std::isfinite(settings.tailWeight))
        throw ProbeError(fmt::format("--tail-weight: {} is not a weight >= 0", settings.tailWeight));
    if (settings.checkerWeight < 0.0 || !std::isfinite(settings.checkerWeight))
        throw ProbeError(fmt::format("--checker-weight: {} is not a weight >= 0", settings.checkerWeight));
    checkCount("--starts", settings.starts, 1, kMaxStarts);
    checkCount("--bank-starts", settings.bankStarts, 1, kMaxStarts);
    checkCount("--coarse-iterations", settings.coarseIterations, 0, kMaxIterations);
    checkCount("--hops", settings.hops, 0, kMaxHops);
    checkCount("--seam-pairs", settings.seamPairBudget, 1, kMaxTexelBudget);
    checkCount("--texels", settings.stratifiedBudget, 24, kMaxTexelBudget);
    for (const std::string& path : init) {
        const TapTable& t = settings.inits.emplace_back(readTable(path));
        if (t.faceSize != settings.faceSize || t.levelCount != settings.levelCount ||
            (t.taps != settings.taps && 2 * t.taps != settings.taps))
            throw ProbeError(fmt::format("--init {}: table is for size {}, {} levels, {} taps; this fit is size {}, {} "
                                         "levels, {} taps (the init needs the same size and levels, and N or N/2 taps)",
                                         path, t.faceSize, t.levelCount, t.taps, settings.faceSize, settings.levelCount, settings.taps));
    }
    settings.bank = readBank(bank, settings);
    // After each level the table so far goes to PREFIX.resume.json, which --resume continues from.
    const std::filesystem::path checkpointPath = out + ".resume.json";
    if (!estimateOnly) {
        probefit::checkWritable(out);
        try {
            const StagedFile checkpoint(checkpointPath); // checks, creating nothing
        } catch (const ProbeError& e) {
            throw ProbeError(fmt::format("--out {}: {}", out, e.what()));
        }
    }
    std::optional<TapTable> checkpoint;
    std::error_code error;
    if (resume && !estimateOnly && std::filesystem::exists(checkpointPath, error)) checkpoint = readTable(checkpointPath);
    settings.resume = checkpoint ? &*checkpoint : nullptr;

    fmt::print("probefit: size {}, {} levels, {} taps x 3 frames, {}, mapping {}, lobe {}, pyramid {} {}, {} texels per level, "
               "solver {}\n",
               settings.faceSize, settings.levelCount, settings.taps, form, describeRoughnessMapping(settings.mapping),
               lobeName(settings.lobe), pyramid, weighting, settings.stratifiedBudget, solver);
    const probefit::FitEstimate estimate = probefit::estimateFit(settings);
    std::string perLevel;
    for (std::size_t m = 0; m < estimate.levelSeconds.size(); ++m)
        if (estimate.levelSeconds[m] > 0.0)
            perLevel += fmt::format("{}level {} {:.0f} s", perLevel.empty() ? "" : ", ", m, estimate.levelSeconds[m]);
    fmt::print("estimate: about {:.0f} s ({:.1f} min) at the machine's present speed ({})\n", estimate.seconds, estimate.seconds / 60.0,
               perLevel);
    std::fflush(stdout);
    if (estimateOnly) return 0;
    // Where the time goes, summed over levels: reference kernels, the model inside the solver, the
    // solver's own work, and everything else (start candidates, the measurement over all texels).
    double kernels = 0.0, evaluation = 0.0, solverOwn = 0.0, levelTime = 0.0, estimatedDone = 0.0;
    int evaluations = 0;
    const std::string objective = fmt::format("L1{}{}{}", settings.tailWeight > 0.0 ? " + T tail" : "",
                                              settings.checkerWeight > 0.0 ? " + C c" : "", settings.seamWeight > 0.0 ? " + W s" : "");
    // What a progress line's value is: a term's mean, the objective, or the L1.
    auto quantityOf = [](const std::string& stage) {
        if (stage.starts_with("seam term")) return "mean s";
        if (stage.starts_with("checker term")) return "mean c";
        return stage.starts_with("objective") ? "f" : "L1";
    };
    // A level's L1 when done: the exact one it records, or without records the fit's own.
    const char* doneQuantity =
        settings.records == probefit::Records::none && settings.measure == probefit::Measure::cells ? "L1 over cells" : "L1";
    // The checkpoint's unfinished levels hold a lobe layout (a valid filter), unmeasured.
    auto writeCheckpoint = [&](const TapTable& fitted) {
        TapTable snapshot = fitted;
        for (int m = 0; m < snapshot.levelCount; ++m)
            if (!probefit::levelFinished(snapshot.levels[m]) && tableLevelAlpha(snapshot, m) > 0.0)
                probefit::lobeLayout(snapshot, m, tableLevelAlpha(snapshot, m));
        StagedFile file(checkpointPath);
        writeFile(file.path(), tableToJson(snapshot));
        file.commit();
    };
    const TapTable table = probefit::fitTable(
        settings,
        [&](const probefit::FitProgress& p) {
            if (p.stage == "iteration")
                fmt::print("  level {} iteration {:3d}  {} {:.5f}  {:7.1f} s\n", p.level, p.iteration, objective, p.l1, p.seconds);
            else if (p.stage == "done") {
                // Time left: the estimate of the levels to come, at the pace of the estimate so far (at
                // least 0: the sum's rounding would print "-0" after the last level).
                estimatedDone += estimate.levelSeconds[static_cast<std::size_t>(p.level)];
                const double left = estimatedDone > 0.0 ? std::max(0.0, estimate.seconds - estimatedDone) * p.seconds / estimatedDone : 0.0;
                fmt::print("level {} done: {} {:.5f}  {:7.1f} s  ({} iterations; kernels {:.1f} s, model {:.1f} s in {} "
                           "evaluations, solver {:.1f} s); about {:.0f} s left\n",
                           p.level, doneQuantity, p.l1, p.seconds, p.iteration, p.kernelSeconds, p.evaluationSeconds, p.evaluations,
                           p.solverSeconds, left);
                kernels += p.kernelSeconds;
                evaluation += p.evaluationSeconds;
                solverOwn += p.solverSeconds;
                evaluations += p.evaluations;
                levelTime += p.levelSeconds;
            } else if (p.l1 < 0.0) // a level resumed or copied without records
                fmt::print("level {} {}: L1 not measured  {:7.1f} s\n", p.level, p.stage, p.seconds);
            else fmt::print("level {} {}: {} {:.5f}  {:7.1f} s\n", p.level, p.stage, quantityOf(p.stage), p.l1, p.seconds);
            std::fflush(stdout);
        },
        writeCheckpoint);
    // Levels fitted at once overlap: the parts are summed over levels, beside the wall time.
    fmt::print("time: {:.1f} s in all; summed over the levels {:.1f} s: reference kernels {:.1f} s, model in the solver {:.1f} s ({} "
               "evaluations), solver's own work {:.1f} s, other (start candidates{}) {:.1f} s\n",
               table.fitSeconds, levelTime, kernels, evaluation, evaluations, solverOwn,
               settings.records == probefit::Records::none ? "" : ", exact records", levelTime - kernels - evaluation - solverOwn);
    probefit::writeTableOutputs(out, table);
    std::filesystem::remove(checkpointPath, error);
    for (const std::string& line : tableSummary(table)) fmt::print("{}\n", line);
    fmt::print("wrote {0}.json, {0}.h, {0}.glsl\n", out);
    return 0;
}

// Prints the L1 per level; with a tolerance, exits 1 where it differs from the recorded value.
// With `cells`, also the fit's L1 over cells (lobe_cells.h) on the same texels, against the exact one.
// A budget other than the table's measures that many stratified texels, which it has no record of.
// With `recordOut`, the table goes there with the L1 measured as its records.
int runEval(const std::string& path, const std::string& texels, double tolerance, bool cells, std::optional<int> budget,
            const std::string& recordOut) {
    TapTable table = readTable(path);
    if (texels != "all" && texels != "stratified") throw ProbeError(fmt::format("--texels: '{}' is neither all nor stratified", texels));
    if (cells && texels != "stratified") throw ProbeError("--cells: measures the stratified texels alone (--texels stratified)");
    if (budget && texels != "stratified") throw ProbeError("--budget: sets the stratified texels alone (--texels stratified)");
    if (budget) checkCount("--budget", *budget, 24, kMaxTexelBudget);
    const bool recordedTexels = !budget || *budget == table.stratifiedBudget;
    if (!recordOut.empty() && !recordedTexels)
        throw ProbeError(
            fmt::format("--record: the table records {} stratified texels per level, not --budget {}", table.stratifiedBudget, *budget));
    if (!recordOut.empty()) probefit::checkWritable(recordOut, "--record");
    if (budget) table.stratifiedBudget = *budget;
    const TexelSet set = texels == "all" ? TexelSet::all : TexelSet::stratified;
    fmt::print("{}: impulse-response L1 over {} texels{}\n", path, texels,
               set == TexelSet::stratified ? fmt::format(" (budget {} per level)", table.stratifiedBudget) : "");
    bool mismatch = false;
    for (int m = 0; m < table.levelCount; ++m) {
        if (tableLevelAlpha(table, m) <= 0.0) {
            fmt::print("level {} copy of the source\n", m);
            continue;
        }
        const probefit::LevelEvaluation e = probefit::evaluateLevel(table, m, set);
        const ImpulseError& recorded = set == TexelSet::all ? table.levels[m].all : table.levels[m].stratified;
        std::string comparison = "not recorded";
        if (recorded.mean >= 0.0 && recordedTexels) {
            const double difference = std::max(std::abs(e.error.mean - recorded.mean), std::abs(e.error.max - recorded.max));
            comparison = fmt::format("recorded {:.6f} / {:.6f}, difference {:.2e}", recorded.mean, recorded.max, difference);
            if (tolerance >= 0.0 && difference > tolerance) mismatch = true;
        }
        if (cells) {
            const probefit::ImpulseModel model(table.faceSize, table.pyramid, table.taps, table.form);
            const std::vector<probefit::OutputTexel> prepared = probefit::prepareTexels(
                probefit::levelTexels(table, m, set), table.faceSize, m, tableLevelLobe(table, m), false, probefit::Measure::cells);
            const double fast = probefit::evaluatePrepared(model, probefit::levelBlocks(table, m).data(), prepared).error.mean;
            std::size_t cellCount = 0;
            for (const probefit::OutputTexel& texel : prepared) cellCount += texel.cells.size();
            comparison += fmt::format("; over cells {:.6f} ({:+.2f}%), {} cells per texel", fast, 100.0 * (fast / e.error.mean - 1.0),
                                      cellCount / std::max<std::size_t>(prepared.size(), 1));
        }
        fmt::print("level {} mean {:.6f} max {:.6f} worst texel face {} ({}, {}) min weight sum {:.4f}; {}\n", m, e.error.mean, e.error.max,
                   e.error.worst.face, e.error.worst.i, e.error.worst.j, e.minWeightSum, comparison);
        std::fflush(stdout);
        if (!recordOut.empty()) probefit::recordEvaluation(table.levels[m], set, e);
    }
    if (!recordOut.empty()) {
        probefit::writeTableOutputs(recordOut, table, "--record");
        fmt::print("wrote {0}.json, {0}.h, {0}.glsl\n", recordOut);
    }
    if (mismatch) printToStderr(fmt::format("probefit eval: {} differs from its recorded L1 by more than {}\n", path, tolerance));
    return mismatch ? 1 : 0;
}

// Prints per level the share of the reference's tail mass the table puts in the tail; exits 1 where
// some texel with a tail is out of the bound (tail_check.h).
int runTail(const std::string& path) {
    const TapTable table = readTable(path);
    fmt::print("{}: mass beyond {} texels of the level from the lobe centre, table / reference (bound {} to {}; levels with "
               "less than {} of the reference's mass there have no tail)\n",
               path, probefit::kTailTexels, probefit::kTailBound, 1.0 / probefit::kTailBound, probefit::kMinTailMass);
    bool reached = true;
    if (table.lobe != Lobe::ggx) fmt::print("the {} lobe has no tail to check: it is GGX's\n", lobeName(table.lobe));
    for (const probefit::TailLevel& level : probefit::checkTail(table)) {
        std::string line;
        for (const probefit::TailSample& s : level.samples) {
            line += s.hasTail() ? fmt::format("  {} {:.3f} / {:.3f} = {:.2f}{}", s.where, s.tableMass, s.referenceMass, s.fraction(),
                                              s.reached() ? "" : " (out of bound)")
                                : fmt::format("  {} no tail ({:.4f})", s.where, s.referenceMass);
            reached = reached && s.reached();
        }
        fmt::print("level {} radius {:.3f} rad:{}\n", level.level, level.radius, line);
    }
    if (!reached) printToStderr(fmt::format("probefit tail: {} misses the lobe's tail at some level\n", path));
    return reached ? 0 : 1;
}

// Assembles a table level by level from fits of the same shape (seam_select.h) and prints the choice.
int runSelect(const std::vector<std::string>& paths, const std::string& out, bool first) {
    std::vector<probefit::SeamCandidate> candidates;
    for (const std::string& path : paths) candidates.push_back({std::filesystem::path(path).stem().string(), readTable(path)});
    probefit::checkWritable(out);
    const probefit::SeamSelection selection =
        probefit::selectWithinSeamBound(candidates, first ? probefit::SelectOrder::first : probefit::SelectOrder::lowestL1);
    bool allWithin = true;
    for (int m = 0; m < selection.table.levelCount; ++m) {
        const probefit::LevelSelection& level = selection.levels[m];
        std::string ratios;
        for (std::size_t k = 0; k < candidates.size(); ++k)
            ratios += fmt::format("  {} {:.4f} (steps over the reference's: edges {:.3f}x, quarter lines {:.3f}x; L1 {:.4f}{})",
                                  candidates[k].name, level.seamRatios[k], level.edgeSteps[k], level.quarterSteps[k],
                                  candidates[k].table.levels[m].all.mean, level.tailReached[k] ? "" : ", misses the tail");
        fmt::print("level {} bound {:.4f}:{}\n  -> {}{}\n", m, level.bound, ratios, candidates[level.chosen].name,
                   level.withinBound ? "" : " (no fit within the bound: the nearest)");
        allWithin = allWithin && level.withinBound;
    }
    probefit::writeTableOutputs(out, selection.table);
    fmt::print("wrote {0}.json, {0}.h, {0}.glsl{1}\n", out, allWithin ? "" : "; some level is out of the seam bound");
    return 0;
}

// Rewrites a table's outputs, with the levels of `handOffs` ("LEVEL:SAMPLES") handed to FIS with that
// many samples per texel (0: back to the table's taps).
int runExport(const std::string& path, const std::vector<std::string>& handOffs, const std::string& out) {
    TapTable table = readTable(path);
    for (const std::string& handOff : handOffs) {
        const std::size_t colon = handOff.find(':');
        const std::string level = handOff.substr(0, colon), samples = colon == std::string::npos ? "" : handOff.substr(colon + 1);
        // Digits alone, at most 3 for a level and 5 for samples (validateTable bounds them).
        const bool digits =
            isLevelNumber(level) && !samples.empty() && samples.size() <= 5 && samples.find_first_not_of("0123456789") == std::string::npos;
        if (!digits || std::stoi(level) >= table.levelCount)
            throw ProbeError(fmt::format("--fis-level {}: expected LEVEL:SAMPLES, a level of the table (0 to {}) and a sample count",
                                         handOff, table.levelCount - 1));
        table.levels[std::stoi(level)].fisSamples = std::stoi(samples);
    }
    validateTable(table, "--fis-level");
    probefit::checkWritable(out);
    probefit::writeTableOutputs(out, table);
    for (int m = 0; m < table.levelCount; ++m)
        if (table.levels[m].fisSamples > 0) fmt::print("level {}: FIS with {} samples per texel\n", m, table.levels[m].fisSamples);
    return 0;
}

// Assembles a table whose levels use different tap counts (table_mix.h): one source table per level.
int runMix(const std::vector<std::string>& paths, const std::string& out) {
    std::vector<probefit::MixSource> perLevel;
    for (const std::string& path : paths) perLevel.push_back({std::filesystem::path(path).stem().string(), readTable(path)});
    probefit::checkWritable(out);
    const TapTable mixed = probefit::mixTables(perLevel);
    for (int m = 0; m < mixed.levelCount; ++m)
        fmt::print("level {}: {} ({} taps), impulse L1 {:.4f}\n", m, perLevel[m].name, perLevel[m].table.taps, mixed.levels[m].all.mean);
    probefit::writeTableOutputs(out, mixed);
    fmt::print("wrote {0}.json, {0}.h, {0}.glsl ({1} taps per frame, the rest zero weight)\n", out, mixed.taps);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    // An interrupted fit writes no table and leaves no staging file.
    probe::removeStagingOnInterrupt();
    CLI::App app{"probefit: fits and evaluates tap tables for fast GGX filtering of reflection probes"};
    app.require_subcommand(1);
    probefit::FitSettings settings;
    std::string form, mapping, roughness, lobe = "ggx", pyramid = "bspline", weighting = "solid-angle", solver = "lm-bfgs",
                                          measure = "cells", fitLevels, out;
    std::string levels; // not given: the default for the size
    std::string bank;   // not given: the committed tables
    std::vector<std::string> init;
    CLI::App* fit = app.add_subcommand("fit", "fit a tap table: per level, the coefficients whose impulse response is nearest "
                                              "the GGX lobe (writes PREFIX.json, PREFIX.h, PREFIX.glsl)");
    fit->add_option("--size", settings.faceSize, fmt::format("base face size S_0 (a power of two from 2 to {})", kMaxFitFaceSize));
    CLI::Option* levelsOption =
        fit->add_option("--levels", levels, "output levels M (default: one per --roughness value, else max(1, log2 S_0))");
    fit->add_option("--taps", settings.taps, fmt::format("taps per frame N (a multiple of 4 from 4 to {})", kMaxTaps));
    fit->add_option("--form", form, "const or quad");
    CLI::Option* mappingOption = fit->add_option("--mapping", mapping, "roughness per level: gltf (the default), authors, filament, unity");
    fit->add_option("--roughness", roughness,
                    "roughness per level instead of a named mapping: a comma-separated list, level 0 first, increasing, in [0, 1]")
        ->excludes(mappingOption);
    fit->add_option("--lobe", lobe, "the lobe the levels are fitted to: ggx (specular) or charlie (the sheen of KHR_materials_sheen)")
        ->capture_default_str();
    fit->add_option("--pyramid", pyramid, "bspline or box")->capture_default_str();
    fit->add_option("--pyramid-weighting", weighting, "pyramid weighting: solid-angle or inverse-solid-angle (probefilter's name)")
        ->capture_default_str();
    // The flag's earlier name, refused with the one it has now.
    fit->add_option_function<std::string>(
           "--weighting", [](const std::string&) { throw ProbeError("--weighting is now --pyramid-weighting, as in probefilter"); })
        ->group("");
    fit->add_option("--init", init,
                    "table file to start from (same size and levels, N or N/2 taps; repeat for several); the fit "
                    "keeps its filter where it cannot beat it")
        ->allow_extra_args(false);
    fit->add_option("--bank", bank,
                    "tables whose levels of the nearest roughness are starts (any size, level count or mapping; those with "
                    "the fit's taps, pyramid and lobe are used); default: the committed tables; none: no bank");
    fit->add_option("--texels", settings.stratifiedBudget, "stratified output texels per level")->capture_default_str();
    fit->add_option("--measure", measure,
                    "the fit's L1: cells (base texels near the lobe centre, larger squares of them further away: a cost "
                    "that hardly grows with the size) or exact (every base texel); the table's records are exact either way")
        ->capture_default_str();
    fit->add_option("--solver", solver, "lm-bfgs (Levenberg-Marquardt, then BFGS on the L1), bfgs, or lm")->capture_default_str();
    fit->add_option("--lm-iterations", settings.lmIterations, "Levenberg-Marquardt iterations per level of lm-bfgs")->capture_default_str();
    fit->add_option("--iterations", settings.maxIterations, "solver iterations per level (at the full texel budget)")
        ->capture_default_str();
    fit->add_option("--coarse-iterations", settings.coarseIterations,
                    "BFGS iterations per level with every frame's taps tied, on the coarse texels (every few of the stratified "
                    "texels, at least 128), before --iterations on all of them with each frame free; 0: none")
        ->capture_default_str();
    fit->add_option("--rough-factor", settings.roughIterationFactor,
                    "levels with fewer stratified texels get up to this many times the iterations")
        ->capture_default_str();
    fit->add_option("--seam-weight", settings.seamWeight,
                    "weight of the seam term (the step of the response's smooth moments across face edges against "
                    "the reference's) beside the mean L1; 0: off")
        ->capture_default_str();
    fit->add_option("--tail-weight", settings.tailWeight,
                    "weight of the tail term (per texel, the response's mass beyond 3 texels of the lobe centre against "
                    "the reference's) beside the L1; 0: off")
        ->capture_default_str();
    fit->add_option("--checker-weight", settings.checkerWeight,
                    "weight of the checker term (per texel, the response's error on +-1 checkerboards of several "
                    "scales: the aliasing of sharp content) beside the L1; 0: off")
        ->capture_default_str();
    fit->add_option("--seam-pairs", settings.seamPairBudget, "face-edge pairs per level for the seam term")->capture_default_str();
    fit->add_option("--bank-starts", settings.bankStarts,
                    "bank levels per level that start a fit (the best on a few texels); with the best start and --starts, "
                    "each runs Levenberg-Marquardt on the coarse texels and the lowest objective goes on")
        ->capture_default_str();
    fit->add_option("--starts", settings.starts,
                    "fits per level: from the best start and, above 1, from starts - 1 importance layouts (FIS taps, "
                    "turned apart); the lowest objective is kept")
        ->capture_default_str();
    fit->add_flag("--screen-all", settings.screenAll,
                  "with several starts, run each through both solvers (default with lm-bfgs: only the lowest objective after "
                  "Levenberg-Marquardt goes on to BFGS)");
    fit->add_option("--hops", settings.hops,
                    "refits per level from the best fit with its taps moved at random (a step the gradient cannot take); "
                    "each is kept where the objective is lower")
        ->capture_default_str();
    CLI::Option* fitLevelsOption = fit->add_option("--fit-levels", fitLevels,
                                                   "fit only these levels (comma-separated); the others are copied from the "
                                                   "first --init, which must have the table's taps and form");
    fit->add_flag("--fresh", settings.fresh,
                  "the --fit-levels start from the lobe layout and the previous level alone and keep no --init's filter "
                  "(for a refit at a stronger seam or tail weight, which the init's lower L1 would otherwise keep out)");
    bool estimateOnly = false;
    fit->add_flag("--estimate", estimateOnly, "print how long the fit would take, and stop");
    bool resume = false;
    fit->add_flag("--resume", resume,
                  "continue from PREFIX.resume.json, which a fit of the same settings writes after each level (an "
                  "interrupted fit leaves it; a finished one removes it)");
    int jobs = 0;
    fit->add_option("--jobs", jobs, "threads (default: every core); the table is bit for bit the same for any count");
    bool noFullEval = false, noEval = false;
    CLI::Option* noFullEvalOption =
        fit->add_flag("--no-full-eval", noFullEval, "measure the stratified texels exactly after the fit, not every output texel");
    fit->add_flag("--no-eval", noEval,
                  "measure nothing exactly after the fit: the table records no L1 (probefit eval --record measures it); "
                  "the fit alone, whose cost hardly grows with the size")
        ->excludes(noFullEvalOption);
    fit->add_option("--out", out, "output prefix: writes PREFIX.json, PREFIX.h, PREFIX.glsl");

    CLI::App* eval = app.add_subcommand("eval", "impulse-response L1 of a table per level");
    std::string table, texels = "all";
    double tolerance = -1.0;
    eval->add_option("table", table, "table file")->required();
    eval->add_option("--texels", texels, "all or stratified")->capture_default_str();
    eval->add_option("--check", tolerance, "exit 1 where the L1 differs from the recorded one by more than this");
    bool evalCells = false;
    eval->add_flag("--cells", evalCells, "also the fit's L1 over cells on the same texels, against the exact one (stratified texels)");
    int evalBudget = 0;
    const CLI::Option* evalBudgetOption =
        eval->add_option("--budget", evalBudget,
                         "stratified texels per level (default: the table's, whose L1 it records); another count is measured unrecorded");
    std::string recordOut;
    eval->add_option("--record", recordOut,
                     "write the table with the L1 measured as its records (those of --texels) to PREFIX.json, PREFIX.h, PREFIX.glsl");

    CLI::App* tail = app.add_subcommand("tail", "per level, the share of the reference's mass far from the lobe centre that a table "
                                                "reproduces (face centre, edge, corner); exit 1 where out of the bound");
    std::string tailTable;
    tail->add_option("table", tailTable, "table file")->required();

    CLI::App* exportTable = app.add_subcommand("export", "rewrite PREFIX.json, PREFIX.h, PREFIX.glsl from a table file");
    std::string exportSource, exportOut;
    exportTable->add_option("table", exportSource, "table file")->required();
    exportTable->add_option("--out", exportOut, "output prefix")->required();
    std::vector<std::string> handOffs;
    exportTable->add_option("--fis-level", handOffs,
                            "LEVEL:SAMPLES: level LEVEL is filtered by FIS with SAMPLES samples per texel (bias 0, on the table's "
                            "pyramid) in the table's place, where FIS measured better at no more time; 0 hands it back (repeatable)");

    CLI::App* select = app.add_subcommand("select", "a table from several fits of one shape: per level, the lowest-L1 fit "
                                                    "whose seams stay within the bound");
    std::vector<std::string> selectSources;
    std::string selectOut;
    select->add_option("tables", selectSources, "candidate table files")->required();
    select->add_option("--out", selectOut, "output prefix")->required();
    bool selectFirst = false;
    select->add_flag("--first", selectFirst,
                     "per level, the first table listed within the bound instead of the lowest L1 (for fits of another objective, "
                     "listed before the fits they refine)");

    CLI::App* mix = app.add_subcommand("mix", "a table whose levels use different tap counts: level m from the m-th table, "
                                              "padded with taps of zero weight");
    std::vector<std::string> mixSources;
    std::string mixOut;
    mix->add_option("tables", mixSources, "one table file per output level, level 0 first")->required();
    mix->add_option("--out", mixOut, "output prefix")->required();

    // Every value an option or argument takes is given and UTF-8 (core's rule, as in probefilter).
    const CLI::Validator valueCheck([](const std::string& value) { return commandLineValueProblem(value); }, "", "VALUE");
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
        for (CLI::Option* option : command->get_options())
            if (option->get_expected_min() > 0) option->check(valueCheck);
    try {
        app.parse(argc, argv);
        if (mix->parsed()) return runMix(mixSources, mixOut);
        if (select->parsed()) return runSelect(selectSources, selectOut, selectFirst);
        if (eval->parsed())
            return runEval(table, texels, tolerance, evalCells, evalBudgetOption->count() ? std::optional<int>(evalBudget) : std::nullopt,
                           recordOut);
        if (tail->parsed()) return runTail(tailTable);
        if (exportTable->parsed()) return runExport(exportSource, handOffs, exportOut);
        for (const auto& [name, missing] : {std::pair<const char*, bool>{"--size", settings.faceSize == 0},
                                            {"--taps", settings.taps == 0},
                                            {"--form", form.empty()},
                                            {"--out", out.empty() && !estimateOnly}})
            if (missing) throw ProbeError(fmt::format("{} is required", name));
        if (jobs != 0) {
            checkCount("--jobs", jobs, 1, 1024);
            omp_set_num_threads(jobs);
        }
        settings.mapping = roughness.empty() ? parseOption("--mapping", mapping.empty() ? "gltf" : mapping, parseRoughnessMapping)
                                             : parseOption("--roughness", roughness, parseRoughnessList);
        settings.lobe = parseOption("--lobe", lobe, parseLobe);
        settings.records = noEval ? probefit::Records::none : (noFullEval ? probefit::Records::stratified : probefit::Records::all);
        const std::optional<int> levelCount =
            levelsOption->count() > 0 ? std::optional(parseOption("--levels", levels, parseLevelCount)) : std::nullopt;
        const std::optional<std::string> fitLevelList = fitLevelsOption->count() > 0 ? std::optional(fitLevels) : std::nullopt;
        return runFit(settings, form, pyramid, weighting, solver, measure, fitLevelList, init, bank, out, estimateOnly, resume, levelCount);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        printToStderr(fmt::format("probefit: {}\n", oneLine(e.what())));
        return 2;
    } catch (const std::exception& e) {
        printToStderr(fmt::format("probefit: {}\n", oneLine(e.what())));
        return 2;
    }
}
