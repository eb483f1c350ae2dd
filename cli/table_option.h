// What a --table names, in every command that takes one: a compiled-in table's name (tables/<name>.h),
// a table file (probefit's JSON), a committed table's name (probe::committedTablesFolder()/<name>.json,
// where no file of that name is here) or, with its taps and form, a file in the published text layout.
#pragma once

#include <string>

#include "probe/tap_table.h"

namespace probefilter {

// The published text layout's shape, which the file does not carry (taps 0: not given).
struct PublishedLayout {
    int taps = 0;
    std::string form;
    int faceSize = 0;
    int levelCount = 0;
    probe::RoughnessMapping mapping;
    probe::PyramidSettings pyramid;
};

// Throws ProbeError naming the value where it is none of them.
probe::TapTable tableOption(const std::string& table, const PublishedLayout& published = {});

} // namespace probefilter
