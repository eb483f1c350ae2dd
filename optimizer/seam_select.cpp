#include "seam_select.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "evaluate.h"
#include "probe/error.h"
#include "probe/seam_measure.h"
#include "probe/synthetic.h"
#include "probe/table_filter.h"
#include "tail_check.h"

namespace probefit {

using namespace probe;

namespace {

void checkSameShape(const std::vector<SeamCandidate>& candidates) {
    if (candidates.empty()) throw ProbeError("select: no candidate tables");
    const TapTable& first = candidates.front().table;
    for (const SeamCandidate& c : candidates) {
        const TapTable& t = c.table;
        if (t.faceSize != first.faceSize || t.levelCount != first.levelCount || t.taps != first.taps || t.form != first.form ||
            t.mapping != first.mapping || t.lobe != first.lobe || t.pyramid.kind != first.pyramid.kind ||
            t.pyramid.weighting != first.pyramid.weighting)
            throw ProbeError(fmt::format("{}: not the shape of {} (size, levels, taps, form, mapping, lobe and pyramid must agree)", c.name,
                                         candidates.front().name));
    }
}

// The L1 the choice compares: over all texels where every candidate measured it, else the stratified set.
double levelL1(const TableLevel& level, bool all) { return all ? level.all.mean : level.stratified.mean; }

// Per level, whether the table reaches the lobe's tail there (probefit tail; levels without a tail do).
std::vector<bool> tailReached(const TapTable& table) {
    std::vector<bool> reached(static_cast<std::size_t>(table.levelCount), true);
    for (const TailLevel& level : checkTail(table))
        for (const TailSample& sample : level.samples)
            reached[static_cast<std::size_t>(level.level)] = reached[level.level] && sample.reached();
    return reached;
}

} // namespace

SeamSelection selectWithinSeamBound(const std::vector<SeamCandidate>& candidates, SelectOrder order) {
    checkSameShape(candidates);
    const TapTable& shape = candidates.front().table;
    const CubeImage sky = skyProbe(shape.faceSize);
    const CubeLevels reference = skyReference(shape.faceSize, shape.levelCount, shape.mapping, shape.lobe);
    const std::vector<double> bounds = seamBounds(reference, seamBoundCap(shape.lobe));
    std::vector<CubeLevels> filtered;
    std::vector<std::vector<bool>> tails;
    for (const SeamCandidate& c : candidates) {
        filtered.push_back(tableFilter(sky, c.table));
        tails.push_back(tailReached(c.table));
    }

    SeamSelection selection{shape, {}};
    selection.table.fitSeconds = 0.0;
    for (const SeamCandidate& c : candidates) selection.table.fitSeconds += c.table.fitSeconds;
    std::string sources;
    for (int m = 0; m < shape.levelCount; ++m) {
        bool all = true;
        for (const SeamCandidate& c : candidates) all = all && c.table.levels[m].all.mean >= 0.0;
        LevelSelection level;
        level.bound = bounds[m];
        int nearest = 0;
        for (int k = 0; k < static_cast<int>(candidates.size()); ++k) {
            const CubeImage& out = filtered[k][m];
            level.seamRatios.push_back(level.bound > 0.0 ? seamRatio(out) : 0.0);
            const SeamSteps steps = steepestSteps(out), exact = steepestSteps(reference[m]);
            const bool measured = level.bound > 0.0 && exact.edge > 0.0 && exact.quarterLine > 0.0;
            level.edgeSteps.push_back(measured ? steps.edge / exact.edge : 0.0);
            level.quarterSteps.push_back(measured ? steps.quarterLine / exact.quarterLine : 0.0);
            level.within.push_back(withinSeamBound(out, level.bound, &reference[m]));
            level.tailReached.push_back(tails[k][m]);
            if (level.seamRatios[k] < level.seamRatios[nearest]) nearest = k;
        }
        // The lowest L1 (or the first) within the seam bound among the fits that reach the tail, else among all.
        bool found = false;
        for (const bool needTail : {true, false}) {
            for (int k = 0; k < static_cast<int>(candidates.size()); ++k) {
                if (!level.within[k] || (needTail && !tails[k][m])) continue;
                if (!found || (order == SelectOrder::lowestL1 &&
                               levelL1(candidates[k].table.levels[m], all) < levelL1(candidates[level.chosen].table.levels[m], all))) {
                    level.chosen = k;
                    found = true;
                }
            }
            if (found) break;
        }
        if (!found) {
            level.chosen = nearest;
            level.withinBound = false;
        }
        selection.table.levels[m] = candidates[level.chosen].table.levels[m];
        // The selection keeps the first candidate's stratified budget.
        if (candidates[level.chosen].table.stratifiedBudget != shape.stratifiedBudget) restratifyLevel(selection.table, m);
        sources += fmt::format("{}{}: {}", m == 0 ? "" : ", ", m, candidates[level.chosen].name);
        selection.levels.push_back(std::move(level));
    }
    // The seam weight is recorded only where every kept level was fitted with the same one.
    selection.table.seamWeight = candidates[selection.levels.front().chosen].table.seamWeight;
    for (const LevelSelection& level : selection.levels)
        if (candidates[level.chosen].table.seamWeight != selection.table.seamWeight) selection.table.seamWeight = 0.0;
    std::vector<std::string> fits;
    for (const SeamCandidate& c : candidates)
        fits.push_back(fmt::format("[{}: seam weight {}, {}]", c.name, c.table.seamWeight, c.table.solver));
    selection.table.solver =
        fmt::format("probefit select: per level, the {} among {} fits whose seams stay within "
                    "the bound of seam_measure.h, those that reach the lobe's tail first (level: fit) {}; "
                    "the fits: {}",
                    order == SelectOrder::first ? "first listed" : "lowest impulse L1", candidates.size(), sources, fmt::join(fits, " "));
    return selection;
}

} // namespace probefit
