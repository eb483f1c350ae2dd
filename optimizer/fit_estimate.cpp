#include "fit_estimate.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include <omp.h>

#include "checker_term.h"
#include "evaluate.h"
#include "impulse_model.h"
#include "initial_layout.h"

namespace probefit {

using namespace probe;

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Texels timed per level: enough to average the model's cost over the faces, few enough to take a
// fraction of a second at 128^2.
constexpr std::size_t kTimedTexels = 12;

} // namespace

FitEstimate estimateFit(const FitSettings& settings) {
    FitEstimate estimate;
    TapTable table = emptyTable(settings.faceSize, settings.levelCount, settings.taps, settings.form, settings.mapping, settings.pyramid);
    table.lobe = settings.lobe;
    const ImpulseModel model(settings.faceSize, settings.pyramid, settings.taps, settings.form);
    ImpulseModel::Workspace ws = model.workspace();
    const std::size_t parameters = static_cast<std::size_t>(model.blockCount() * model.blockSize());
    std::vector<double> gradient(parameters), weightGradient(parameters);
    const double threads = std::max(1, omp_get_max_threads());
    // The checker term's moments (and the reference's, once per texel) cost beside the L1.
    const std::optional<MomentBasis> checkers =
        settings.checkerWeight > 0.0
            ? std::optional<MomentBasis>(std::in_place, settings.faceSize, settings.pyramid, MomentFunctions::checkers)
            : std::nullopt;
    // The base's geometry, where the fit or its records measure exactly.
    const std::optional<CubeGeometry> geometry = settings.measure == Measure::exact || settings.records != Records::none
                                                     ? std::optional<CubeGeometry>(std::in_place, settings.faceSize)
                                                     : std::nullopt;
    for (int m = 0; m < settings.levelCount; ++m) {
        const double alpha = tableLevelAlpha(table, m);
        if (alpha <= 0.0 || copiesInitRecords(settings, m)) {
            estimate.levelSeconds.push_back(0.0);
            continue;
        }
        importanceLayout(table, m, alpha, 0.0); // reaches about as far as fitted taps
        const std::vector<WeightedTexel> stratified = stratifiedTexels(settings.faceSize >> m, settings.stratifiedBudget);
        std::vector<WeightedTexel> timed;
        const std::size_t step = std::max<std::size_t>(1, stratified.size() / kTimedTexels);
        for (std::size_t n = 0; n < stratified.size(); n += step) timed.push_back(stratified[n]);
        const auto kernelStart = Clock::now();
        std::vector<OutputTexel> texels;
        for (const WeightedTexel& t : timed)
            texels.push_back(settings.measure == Measure::cells ? makeCellTexel(t, settings.faceSize, m, tableLevelLobe(table, m))
                                                                : makeOutputTexel(t, *geometry, m, tableLevelLobe(table, m)));
        // The reference's checker moments are computed once per texel, like its kernel.
        std::vector<std::array<double, kMomentCount>> checkerReference;
        if (checkers) checkerReference = prepareCheckerTerm(texels, *checkers, settings.checkerWeight).reference;
        const double kernel = secondsSince(kernelStart) / static_cast<double>(timed.size());
        // A texel's first evaluation also finds its routes to the cells (lobe_cells.h), which the
        // others reuse: once per texel, like its kernel.
        const auto routesStart = Clock::now();
        for (const OutputTexel& t : texels) model.evaluate(levelBlocks(table, m).data(), t, ws, gradient.data(), weightGradient.data());
        const double routes = secondsSince(routesStart) / static_cast<double>(timed.size());
        const auto modelStart = Clock::now();
        for (const OutputTexel& t : texels) model.evaluate(levelBlocks(table, m).data(), t, ws, gradient.data(), weightGradient.data());
        if (checkers)
            for (std::size_t n = 0; n < texels.size(); ++n)
                checkerError(model, levelBlocks(table, m).data(), texels[n], checkerReference[n], *checkers, gradient.data());
        const double perTexel = secondsSince(modelStart) / static_cast<double>(timed.size());
        // Measuring exactly (the records): the model without its gradient, from the kernel's lobe
        // (evaluate.h), whose normalization is a pass over every base texel.
        double normalization = 0.0, perMeasured = 0.0;
        if (settings.records != Records::none) {
            std::vector<OutputTexel> measured;
            const auto normalizationStart = Clock::now();
            for (std::size_t n = 0; n < timed.size(); ++n) {
                const double sum = ReferenceLobe(texels[n].cubeVector, *geometry, tableLevelLobe(table, m)).normalization();
                measured.push_back(makeMeasuredTexel(timed[n], *geometry, m, tableLevelLobe(table, m), sum));
            }
            normalization = secondsSince(normalizationStart) / static_cast<double>(timed.size());
            const auto measureStart = Clock::now();
            for (const OutputTexel& t : measured) model.evaluate(levelBlocks(table, m).data(), t, ws);
            perMeasured = secondsSince(measureStart) / static_cast<double>(timed.size());
        }
        const double fitTexels = static_cast<double>(stratified.size());
        const bool fitted = settings.fitLevels.empty() || std::ranges::find(settings.fitLevels, m) != settings.fitLevels.end();
        double seconds = (kernel + routes) * fitTexels;
        if (fitted) seconds += perTexel * fitTexels * kEvaluationsPerIteration * levelIterationCost(settings, stratified.size());
        if (settings.measure == Measure::cells && settings.records != Records::none) // the exact record of the stratified texels
            seconds += (normalization + perMeasured) * fitTexels;
        if (settings.records == Records::all) // a normalization per class of symmetric texels (evaluate.h), the model per texel
            seconds += normalization * static_cast<double>(symmetryClassCount(settings.faceSize >> m)) +
                       perMeasured * static_cast<double>(texelCount(settings.faceSize >> m));
        estimate.levelSeconds.push_back(seconds / threads);
        estimate.seconds += seconds / threads;
    }
    return estimate;
}

} // namespace probefit
