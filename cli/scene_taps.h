// The tap generator a scene probe's method uses: its table (file or built in) or FIS.
#pragma once

#include "probe/plan.h"
#include "probe/scene.h"
#include "probe/tap_sum.h"
#include "probe/tap_table.h"

namespace probefilter {

// The table a probe filters with: its "table" file, checked against the probe's size, levels and
// mapping, else the compiled-in table for them; for its Charlie levels (the probe's method's lobe),
// the compiled-in Charlie table. Throws ProbeError naming the scene file and the problem.
probe::TapTable sceneProbeTable(const probe::Scene& scene, const probe::SceneProbe& probe);

// Whether a compiled-in Charlie table fits the probe (its sheen levels filter with it).
bool hasCharlieTable(const probe::SceneProbe& probe);

// The probe's method's taps and how it filters each level (probe/plan.h).
probe::MethodTaps sceneProbeTaps(const probe::Scene& scene, const probe::SceneProbe& probe);

} // namespace probefilter
