#include "fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>

#include "checker_term.h"
#include "evaluate.h"
#include "impulse_model.h"
#include "initial_layout.h"
#include "probe/error.h"
#include "seam_term.h"
#include "tail_check.h"

namespace probefit {

using namespace probe;

namespace {

// The weight sum is kept above this fraction of its mean at the start of the level's fit.
constexpr double kMinWeightSum = 0.25;
constexpr double kPenalty = 10.0;
// How far apart (in texels of the tap's pyramid level) the two halves of a split --init tap start.
constexpr double kSplitSpread = 0.5;
// The bank's starts are screened on every this many stratified texels.
constexpr std::size_t kBankScreenStride = 8;

// The level of `table` whose alpha is nearest alpha (by ratio, within a factor of 2); -1 if none.
int nearestLevel(const TapTable& table, double alpha) {
    int best = -1;
    double bestDistance = std::log(2.0);
    for (int m = 0; m < table.levelCount; ++m) {
        const double a = tableLevelAlpha(table, m);
        if (a <= 0.0) continue;
        const double distance = std::abs(std::log(a / alpha));
        if (distance <= bestDistance) {
            best = m;
            bestDistance = distance;
        }
    }
    return best;
}

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The objective over the stratified texels R with normalized weights a_R:
//   f = sum_R a_R e_R + sum_R a_R p_R^2 + (W / P) sum_pairs s_pair,
//   p_R = kPenalty * max(0, kMinWeightSum - weightSum_R / scale),
// the weighted mean L1, a penalty where the weight sum drops below kMinWeightSum of its mean at the
// start, and with --seam-weight W the mean seam term over P edge pairs (seam_term.h). e_R includes
// the tail term and, with --checker-weight C, C c_R (checker_term.h). Terms are computed in parallel
// and summed in order, so the result does not depend on the number of threads.
class LevelObjective {
public:
    LevelObjective(const ImpulseModel& model, const std::vector<OutputTexel>& texels, double weightScale,
                   const std::vector<SeamPair>& pairs, const MomentBasis& basis, double seamWeight, const CheckerTerm& checker)
        : model_(model), texels_(texels), weightScale_(weightScale), pairs_(pairs), basis_(basis), seamWeight_(seamWeight),
          checker_(checker) {
        for (const OutputTexel& t : texels) weightTotal_ += t.weight;
    }

    std::size_t texelCount() const { return texels_.size(); }
    std::size_t termCount() const { return texels_.size() + pairs_.size(); }
    int parameterCount() const { return model_.blockCount() * model_.blockSize(); }

    struct Term {
        double a = 0.0, error = 0.0, penalty = 0.0;
        double penaltySlope = 0.0; // d p / d weightSum
    };

    // Per term n (texels first, then seam pairs): its term and, with gradients, d error_n / d theta in
    // errorGradient[n * P ...] and (texels) d weightSum_n / d theta in weightGradient[n * P ...]
    // (P = parameterCount()).
    void evaluate(const double* const* blocks, std::vector<Term>& terms, double* errorGradient, double* weightGradient) const {
        const std::size_t count = texels_.size(), p = static_cast<std::size_t>(parameterCount());
        terms.assign(termCount(), Term{});
        const auto start = Clock::now();
        // One workspace per thread, kept between evaluations: at 1024^2 each is a quarter of a GiB.
        while (workspaces_.size() < static_cast<std::size_t>(omp_get_max_threads())) workspaces_.push_back(model_.workspace());
#pragma omp parallel
        {
            ImpulseModel::Workspace& ws = workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
            std::vector<double> scratch;
#pragma omp for schedule(dynamic, 4)
            for (std::size_t n = 0; n < count; ++n) {
                const ImpulseModel::Result r = model_.evaluate(blocks, texels_[n], ws, errorGradient ? errorGradient + n * p : nullptr,
                                                               errorGradient ? weightGradient + n * p : nullptr);
                const double deficit = kMinWeightSum - r.weightSum / weightScale_;
                Term& t = terms[n];
                t.a = texels_[n].weight / weightTotal_;
                t.error = r.error + model_.tailWeight() * r.tail;
                if (checker_.weight > 0.0) {
                    scratch.resize(p);
                    const double c = checkerError(model_, blocks, texels_[n], checker_.reference[n], checker_.basis,
                                                  errorGradient ? scratch.data() : nullptr);
                    t.error += checker_.weight * c;
                    if (errorGradient)
                        for (std::size_t q = 0; q < p; ++q) errorGradient[n * p + q] += checker_.weight * scratch[q];
                }
                t.penalty = deficit > 0.0 ? kPenalty * deficit : 0.0;
                t.penaltySlope = deficit > 0.0 ? -kPenalty / weightScale_ : 0.0;
            }
#pragma omp for schedule(dynamic, 2)
            for (std::size_t k = 0; k < pairs_.size(); ++k) {
                const std::size_t n = count + k;
                Term& t = terms[n];
                t.a = seamWeight_ / static_cast<double>(pairs_.size());
                t.error = seamError(model_, blocks, pairs_[k], basis_, errorGradient ? errorGradient + n * p : nullptr, scratch);
                if (errorGradient) std::fill(weightGradient + n * p, weightGradient + (n + 1) * p, 0.0);
            }
        }
        seconds_ += secondsSince(start);
        ++evaluations_;
    }

    // f itself (the value the solvers minimize).
    double value(const double* const* blocks) const {
        std::vector<Term> terms;
        evaluate(blocks, terms, nullptr, nullptr);
        double f = 0.0;
        for (const Term& t : terms) f += t.a * (t.error + t.penalty * t.penalty);
        return f;
    }

    double seconds() const { return seconds_; }
    int evaluations() const { return evaluations_; }

private:
    const ImpulseModel& model_;
    const std::vector<OutputTexel>& texels_;
    double weightScale_;
    const std::vector<SeamPair>& pairs_;
    const MomentBasis& basis_;
    double seamWeight_;
    const CheckerTerm& checker_;
    double weightTotal_ = 0.0;
    mutable std::vector<ImpulseModel::Workspace> workspaces_;
    mutable double seconds_ = 0.0;
    mutable int evaluations_ = 0;
};

std::vector<const double*> blockPointers(const ImpulseModel& model, const double* parameters) {
    std::vector<const double*> blocks(static_cast<std::size_t>(model.blockCount()));
    for (std::size_t b = 0; b < blocks.size(); ++b) blocks[b] = parameters + b * static_cast<std::size_t>(model.blockSize());
    return blocks;
}

// BFGS (line search) on f itself. L1 is only piecewise smooth, but BFGS copes with that well in
// practice and, unlike the Gauss-Newton model of Levenberg-Marquardt, its curvature estimate comes
// from the true gradients: measured on 128^2 quad 8, 60 iterations reach 0.087 / 0.113 / 0.132 at
// levels 2 / 5 / 6 where Levenberg-Marquardt's reach 0.093 / 0.126 / 0.156.
class LevelFunction final : public ceres::FirstOrderFunction {
public:
    LevelFunction(const ImpulseModel& model, const LevelObjective& objective) : model_(model), objective_(objective) {}
    int NumParameters() const override { return objective_.parameterCount(); }

    bool Evaluate(const double* parameters, double* cost, double* gradient) const override {
        const std::vector<const double*> blocks = blockPointers(model_, parameters);
        const std::size_t p = static_cast<std::size_t>(NumParameters());
        if (gradient) {
            errorGradient_.resize(objective_.termCount() * p);
            weightGradient_.resize(errorGradient_.size());
        }
        objective_.evaluate(blocks.data(), terms_, gradient ? errorGradient_.data() : nullptr, gradient ? weightGradient_.data() : nullptr);
        double f = 0.0;
        for (const auto& t : terms_) f += t.a * (t.error + t.penalty * t.penalty);
        *cost = f;
        if (!gradient) return true;
        std::fill(gradient, gradient + p, 0.0);
        for (std::size_t n = 0; n < terms_.size(); ++n) {
            const auto& t = terms_[n];
            const double* ge = &errorGradient_[n * p];
            for (std::size_t q = 0; q < p; ++q) gradient[q] += t.a * ge[q];
            if (t.penalty <= 0.0) continue;
            const double s = 2.0 * t.a * t.penalty * t.penaltySlope;
            const double* gw = &weightGradient_[n * p];
            for (std::size_t q = 0; q < p; ++q) gradient[q] += s * gw[q];
        }
        return true;
    }

private:
    const ImpulseModel& model_;
    const LevelObjective& objective_;
    mutable std::vector<LevelObjective::Term> terms_;
    mutable std::vector<double> errorGradient_, weightGradient_;
};

// Levenberg-Marquardt on the same f as a sum of squares: residuals 0..R-1 are sqrt(a_R e_R) (texels,
// then seam pairs), residuals R..2R-1 sqrt(a_R) p_R; Ceres's cost 0.5 * sum r^2 is f / 2.
class LevelCost final : public ceres::CostFunction {
public:
    LevelCost(const ImpulseModel& model, const LevelObjective& objective) : model_(model), objective_(objective) {
        set_num_residuals(static_cast<int>(2 * objective.termCount()));
        for (int b = 0; b < model.blockCount(); ++b) mutable_parameter_block_sizes()->push_back(model.blockSize());
    }

    bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
        const std::size_t count = objective_.termCount(), p = static_cast<std::size_t>(objective_.parameterCount());
        if (jacobians) {
            errorGradient_.resize(count * p);
            weightGradient_.resize(count * p);
        }
        objective_.evaluate(parameters, terms_, jacobians ? errorGradient_.data() : nullptr, jacobians ? weightGradient_.data() : nullptr);
        const int blockSize = model_.blockSize();
        for (std::size_t n = 0; n < count; ++n) {
            const auto& t = terms_[n];
            const double residual = std::sqrt(t.a * t.error);
            residuals[n] = residual;
            residuals[count + n] = std::sqrt(t.a) * t.penalty;
            if (!jacobians) continue;
            const double errorScale = residual > 0.0 ? 0.5 * t.a / residual : 0.0;
            const double penaltyScale = std::sqrt(t.a) * t.penaltySlope;
            for (int b = 0; b < model_.blockCount(); ++b) {
                if (!jacobians[b]) continue;
                double* errorRow = jacobians[b] + n * blockSize;
                double* penaltyRow = jacobians[b] + (count + n) * blockSize;
                for (int q = 0; q < blockSize; ++q) {
                    errorRow[q] = errorScale * errorGradient_[n * p + b * blockSize + q];
                    penaltyRow[q] = penaltyScale * weightGradient_[n * p + b * blockSize + q];
                }
            }
        }
        return true;
    }

private:
    const ImpulseModel& model_;
    const LevelObjective& objective_;
    mutable std::vector<LevelObjective::Term> terms_;
    mutable std::vector<double> errorGradient_, weightGradient_;
};

class ProgressCallback final : public ceres::IterationCallback {
public:
    ProgressCallback(const std::function<void(const FitProgress&)>& progress, int level, Clock::time_point start, double costScale)
        : progress_(progress), level_(level), start_(start), costScale_(costScale) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
        // Rejected trial steps report the trial's cost; show the accepted state only.
        if (progress_ && summary.step_is_successful)
            progress_({level_, summary.iteration, costScale_ * summary.cost, secondsSince(start_), "iteration"});
        return ceres::SOLVER_CONTINUE;
    }

private:
    const std::function<void(const FitProgress&)>& progress_;
    int level_;
    Clock::time_point start_;
    double costScale_; // to the weighted mean L1
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

std::string initDescription(const FitSettings& s) {
    std::string text;
    if (s.fresh) return text;
    for (const TapTable& init : s.inits)
        text += fmt::format(", --init table {} {}x3{}", tableFormName(init.form), init.taps,
                            init.taps != s.taps ? fmt::format(" (taps split {} texels apart)", 2 * kSplitSpread) : "");
    if (!s.inits.empty()) text += "; an --init's exact filter is kept where the fit is not better";
    if (!s.bank.empty()) text += fmt::format(", the nearest roughness among {} bank tables", s.bank.size());
    return text;
}

std::string solverDescription(const FitSettings& s) {
    const std::string lm = "Levenberg-Marquardt (dense QR, residual sqrt(a e) per stratified output texel, function "
                           "tolerance 1e-6)";
    const std::string bfgs = "BFGS (Wolfe line search, function tolerance 1e-7)";
    std::string method;
    switch (s.solver) {
    case FitSolver::lmBfgs:
        method = fmt::format("{} iterations of {}, then at most {} of {}", s.lmIterations, lm, s.maxIterations, bfgs);
        break;
    case FitSolver::bfgs: method = fmt::format("at most {} iterations of {}", s.maxIterations, bfgs); break;
    case FitSolver::lm: method = fmt::format("at most {} iterations of {}", s.maxIterations, lm); break;
    }
    const std::string seam = s.seamWeight > 0.0
                                 ? fmt::format(" plus {} x the mean seam term over at most {} face-edge pairs (the change of "
                                               "the response's order-1 and order-2 SH moments across the edge against the "
                                               "reference's)",
                                               s.seamWeight, s.seamPairBudget)
                                 : "";
    const std::string checker = s.checkerWeight > 0.0
                                    ? fmt::format(" (plus {} x the checker term: the error of the response on +-1 checkerboards of "
                                                  "squares S/4 to S/32 texels, two phases each)",
                                                  s.checkerWeight)
                                    : "";
    const std::string tail =
        s.tailWeight > 0.0 ? fmt::format(" (each texel's L1 plus {} x |W - K|, its mass beyond {} texels of the lobe centre against the "
                                         "reference's)",
                                         s.tailWeight, kTailTexels)
                           : "";
    return fmt::format(
        "Ceres {}: {} on the weighted mean impulse L1{}{} over the stratified output texels{}, per level; "
        "levels with fewer stratified texels get up to {}x the iterations, in proportion; weight sum "
        "kept >= {} of its mean (penalty {}); start: best of lobe layout, previous level{}{}{}",
        CERES_VERSION_STRING, method, tail, checker, seam, s.roughIterationFactor, kMinWeightSum, kPenalty, initDescription(s),
        s.starts > 1 ? fmt::format("; also fitted from {} importance layouts (FIS taps), the lowest objective kept{}", s.starts - 1,
                                   screensStarts(s) ? " (every start runs Levenberg-Marquardt, the lowest objective then BFGS)" : "")
                     : "",
        s.hops > 0 ? fmt::format("; then {} hops (the fit's taps moved at random and refitted, kept where the objective is lower)", s.hops)
                   : "");
}

struct SolveReport {
    int iterations = 0;
    double solverSeconds = 0.0; // total time inside Ceres
};

SolveReport solveBfgs(const ImpulseModel& model, const LevelObjective& objective, double* parameters, int iterations,
                      ProgressCallback& callback) {
    ceres::GradientProblem problem(new LevelFunction(model, objective));
    ceres::GradientProblemSolver::Options options;
    options.line_search_direction_type = ceres::BFGS;
    options.line_search_type = ceres::WOLFE;
    options.max_num_iterations = iterations;
    options.function_tolerance = 1e-7;
    options.logging_type = ceres::SILENT;
    options.callbacks.push_back(&callback);
    ceres::GradientProblemSolver::Summary summary;
    ceres::Solve(options, problem, parameters, &summary);
    return {summary.iterations.empty() ? 0 : summary.iterations.back().iteration, summary.total_time_in_seconds};
}

SolveReport solveLevenbergMarquardt(const ImpulseModel& model, const LevelObjective& objective, const std::vector<double*>& blocks,
                                    int iterations, ProgressCallback& callback) {
    ceres::Problem problem;
    problem.AddResidualBlock(new LevelCost(model, objective), nullptr, blocks);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = iterations;
    options.function_tolerance = 1e-6;
    // Start with a small step: the default radius wastes the first iterations on rejected steps.
    options.initial_trust_region_radius = 1.0;
    options.num_threads = 1; // the cost parallelizes itself, deterministically
    options.logging_type = ceres::SILENT;
    options.callbacks.push_back(&callback);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    return {summary.num_successful_steps, summary.total_time_in_seconds};
}

// What decides between the fit and an exact --init: the exact mean L1 (over `judge`, the stratified
// texels measured exactly), plus the tail and checker terms (over the fit's texels) where they are on.
double fitScore(const ImpulseModel& model, const double* const* blocks, const std::vector<OutputTexel>& texels,
                const std::vector<OutputTexel>& judge, const CheckerTerm& checker) {
    const double l1 = evaluatePrepared(model, blocks, judge).error.mean;
    const double tail = model.tailWeight() > 0.0 ? model.tailWeight() * evaluatePrepared(model, blocks, texels).tailMean : 0.0;
    const double c = checker.weight > 0.0 ? checker.weight * meanCheckerError(model, blocks, texels, checker) : 0.0;
    return l1 + tail + c;
}

// Records level m's exact L1 (over `judge`, the stratified texels measured exactly, and with `all` over
// every texel) and lowest weight sum in the table.
void recordLevel(TapTable& table, int m, const ImpulseModel& model, const std::vector<OutputTexel>& judge, bool all) {
    TableLevel& level = table.levels[m];
    const LevelEvaluation stratified = evaluatePrepared(model, levelBlocks(table, m).data(), judge);
    level.stratified = stratified.error;
    level.minWeightSum = stratified.minWeightSum;
    if (!all) return;
    const LevelEvaluation every = evaluateLevel(table, m, TexelSet::all);
    level.all = every.error;
    level.minWeightSum = std::min(level.minWeightSum, every.minWeightSum);
}

} // namespace

bool screensStarts(const FitSettings& settings) {
    return settings.starts > 1 && settings.solver == FitSolver::lmBfgs && !settings.screenAll;
}

int levelIterations(const FitSettings& settings, int iterations, std::size_t texels) {
    const double budget = settings.stratifiedBudget;
    const double factor = std::clamp(budget / std::max<double>(1.0, static_cast<double>(texels)), 1.0,
                                     static_cast<double>(std::max(1, settings.roughIterationFactor)));
    return static_cast<int>(std::lround(iterations * factor));
}

FitSolver parseFitSolver(const std::string& name) {
    if (name == "lm-bfgs") return FitSolver::lmBfgs;
    if (name == "bfgs") return FitSolver::bfgs;
    if (name == "lm") return FitSolver::lm;
    throw ProbeError(fmt::format("'{}' is none of lm-bfgs, bfgs, lm", name));
}

TapTable fitTable(const FitSettings& settings, const std::function<void(const FitProgress&)>& progress,
                  const std::function<void(const TapTable&)>& levelDone) {
    TapTable table = emptyTable(settings.baseSize, settings.levelCount, settings.taps, settings.form, settings.mapping, settings.pyramid);
    table.stratifiedBudget = settings.stratifiedBudget;
    table.solver = solverDescription(settings);
    // A partial refit names the levels it fitted and keeps the provenance of those it copied.
    if (!settings.fitLevels.empty() && !settings.inits.empty())
        table.solver = fmt::format("levels {}: {}; the other levels copied from the first --init: [{}]",
                                   fmt::join(settings.fitLevels, ", "), table.solver, settings.inits.front().solver);
    table.seamWeight = settings.seamWeight;
    for (const TapTable& init : settings.inits) {
        if (init.baseSize != settings.baseSize || init.levelCount != settings.levelCount)
            throw ProbeError(fmt::format("--init: table is for base size {} with {} levels, not {} with {}", init.baseSize, init.levelCount,
                                         settings.baseSize, settings.levelCount));
        if (init.taps != settings.taps && init.taps * 2 != settings.taps)
            throw ProbeError(
                fmt::format("--init: table has {} taps per frame, expected {} or {}", init.taps, settings.taps, settings.taps / 2));
    }
    if (!settings.fitLevels.empty()) {
        if (settings.inits.empty() || settings.inits.front().taps != settings.taps || settings.inits.front().form != settings.form)
            throw ProbeError("--fit-levels: the first --init must have the table's taps and form (the other levels are copied from it)");
        for (int m : settings.fitLevels)
            if (m < 0 || m >= settings.levelCount)
                throw ProbeError(fmt::format("--fit-levels: level {} is not one of 0..{}", m, settings.levelCount - 1));
    }
    if (settings.fresh && settings.fitLevels.empty())
        throw ProbeError("--fresh: needs --fit-levels (the --init supplies the other levels)");
    if (const TapTable* r = settings.resume;
        r && (r->baseSize != table.baseSize || r->levelCount != table.levelCount || r->taps != table.taps || r->form != table.form ||
              r->mapping != table.mapping || !(r->pyramid == table.pyramid) || r->stratifiedBudget != table.stratifiedBudget ||
              r->solver != table.solver))
        throw ProbeError("--resume: the checkpoint was written by a fit of another shape or solver settings");
    const auto start = Clock::now();
    const ImpulseModel model(settings.baseSize, settings.pyramid, settings.taps, settings.form, settings.tailWeight);
    // The seam term's basis (half a GiB at 1024^2): only where the term is on.
    const MomentBasis basis = settings.seamWeight > 0.0 ? MomentBasis(settings.baseSize, settings.pyramid) : MomentBasis();
    const std::optional<MomentBasis> checkers =
        settings.checkerWeight > 0.0
            ? std::optional<MomentBasis>(std::in_place, settings.baseSize, settings.pyramid, MomentFunctions::checkers)
            : std::nullopt;
    // The base's geometry, for the exact measure of the stratified texels where the fit measures cells.
    const std::optional<CubeGeometry> geometry =
        settings.measure == Measure::cells ? std::optional<CubeGeometry>(std::in_place, settings.baseSize) : std::nullopt;
    int previous = -1;
    for (int m = 0; m < settings.levelCount; ++m) {
        const double alpha = tableLevelAlpha(table, m);
        TableLevel& level = table.levels[m];
        if (alpha <= 0.0) {
            level.stratified = level.all = {};
            continue;
        }
        if (settings.resume && settings.resume->levels[m].stratified.mean >= 0.0) {
            level = settings.resume->levels[m];
            if (progress) progress({m, 0, level.stratified.mean, secondsSince(start), "resumed"});
            previous = m;
            continue;
        }
        const auto kernelStart = Clock::now();
        const std::vector<WeightedTexel> stratified = stratifiedTexels(settings.baseSize >> m, settings.stratifiedBudget);
        const std::vector<OutputTexel> texels =
            prepareTexels(stratified, settings.baseSize, m, alpha, settings.tailWeight > 0.0, settings.measure);
        // What judges the level (its records, the kept --init): the exact L1, whatever the fit measures.
        const std::vector<OutputTexel> measured =
            settings.measure == Measure::cells ? measuredTexels(*geometry, m, alpha, stratified) : std::vector<OutputTexel>{};
        const std::vector<OutputTexel>& judge = measured.empty() ? texels : measured;
        const CheckerTerm checker = checkers ? prepareCheckerTerm(texels, *checkers, settings.checkerWeight) : CheckerTerm{basis, {}, 0.0};
        const double kernelSeconds = secondsSince(kernelStart);
        if (!settings.fitLevels.empty() && std::ranges::find(settings.fitLevels, m) == settings.fitLevels.end()) {
            startFromTable(table, m, settings.inits.front());
            recordLevel(table, m, model, judge, settings.measureAll);
            if (progress) progress({m, 0, level.stratified.mean, secondsSince(start), "copied from --init"});
            if (levelDone) levelDone(table);
            previous = m;
            continue;
        }

        // Starting candidates; keep the one with the lowest L1.
        std::vector<std::pair<std::string, std::vector<double>>> candidates;
        lobeLayout(table, m, alpha);
        candidates.emplace_back("lobe layout", level.coefficients);
        if (previous >= 0) {
            warmStartFromLevel(table, m, previous);
            candidates.emplace_back(fmt::format("level {}", previous), level.coefficients);
        }
        // The bank: each table's level of the nearest roughness (within a factor of 2 in alpha), screened
        // on every 8th stratified texel; the best joins the candidates.
        if (!settings.fresh && !settings.bank.empty()) {
            std::vector<OutputTexel> screen;
            for (std::size_t n = 0; n < texels.size(); n += kBankScreenStride) screen.push_back(texels[n]);
            double bestBank = 1e300;
            std::string bestName;
            std::vector<double> bestBankCoefficients;
            for (const FitSettings::BankTable& bank : settings.bank) {
                const int from = nearestLevel(bank.table, alpha);
                if (from < 0) continue;
                startFromBank(table, m, bank.table, from);
                const double l1 = evaluatePrepared(model, levelBlocks(table, m).data(), screen).error.mean;
                if (l1 < bestBank) {
                    bestBank = l1;
                    bestName = fmt::format("bank {} level {}", bank.name, from);
                    bestBankCoefficients = level.coefficients;
                }
            }
            if (!bestBankCoefficients.empty()) candidates.emplace_back(bestName, bestBankCoefficients);
        }
        // An init table whose filter this table can express exactly (same form, or const into quad)
        // is kept aside: the fit keeps it where it cannot beat it, so more taps (or the quadratic
        // form) are never worse. With N/2 taps the fit starts from its taps split and moved apart
        // (the exact split sits at the init's stationary point). With --fresh they take no part.
        std::optional<std::pair<double, std::vector<double>>> fallback;
        const std::size_t startInits = settings.fresh ? 0 : settings.inits.size();
        for (std::size_t i = 0; i < startInits; ++i) {
            const TapTable& init = settings.inits[i];
            const std::string name = settings.inits.size() > 1 ? fmt::format("--init {}", i + 1) : "--init";
            startFromTable(table, m, init);
            if (init.form == settings.form || init.form == TableForm::constant) {
                const double score = fitScore(model, levelBlocks(table, m).data(), texels, judge, checker);
                if (progress) progress({m, 0, score, secondsSince(start), fmt::format("start {} (exact, kept aside)", name)});
                if (!fallback || score < fallback->first) fallback.emplace(score, level.coefficients);
            }
            if (init.taps != settings.taps) startFromTable(table, m, init, kSplitSpread);
            candidates.emplace_back(name, level.coefficients);
        }
        double best = 1e300;
        std::vector<double> bestCoefficients;
        for (auto& [name, coefficients] : candidates) {
            level.coefficients = coefficients;
            const double l1 = evaluatePrepared(model, levelBlocks(table, m).data(), texels).error.mean;
            if (progress) progress({m, 0, l1, secondsSince(start), "start " + name});
            if (l1 < best) {
                best = l1;
                bestCoefficients = coefficients;
            }
        }
        // The fit runs from the best candidate and, with --starts K > 1, also from K - 1 importance
        // layouts (turned apart about the axis); the lowest objective is kept.
        std::vector<std::pair<std::string, std::vector<double>>> starts{{"best start", bestCoefficients}};
        for (int k = 0; k + 1 < settings.starts; ++k) {
            const double rotation = 2.0 * std::numbers::pi * k / ((settings.starts - 1) * settings.taps);
            importanceLayout(table, m, alpha, rotation);
            const double l1 = evaluatePrepared(model, levelBlocks(table, m).data(), texels).error.mean;
            const std::string name = fmt::format("importance layout {}", k + 1);
            if (progress) progress({m, 0, l1, secondsSince(start), "start " + name});
            starts.emplace_back(name, level.coefficients);
        }

        const std::vector<const double*> constBlocks = levelBlocks(table, m);
        const std::vector<SeamPair> pairs = settings.seamWeight > 0.0
                                                ? prepareSeamPairs(settings.baseSize, m, alpha, settings.seamPairBudget, basis)
                                                : std::vector<SeamPair>{};
        auto reportSeam = [&](const char* when) {
            if (pairs.empty() || !progress) return;
            std::vector<double> scratch;
            double sum = 0.0;
            for (const SeamPair& pair : pairs) sum += seamError(model, constBlocks.data(), pair, basis, nullptr, scratch);
            progress({m, 0, sum / static_cast<double>(pairs.size()), secondsSince(start), fmt::format("seam term {}", when)});
        };
        auto reportChecker = [&](const char* when) {
            if (checker.weight > 0.0 && progress)
                progress({m, 0, meanCheckerError(model, constBlocks.data(), texels, checker), secondsSince(start),
                          fmt::format("checker term {}", when)});
        };
        SolveReport report;
        double modelSeconds = 0.0;
        int evaluations = 0;
        // Runs the Levenberg-Marquardt part (lm) and the BFGS part (bfgs) of the solver from
        // level.coefficients; returns the objective at the end where `compare` (one more evaluation).
        auto solve = [&](bool lm, bool bfgs, bool compare) {
            const LevelObjective objective(model, texels, weightedMeanWeightSum(model, constBlocks.data(), texels), pairs, basis,
                                           settings.seamWeight, checker);
            reportSeam("at the start");
            reportChecker("at the start");
            if (lm && settings.solver != FitSolver::bfgs) {
                ProgressCallback callback(progress, m, start, 2.0);
                std::vector<double*> blocks;
                for (const double* b : constBlocks) blocks.push_back(const_cast<double*>(b));
                const int iterations = settings.solver == FitSolver::lm ? settings.maxIterations : settings.lmIterations;
                const SolveReport r =
                    solveLevenbergMarquardt(model, objective, blocks, levelIterations(settings, iterations, texels.size()), callback);
                report.iterations += r.iterations;
                report.solverSeconds += r.solverSeconds;
            }
            if (bfgs && settings.solver != FitSolver::lm) {
                ProgressCallback callback(progress, m, start, 1.0);
                const SolveReport r = solveBfgs(model, objective, level.coefficients.data(),
                                                levelIterations(settings, settings.maxIterations, texels.size()), callback);
                report.iterations += r.iterations;
                report.solverSeconds += r.solverSeconds;
            }
            const double value = compare ? objective.value(constBlocks.data()) : 0.0;
            modelSeconds += objective.seconds();
            evaluations += objective.evaluations();
            return value;
        };
        // With several starts and lm-bfgs, every start runs the Levenberg-Marquardt part and only the
        // lowest objective goes on to BFGS (with --screen-all, or another solver, every start runs in
        // full and the lowest objective is kept).
        const bool screen = screensStarts(settings);
        double bestObjective = 1e300;
        std::vector<double> fitted;
        for (const auto& [name, coefficients] : starts) {
            level.coefficients = coefficients;
            const double value = solve(true, !screen, starts.size() > 1);
            if (starts.size() > 1 && progress)
                progress({m, 0, value, secondsSince(start),
                          fmt::format("objective after {} from {}", screen ? "Levenberg-Marquardt" : "the fit", name)});
            if (value < bestObjective || fitted.empty()) {
                bestObjective = value;
                fitted = level.coefficients;
            }
        }
        level.coefficients = fitted;
        if (screen) solve(false, true, false);
        // Hops: refits from the best fit so far, moved at random; a hop that lowers the objective is kept.
        if (settings.hops > 0) {
            double current = solve(false, false, true);
            for (int k = 0; k < settings.hops; ++k) {
                const std::vector<double> kept = level.coefficients;
                hopLayout(table, m, alpha, static_cast<unsigned>(1000 * m + k));
                const double value = solve(true, true, true);
                if (progress) progress({m, 0, value, secondsSince(start), fmt::format("objective after hop {}", k + 1)});
                if (value < current) current = value;
                else level.coefficients = kept;
            }
        }

        if (fallback && fitScore(model, constBlocks.data(), texels, judge, checker) > fallback->first) {
            level.coefficients = fallback->second;
            if (progress) progress({m, 0, fallback->first, secondsSince(start), "kept the exact --init"});
        }
        reportSeam("after the fit");
        reportChecker("after the fit");
        // Weights only matter relative to each other: scale them so the mean weight sum is 1.
        scaleWeights(table, m, 1.0 / weightedMeanWeightSum(model, constBlocks.data(), texels));
        recordLevel(table, m, model, judge, false);
        if (progress) {
            FitProgress done{m, report.iterations, level.stratified.mean, secondsSince(start), "done"};
            done.kernelSeconds = kernelSeconds;
            done.evaluationSeconds = modelSeconds;
            done.solverSeconds = std::max(0.0, report.solverSeconds - modelSeconds);
            done.evaluations = evaluations;
            progress(done);
        }
        if (settings.measureAll) {
            recordLevel(table, m, model, judge, true);
            if (progress) progress({m, 0, level.all.mean, secondsSince(start), "all texels"});
        }
        if (levelDone) levelDone(table);
        previous = m;
    }
    table.fitSeconds = secondsSince(start);
    return table;
}

} // namespace probefit
