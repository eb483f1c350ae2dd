// How a probe is filtered: the exact reference, a tap table (Manson & Sloan) or filtered importance
// sampling (Krivanek & Colbert). One description for the CPU filters, scene files, the GPU runtime
// and the command line.
#pragma once

#include <string_view>

#include "probe/fis.h"
#include "probe/lobe.h"
#include "probe/tap_sum.h"
#include "probe/tap_table.h"

namespace probe {

enum class MethodKind { table, fis, reference };
// "table", "fis" or "reference"; parsing throws ParameterError("method.kind", ...) for anything else.
std::string_view methodKindName(MethodKind kind);
MethodKind parseMethodKind(std::string_view name);

struct FilterMethod {
    MethodKind kind = MethodKind::table;
    const TapTable* table = nullptr; // table: the tap table (the caller keeps it alive)
    FisSettings fis;                 // fis: samples per texel (or per level), level bias, pyramid
    Lobe lobe = Lobe::ggx;           // the lobe filtered with (a table's must be its own)

    // Pass 1's pyramid: the table's (it was fitted over it) or FIS's.
    PyramidSettings pyramid() const { return kind == MethodKind::table && table ? table->pyramid : fis.pyramid; }
};

// Throws ParameterError naming the parameter and every reason unless `method` filters probes of
// this face size, level count and mapping: a table of that shape (validateTable), FIS sample counts
// of at least 1 (one per level when given per level), a table fitted for the lobe, the Charlie lobe
// with FIS only on the cube pyramid.
void validateMethod(const FilterMethod& method, int faceSize, int levelCount, const RoughnessMapping& mapping);

} // namespace probe
