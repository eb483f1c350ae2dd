// Filtered importance sampling (Krivanek & Colbert 2008), the baseline, as engines do it: N
// Hammersley samples of GGX around R with n = v = R, each read from the pyramid at the level whose
// texels cover the sample's solid angle, weighted by n.l.
#pragma once

#include <string_view>
#include <vector>

#include "probe/lobe.h"
#include "probe/roughness.h"
#include "probe/tap_sum.h"

namespace probe {

// What the samples read: the cube pyramid (engines' FIS), or a dual-paraboloid map with its own mips
// (Krivanek & Colbert as published; probe/paraboloid.h).
enum class FisMap { cube, paraboloid };
std::string_view fisMapName(FisMap map);   // "cube" or "paraboloid"
FisMap parseFisMap(std::string_view name); // ParameterError("method.fis.map") for anything else

struct FisSettings {
    int samples = 32;
    double bias = 0.0;       // added to the level; 0 is the accurate setting (docs/design.md), Filament uses 1
    PyramidSettings pyramid; // the cube pyramid's; a paraboloid map's mips are box averages
    // Samples per output level, level 0 first; empty: `samples` at every level. Rough levels need
    // many more samples than sharp ones and hold few texels, so a per-level count buys accuracy cheaply.
    std::vector<int> levelSamples;
    FisMap map = FisMap::cube;

    int samplesAt(int level) const { return levelSamples.empty() ? samples : levelSamples[static_cast<std::size_t>(level)]; }
};

// Throws ParameterError ("samples", "fis-bias") unless every sample count is >= 1, a per-level list
// has levelCount entries and the bias is finite.
void validateSampleCounts(const FisSettings& settings, int levelCount);

// The per-level mix of sweeps and scenes: N at level 1, 4N at level 2, 16N from level 3 on, at most
// 1024 (level 0, a copy where alpha = 0, gets N).
std::vector<int> mixedLevelSamples(int samples, int levelCount);

// The samples of one output level in the tangent frame of R (R = +z), as taps: they do not depend
// on R, so a filter makes them once per level and rotates them to each texel (fisTaps,
// and the GPU shader from the same list). Sample i of N uses the Hammersley point
// (i / N, radicalInverse2(i)), h from the lobe's distribution of alpha (lobeSample; Charlie takes
// (i + 1/2) / N, since its density vanishes at h = n), l = reflect(-z, h); samples with n.l <= 0 are
// dropped. pdf_l the lobe's, level = 0.5 log2((1 / (N pdf_l)) / (4 pi / (6 S_0^2))) + bias, weight
// n.l (= l.z): the kernel D n.l over the density, which is D / 4 up to a constant for both lobes.
std::vector<Tap> fisSamples(double alpha, int faceSize, int samples, double bias, Lobe lobe = Lobe::ggx);

// fisSamples for every output level of a mapping, settings.samplesAt(m) at level m, at the lobe's
// alpha (lobeAlpha); empty at the levels with alpha = 0, which are copies. Throws ProbeError as
// validateSampleCounts.
std::vector<std::vector<Tap>> fisSamplesPerLevel(int faceSize, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings,
                                                 Lobe lobe = Lobe::ggx);

// The tangent frame of R (unit) that the samples are rotated into: up = +Z, or +X where
// |R.z| > 0.999; x = normalize(cross(up, R)), y = cross(R, x), z = R.
void fisFrame(const glm::dvec3& R, glm::dvec3& x, glm::dvec3& y);

// The taps for direction R: `samples` (from fisSamples) rotated into the frame of R.
void fisTaps(const glm::dvec3& R, const std::vector<Tap>& samples, std::vector<Tap>& taps);

// As a TapGenerator over the output levels of a mapping (levels with alpha = 0 are copies), with
// settings.samplesAt(level) samples at each level.
TapGenerator fisTapGenerator(int faceSize, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings,
                             Lobe lobe = Lobe::ggx);

} // namespace probe
