// One level's objective over its stratified texels and the Ceres solvers that minimize it: BFGS on
// the objective itself (each frame's taps free, or every frame's tied) and Levenberg-Marquardt on it
// as a sum of squares.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <vector>

#include <ceres/ceres.h>

#include "checker_term.h"
#include "fit.h"
#include "impulse_model.h"
#include "seam_term.h"

namespace probefit {

// The weight sum is kept above this fraction of its mean at the start of the level's fit.
inline constexpr double kMinWeightSum = 0.25;
inline constexpr double kPenalty = 10.0;

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The threads a level's evaluations use: all of them, shared by the chains of levels not yet finished
// (fitTable), so that a chain's threads go to the others when it ends.
struct ThreadShare {
    int threads = 1;
    std::atomic<int> chainsLeft{1};
    int now() const { return std::max(1, threads / std::clamp(chainsLeft.load(), 1, threads)); }
};

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
                   const std::vector<SeamPair>& pairs, const MomentBasis& basis, double seamWeight, const CheckerTerm& checker,
                   const ThreadShare& share);

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
    void evaluate(const double* const* blocks, std::vector<Term>& terms, double* errorGradient, double* weightGradient) const;
    // f itself (the value the solvers minimize).
    double value(const double* const* blocks) const;

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
    const ThreadShare& share_;
    double weightTotal_ = 0.0;
    mutable std::vector<ImpulseModel::Workspace> workspaces_;
    mutable double seconds_ = 0.0;
    mutable int evaluations_ = 0;
};

// f for BFGS (line search). L1 is only piecewise smooth, but BFGS copes with that well in practice
// and, unlike the Gauss-Newton model of Levenberg-Marquardt, its curvature estimate comes from the
// true gradients: measured on 128^2 quad 8, 60 iterations reach 0.087 / 0.113 / 0.132 at levels
// 2 / 5 / 6 where Levenberg-Marquardt's reach 0.093 / 0.126 / 0.156.
class LevelFunction final : public ceres::FirstOrderFunction {
public:
    LevelFunction(const ImpulseModel& model, const LevelObjective& objective) : model_(model), objective_(objective) {}
    int NumParameters() const override { return objective_.parameterCount(); }
    bool Evaluate(const double* parameters, double* cost, double* gradient) const override;

private:
    const ImpulseModel& model_;
    const LevelObjective& objective_;
    mutable std::vector<LevelObjective::Term> terms_;
    mutable std::vector<double> errorGradient_, weightGradient_;
};

// f with every frame's taps the same: the parameters are one frame's, the slope is the sum of the
// frames'. A fit's frames left free from the start can settle in different basins, and on a quarter
// of the texels (the coarse ones) a third of the parameters overfits less.
class TiedFrames final : public ceres::FirstOrderFunction {
public:
    TiedFrames(const ImpulseModel& model, const LevelObjective& objective) : untied_(model, objective) {}
    int NumParameters() const override { return untied_.NumParameters() / probe::kFrameCount; }
    bool Evaluate(const double* parameters, double* cost, double* gradient) const override;

private:
    LevelFunction untied_;
    mutable std::vector<double> frames_, framesGradient_;
};

// Reports each accepted iteration's cost, scaled to the weighted mean L1, as the level's progress.
class ProgressCallback final : public ceres::IterationCallback {
public:
    ProgressCallback(const std::function<void(const FitProgress&)>& progress, int level, Clock::time_point start, double costScale)
        : progress_(progress), level_(level), start_(start), costScale_(costScale) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override;

private:
    const std::function<void(const FitProgress&)>& progress_;
    int level_;
    Clock::time_point start_;
    double costScale_; // to the weighted mean L1
};

struct SolveReport {
    int iterations = 0;
    double solverSeconds = 0.0; // total time inside Ceres
};

// At most `iterations` of BFGS on f from `parameters` (every frame's taps, or with `tied` one frame's).
SolveReport solveBfgs(const ImpulseModel& model, const LevelObjective& objective, double* parameters, int iterations,
                      ProgressCallback& callback, bool tied);

// At most `iterations` of Levenberg-Marquardt on f as a sum of squares, over the level's blocks.
SolveReport solveLevenbergMarquardt(const ImpulseModel& model, const LevelObjective& objective, const std::vector<double*>& blocks,
                                    int iterations, ProgressCallback& callback);

} // namespace probefit
