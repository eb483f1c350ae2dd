#include "level_solver.h"

#include <cmath>

#include <omp.h>

namespace probefit {

namespace {

std::vector<const double*> blockPointers(const ImpulseModel& model, const double* parameters) {
    std::vector<const double*> blocks(static_cast<std::size_t>(model.blockCount()));
    for (std::size_t b = 0; b < blocks.size(); ++b) blocks[b] = parameters + b * static_cast<std::size_t>(model.blockSize());
    return blocks;
}

// Levenberg-Marquardt on f as a sum of squares: residuals 0..R-1 are sqrt(a_R e_R) (texels, then
// seam pairs), residuals R..2R-1 sqrt(a_R) p_R; Ceres's cost 0.5 * sum r^2 is f / 2.
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

} // namespace

LevelObjective::LevelObjective(const ImpulseModel& model, const std::vector<OutputTexel>& texels, double weightScale,
                               const std::vector<SeamPair>& pairs, const MomentBasis& basis, double seamWeight, const CheckerTerm& checker,
                               const ThreadShare& share)
    : model_(model), texels_(texels), weightScale_(weightScale), pairs_(pairs), basis_(basis), seamWeight_(seamWeight), checker_(checker),
      share_(share) {
    for (const OutputTexel& t : texels) weightTotal_ += t.weight;
}

void LevelObjective::evaluate(const double* const* blocks, std::vector<Term>& terms, double* errorGradient, double* weightGradient) const {
    const std::size_t count = texels_.size(), p = static_cast<std::size_t>(parameterCount());
    terms.assign(termCount(), Term{});
    const auto start = Clock::now();
    // The chain's share of the threads now (ThreadShare): this evaluation's team, and that of the
    // level's parallel work after it.
    omp_set_num_threads(share_.now());
    // One workspace per thread, kept between evaluations: at 1024^2 each is a quarter of a GiB.
    while (workspaces_.size() < static_cast<std::size_t>(omp_get_max_threads())) workspaces_.push_back(model_.workspace());
#pragma omp parallel
    {
        ImpulseModel::Workspace& ws = workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
        std::vector<double> scratch;
#pragma omp for schedule(dynamic, 4)
        for (std::size_t n = 0; n < count; ++n) {
            if (n + 1 < count) prefetch(texels_[n + 1]);
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

double LevelObjective::value(const double* const* blocks) const {
    std::vector<Term> terms;
    evaluate(blocks, terms, nullptr, nullptr);
    double f = 0.0;
    for (const Term& t : terms) f += t.a * (t.error + t.penalty * t.penalty);
    return f;
}

bool LevelFunction::Evaluate(const double* parameters, double* cost, double* gradient) const {
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

bool TiedFrames::Evaluate(const double* parameters, double* cost, double* gradient) const {
    const auto n = static_cast<std::size_t>(NumParameters());
    frames_.resize(n * probe::kFrameCount);
    for (std::size_t f = 0; f < probe::kFrameCount; ++f) std::copy(parameters, parameters + n, frames_.begin() + std::ptrdiff_t(f * n));
    framesGradient_.resize(frames_.size());
    untied_.Evaluate(frames_.data(), cost, gradient ? framesGradient_.data() : nullptr);
    if (gradient)
        for (std::size_t q = 0; q < n; ++q) gradient[q] = framesGradient_[q] + framesGradient_[n + q] + framesGradient_[2 * n + q];
    return true;
}

ceres::CallbackReturnType ProgressCallback::operator()(const ceres::IterationSummary& summary) {
    // Rejected trial steps report the trial's cost; show the accepted state only.
    if (progress_ && summary.step_is_successful)
        progress_({level_, summary.iteration, costScale_ * summary.cost, secondsSince(start_), "iteration"});
    return ceres::SOLVER_CONTINUE;
}

SolveReport solveBfgs(const ImpulseModel& model, const LevelObjective& objective, double* parameters, int iterations,
                      ProgressCallback& callback, bool tied) {
    ceres::GradientProblem problem(tied ? static_cast<ceres::FirstOrderFunction*>(new TiedFrames(model, objective))
                                        : new LevelFunction(model, objective));
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
    options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
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

} // namespace probefit
