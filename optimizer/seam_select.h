// `probefit select`: a table assembled level by level from several fits of the same shape (different
// seam weights, iterations or starts). Output levels are independent filters, so each level takes the
// fit with the lowest impulse L1 (or the first listed) among those whose seams stay within the bound of
// seam_measure.h and, where any of those does, that reach the lobe's tail (tail_check.h): multi-start
// under constraints that the L1 alone does not see.
#pragma once

#include <string>
#include <vector>

#include "probe/tap_table.h"

namespace probefit {

struct SeamCandidate {
    std::string name; // for the table's solver text and the log
    probe::TapTable table;
};

// Per level, what was measured and which candidate was kept.
struct LevelSelection {
    int chosen = 0;                   // index into the candidates
    std::vector<double> seamRatios;   // per candidate (0 where the level has no bound)
    std::vector<double> edgeSteps;    // per candidate: its steepest edge step over the reference's
    std::vector<double> quarterSteps; // per candidate: its steepest quarter-line step over the reference's
    std::vector<bool> within;         // per candidate: within the bound (probe::withinSeamBound)
    std::vector<bool> tailReached;    // per candidate
    double bound = 0.0;               // 0: faces under 4 texels, chosen by L1 alone
    bool withinBound = true;          // false: no candidate was; the one nearest the bound was kept
};

struct SeamSelection {
    probe::TapTable table;
    std::vector<LevelSelection> levels;
};

// What a level takes among the candidates within the bound: the lowest impulse L1, or the first in
// order (for fits of another objective than the L1 alone, listed before the fits they refine).
enum class SelectOrder { lowestL1, first };

// Throws ProbeError naming the candidate unless every candidate has the first one's size, levels,
// taps, form, mapping, lobe and pyramid. Costs the exact reference of the sky at the table's size.
SeamSelection selectWithinSeamBound(const std::vector<SeamCandidate>& candidates, SelectOrder order = SelectOrder::lowestL1);

} // namespace probefit
