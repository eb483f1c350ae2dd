// How long a fit takes, said before it starts: per level, the model is timed on a few stratified
// texels at an importance layout and scaled to the fit's texels, iterations, starts and threads.
#pragma once

#include <vector>

#include "fit.h"

namespace probefit {

struct FitEstimate {
    std::vector<double> levelSeconds; // per output level (0 for copies)
    double seconds = 0.0;             // all levels
};

// Solver evaluations of the model per iteration, over the fits of the 128^2 tables (docs/optimizer.md).
inline constexpr double kEvaluationsPerIteration = 1.15;

// Wall time on this machine's threads at its present speed (the timing shares the machine with
// whatever else runs); the taps of a fitted level may reach further than the importance layout's.
FitEstimate estimateFit(const FitSettings& settings);

} // namespace probefit
