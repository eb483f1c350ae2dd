// The tap generator a scene probe's method uses: its table (file or built in) or FIS.
#pragma once

#include "probe/scene.h"
#include "probe/tap_sum.h"
#include "probe/tap_table.h"

namespace probefilter {

// The table a probe filters with: its "table" file, checked against the probe's size, levels and
// mapping, else the compiled-in table for them. Throws ProbeError naming the scene file and the
// problem.
probe::TapTable sceneProbeTable(const probe::Scene& scene, const probe::SceneProbe& probe);

probe::TapGenerator sceneProbeTaps(const probe::Scene& scene, const probe::SceneProbe& probe);

} // namespace probefilter
