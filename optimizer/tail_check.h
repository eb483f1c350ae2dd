// The analyzer of the lobe's tail: how much of the reference's impulse-response mass far from the
// lobe centre a table reproduces. GGX falls off slowly (D ~ alpha^2 / tan^4 theta), and taps held
// near the centre drop that mass: the L1 counts it only once among the whole lobe's errors.
#pragma once

#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "probe/tap_table.h"

namespace probefit {

// The tail begins this many texels of the output level (at a face centre, 2 / S_m radians each)
// from the lobe centre.
inline constexpr double kTailTexels = 3.0;
// That radius in radians at an output level of face size `size`.
inline double tailRadius(int size) { return std::min(kTailTexels * 2.0 / size, std::numbers::pi); }
// Levels whose reference puts less than this share of its mass in the tail have no tail to reach.
inline constexpr double kMinTailMass = 0.01;
// A table reaches the tail where the mass it puts there is within this factor of the reference's
// (at 0.5 the mass it misses costs at most half the reference's tail mass in L1).
inline constexpr double kTailBound = 0.5;

struct TailSample {
    std::string where;          // "face centre", "edge", "corner"
    double referenceMass = 0.0; // the reference's mass beyond the tail radius (of 1)
    double tableMass = 0.0;     // the table's (normalized) response there
    double fraction() const { return referenceMass > 0.0 ? tableMass / referenceMass : 1.0; }
    bool hasTail() const { return referenceMass >= kMinTailMass; }
    bool reached() const { return !hasTail() || (fraction() >= kTailBound && fraction() <= 1.0 / kTailBound); }
};

struct TailLevel {
    int level = 0;
    double radius = 0.0; // radians
    std::vector<TailSample> samples;
};

// Levels with alpha > 0 of a GGX table, three output texels each: face 0's centre, the middle of its
// edge i = 0, its corner (0, 0). A Charlie table has none: its lobe is a ring that ends at R's
// horizon, without GGX's slow falloff, and most of its mass lies beyond the radius.
std::vector<TailLevel> checkTail(const probe::TapTable& table);

} // namespace probefit
