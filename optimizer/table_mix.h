// `probefit mix`: a table whose output levels use different tap counts. Level m is level m of the
// m-th source table, padded to the largest N with taps of zero weight, which the filters skip
// (probe::tapHasZeroWeight). A level's cost is proportional to its texel count (level 1 holds 3/4 of
// a probe's filtered texels), so more taps on the small, rough levels cost little time.
#pragma once

#include <string>
#include <vector>

#include "probe/tap_table.h"

namespace probefit {

struct MixSource {
    std::string name; // for the table's solver text
    probe::TapTable table;
};

// One source per output level. Throws ProbeError naming the source unless the count matches the
// level count and every source has the first one's size, levels, form, mapping and pyramid.
probe::TapTable mixTables(const std::vector<MixSource>& perLevel);

} // namespace probefit
