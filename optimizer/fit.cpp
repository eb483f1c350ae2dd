#include "fit.h"

#include <chrono>
#include <cmath>

#include <ceres/ceres.h>
#include <fmt/format.h>

#include "evaluate.h"
#include "impulse_model.h"
#include "initial_layout.h"
#include "probe/error.h"

namespace probefit {

using namespace probe;

namespace {

// The weight sum is kept above this fraction of its mean at the start of the level's fit.
constexpr double kMinWeightSum = 0.25;
constexpr double kPenalty = 10.0;

// Residuals 0..R-1: sqrt(a_R e_R) with a_R the texel's normalized weight, so the cost is the
// weighted mean L1 itself; residuals R..2R-1: a penalty where the weight sum drops below kMinWeightSum.
class LevelCost final : public ceres::CostFunction {
public:
    LevelCost(const ImpulseModel& model, const std::vector<OutputTexel>& texels, double weightScale)
        : model_(model), texels_(texels), weightScale_(weightScale) {
        set_num_residuals(static_cast<int>(2 * texels.size()));
        for (int b = 0; b < model.blockCount(); ++b) mutable_parameter_block_sizes()->push_back(model.blockSize());
        for (const OutputTexel& t : texels) weightTotal_ += t.weight;
    }

    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
        const std::size_t count = texels_.size();
        const int blockSize = model_.blockSize(), blocks = model_.blockCount();
#pragma omp parallel
        {
            ImpulseModel::Workspace ws = model_.workspace();
            std::vector<double> gradient, weightGradient;
            if (jacobians) {
                gradient.resize(static_cast<std::size_t>(blocks * blockSize));
                weightGradient.resize(gradient.size());
            }
#pragma omp for schedule(dynamic, 4)
            for (std::size_t n = 0; n < count; ++n) {
                const ImpulseModel::Result r = model_.evaluate(parameters, texels_[n], ws,
                                                               jacobians ? gradient.data() : nullptr,
                                                               jacobians ? weightGradient.data() : nullptr);
                const double a = texels_[n].weight / weightTotal_;
                const double residual = std::sqrt(a * r.error);
                const double deficit = kMinWeightSum - r.weightSum / weightScale_;
                residuals[n] = residual;
                residuals[count + n] = deficit > 0.0 ? kPenalty * std::sqrt(a) * deficit : 0.0;
                if (!jacobians) continue;
                const double errorScale = residual > 0.0 ? 0.5 * a / residual : 0.0;
                const double penaltyScale = deficit > 0.0 ? -kPenalty * std::sqrt(a) / weightScale_ : 0.0;
                for (int b = 0; b < blocks; ++b) {
                    if (!jacobians[b]) continue;
                    double* errorRow = jacobians[b] + n * blockSize;
                    double* penaltyRow = jacobians[b] + (count + n) * blockSize;
                    for (int q = 0; q < blockSize; ++q) {
                        errorRow[q] = errorScale * gradient[b * blockSize + q];
                        penaltyRow[q] = penaltyScale * weightGradient[b * blockSize + q];
                    }
                }
            }
        }
        return true;
    }

private:
    const ImpulseModel& model_;
    const std::vector<OutputTexel>& texels_;
    double weightScale_;
    double weightTotal_ = 0.0;
};

class ProgressCallback final : public ceres::IterationCallback {
public:
    ProgressCallback(const std::function<void(const FitProgress&)>& progress, int level,
                     std::chrono::steady_clock::time_point start)
        : progress_(progress), level_(level), start_(start) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
        // Rejected trial steps report the trial's cost; show the accepted state only.
        if (progress_ && summary.step_is_successful)
            progress_({level_, summary.iteration, 2.0 * summary.cost, seconds(start_), "iteration"});
        return ceres::SOLVER_CONTINUE;
    }
    static double seconds(std::chrono::steady_clock::time_point start) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

private:
    const std::function<void(const FitProgress&)>& progress_;
    int level_;
    std::chrono::steady_clock::time_point start_;
};

double weightedMeanWeightSum(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels) {
    double sum = 0.0, total = 0.0;
    ImpulseModel::Workspace ws = model.workspace();
    for (const OutputTexel& t : texels) {
        sum += t.weight * model.evaluate(blocks, t, ws).weightSum;
        total += t.weight;
    }
    return sum / total;
}

void scaleWeights(TapTable& table, int level, double factor) {
    const int k = coefficientCount(table.form);
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < table.taps; ++t)
            for (int q = 0; q < k; ++q) table.levels[level].coefficients[table.offset(frame, t, tapWeight) + q] *= factor;
}

std::string solverDescription(const FitSettings& s) {
    return fmt::format("Ceres {} Levenberg-Marquardt, dense QR, residual sqrt(a e) per stratified output texel "
                       "(cost = weighted mean impulse L1), at most {} iterations per level, function tolerance 1e-6, "
                       "weight sum kept >= {} of its mean (penalty {}), start: best of lobe layout, previous level{}",
                       CERES_VERSION_STRING, s.maxIterations, kMinWeightSum, kPenalty, s.init ? ", --init table" : "");
}

} // namespace

TapTable fitTable(const FitSettings& settings, const std::function<void(const FitProgress&)>& progress) {
    TapTable table = emptyTable(settings.baseSize, settings.levelCount, settings.taps, settings.form, settings.mapping,
                                settings.pyramid);
    table.stratifiedBudget = settings.stratifiedBudget;
    table.solver = solverDescription(settings);
    if (settings.init) {
        const TapTable& init = *settings.init;
        if (init.baseSize != settings.baseSize || init.levelCount != settings.levelCount)
            throw ProbeError(fmt::format("--init: table is for base size {} with {} levels, not {} with {}", init.baseSize,
                                         init.levelCount, settings.baseSize, settings.levelCount));
        if (init.taps != settings.taps && init.taps * 2 != settings.taps)
            throw ProbeError(fmt::format("--init: table has {} taps per frame, expected {} or {}", init.taps, settings.taps,
                                         settings.taps / 2));
    }
    const auto start = std::chrono::steady_clock::now();
    const ImpulseModel model(settings.baseSize, settings.pyramid, settings.taps, settings.form);
    int previous = -1;
    for (int m = 0; m < settings.levelCount; ++m) {
        const double alpha = tableLevelAlpha(table, m);
        TableLevel& level = table.levels[m];
        if (alpha <= 0.0) {
            level.stratified = level.all = {};
            continue;
        }
        const std::vector<OutputTexel> texels =
            prepareTexels(stratifiedTexels(settings.baseSize >> m, settings.stratifiedBudget), settings.baseSize, m, alpha);

        // Starting candidates; keep the one with the lowest L1.
        std::vector<std::pair<std::string, std::vector<double>>> candidates;
        lobeLayout(table, m, alpha);
        candidates.emplace_back("lobe layout", level.coefficients);
        if (previous >= 0) {
            warmStartFromLevel(table, m, previous);
            candidates.emplace_back(fmt::format("level {}", previous), level.coefficients);
        }
        if (settings.init) {
            startFromTable(table, m, *settings.init);
            candidates.emplace_back("--init", level.coefficients);
        }
        double best = 1e300;
        std::vector<double> bestCoefficients;
        for (auto& [name, coefficients] : candidates) {
            level.coefficients = coefficients;
            const double l1 = evaluatePrepared(model, levelBlocks(table, m).data(), texels).error.mean;
            if (progress) progress({m, 0, l1, ProgressCallback::seconds(start), "start " + name});
            if (l1 < best) {
                best = l1;
                bestCoefficients = coefficients;
            }
        }
        level.coefficients = bestCoefficients;

        const std::vector<const double*> constBlocks = levelBlocks(table, m);
        const double weightScale = weightedMeanWeightSum(model, constBlocks.data(), texels);
        ceres::Problem problem;
        std::vector<double*> blocks;
        for (const double* b : constBlocks) blocks.push_back(const_cast<double*>(b));
        problem.AddResidualBlock(new LevelCost(model, texels, weightScale), nullptr, blocks);
        ceres::Solver::Options options;
        options.linear_solver_type = ceres::DENSE_QR;
        options.max_num_iterations = settings.maxIterations;
        options.function_tolerance = 1e-6;
        // Start with a small step: the default radius wastes the first iterations on rejected steps.
        options.initial_trust_region_radius = 1.0;
        options.num_threads = 1; // the cost parallelizes itself, deterministically
        options.logging_type = ceres::SILENT;
        ProgressCallback callback(progress, m, start);
        options.callbacks.push_back(&callback);
        ceres::Solver::Summary summary;
        ceres::Solve(options, &problem, &summary);

        // Weights only matter relative to each other: scale them so the mean weight sum is 1.
        scaleWeights(table, m, 1.0 / weightedMeanWeightSum(model, constBlocks.data(), texels));
        const LevelEvaluation stratified = evaluatePrepared(model, constBlocks.data(), texels);
        level.stratified = stratified.error;
        level.minWeightSum = stratified.minWeightSum;
        if (progress) progress({m, summary.num_successful_steps, level.stratified.mean, ProgressCallback::seconds(start), "done"});
        if (settings.measureAll) {
            const LevelEvaluation all = evaluateLevel(table, m, TexelSet::all);
            level.all = all.error;
            level.minWeightSum = std::min(level.minWeightSum, all.minWeightSum);
            if (progress) progress({m, 0, level.all.mean, ProgressCallback::seconds(start), "all texels"});
        }
        previous = m;
    }
    table.fitSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return table;
}

} // namespace probefit
