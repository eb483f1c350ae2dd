// The fit: per output level, Ceres minimizes the impulse-response L1 of the table over the
// stratified texels, one residual per texel.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "probe/tap_table.h"

namespace probefit {

struct FitSettings {
    int baseSize = 0;
    int levelCount = 0;
    int taps = 0;
    probe::TableForm form = probe::TableForm::quadratic;
    probe::RoughnessMapping mapping = probe::RoughnessMapping::gltf;
    probe::PyramidSettings pyramid;
    int stratifiedBudget = 512; // texels per level
    int maxIterations = 60;     // Levenberg-Marquardt iterations per level
    bool measureAll = true;     // also measure every output texel after the fit (recorded in the table)
    std::optional<probe::TapTable> init;
};

struct FitProgress {
    int level = 0;
    int iteration = 0;
    double l1 = 0.0; // stratified mean impulse L1 (plus the weight-sum penalty where it is active)
    double seconds = 0.0;
    std::string stage; // "start <candidate>", "iteration", "done", "all texels"
};

// Fits every level with alpha > 0; deterministic for given settings. Throws ProbeError for bad settings.
probe::TapTable fitTable(const FitSettings& settings, const std::function<void(const FitProgress&)>& progress);

} // namespace probefit
