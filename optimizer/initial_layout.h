// Where the fit starts: a lobe-shaped layout, the neighbouring level's solution, or another table.
#pragma once

#include "probe/tap_table.h"

namespace probefit {

// The angle (radians) the taps of a lobe of GGX alpha are spread over: 2 atan(alpha), the median
// angle of the reflected direction, capped at 0.9.
double lobeAngle(double alpha);

// Every frame gets one tap on the lobe axis and the others on one ring (N < 8) or two rings, with
// levels whose texels match the spacing of the taps; quadratic terms 0. A Charlie table's lobe is a
// ring, not a peak: its levels get the importance layout instead.
void lobeLayout(probe::TapTable& table, int level, double alpha);

// The taps of filtered importance sampling (probe/fis.h) as a start that reaches
// the lobe's tail: tap i at the table lobe's quantile of Hammersley point i, at the pyramid level of its pdf
// and weighted by n.l, so the first iterate is an importance sampler. The samples are turned about
// the lobe axis by `rotation` radians; every frame gets the same taps; quadratic terms 0. Samples
// below the horizon (dropped by FIS) become taps of weight 0 on the axis.
void importanceLayout(probe::TapTable& table, int level, double alpha, double rotation);

// A hop from a fitted level: every tap's direction moved by about a quarter of the lobe angle, its
// level by up to half a pyramid level and its weight by up to 20%, at random from `seed`
// (deterministic); quadratic terms kept. The local gradient cannot carry a tap across a ridge of the
// L1; a refit from a hop can land in another basin.
void hopLayout(probe::TapTable& table, int level, double alpha, unsigned seed);

// Level `level` from the already fitted level `from`: directions widened and levels raised by the
// ratio of the two lobes.
void warmStartFromLevel(probe::TapTable& table, int level, int from);

// Level `level` from level `from` of another table (any face size, level count or mapping; the same
// taps, either form): directions widened and levels moved by the ratio of the two lobes, and levels
// moved by the ratio of the face sizes, so that the taps cover the same angles.
void startFromBank(probe::TapTable& table, int level, const probe::TapTable& bank, int from);

// Level `level` from the same level of `init` (same face size; N or N/2 taps; either form). With
// N/2 taps each tap is split into two. spread 0: at the same place with weights 0.6 and 0.4 of its
// own, so the start filters exactly as `init` does. spread > 0: half the weight each, moved apart by
// +-spread texels of the tap's pyramid level, so that a converged init does not hold the fit at its
// stationary point (the fit keeps the exact split where it cannot beat it).
void startFromTable(probe::TapTable& table, int level, const probe::TapTable& init, double spread = 0.0);

// Every frame gets the taps of frame `frame`. The lobe is the same about every axis, so one frame's
// taps suit the others; a fit's frames can settle in different basins, and the best frame copied
// into the others starts a refit in its basin.
void oneFrameLayout(probe::TapTable& table, int level, int frame);

} // namespace probefit
