// How much harder a filtered cube steps across its face edges than inside its faces, against the
// exact reference (the seam check of the hard-case suite, and what `probefit select` keeps within).
// A level's seam ratio is the steepest step between face-edge neighbours over the steepest step
// between interior neighbours (largest channel difference); its bound is 1.1x the exact reference's
// own ratio on the smooth sky at the same size, level count, mapping and lobe, and never more than one
// k per lobe: 1.1x the largest ratio of that lobe's 64^2 exact reference (default levels, glTF).
// Where the reference's level is at hand, a level whose steepest edge step is within 1.1x the
// reference's own, times how much steeper than the reference's its steps across the lines a quarter
// of the way into each face are (at least 1), is within the bound too: a filter smoother inside its
// faces than the reference lowers the interior step its ratio divides by (a thin Charlie ring's
// reference steps hardest at the pole of a sharp horizon, inside a face), while its seams step no
// harder, against the reference, than its own faces do away from their edges.
#pragma once

#include <vector>

#include "probe/cube_image.h"
#include "probe/lobe.h"
#include "probe/roughness.h"

namespace probe {

// The steepest steps between neighbouring texels of one level: across a face edge, between interior
// neighbours, and across the lines a quarter of the way into each face (to compare with the edges).
struct SeamSteps {
    double edge = 0.0;
    double interior = 0.0;
    double quarterLine = 0.0;
};
SeamSteps steepestSteps(const CubeImage& level); // the largest RGB step of each kind

// edge / interior; 0 for faces under 4 texels (no interior to compare with) or a flat level.
double seamRatio(const CubeImage& level);

// The exact reference of the smooth sky (synthetic.h's skyProbe) with the lobe, all levels; costs
// seconds at 128^2.
CubeLevels skyReference(int faceSize, int levelCount, const RoughnessMapping& mapping, Lobe lobe);

// The lobe's k: 1.1x the largest seam ratio over the levels of its 64^2 sky reference.
double seamBoundCap(Lobe lobe);

// Per level, min(1.1x the seam ratio of `reference` at that level, cap); 0 where faces are under 4.
std::vector<double> seamBounds(const CubeLevels& reference, double cap);

// Whether a level is within its bound (from seamBounds; 0: no bound): its seam ratio at most the
// bound, or, given the reference's level, its steepest edge step at most 1.1x the reference's times
// max(1, its quarter-line steps over the reference's).
bool withinSeamBound(const CubeImage& level, double bound, const CubeImage* reference);

} // namespace probe
