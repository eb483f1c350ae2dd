// The exact reference of docs/design.md: brute-force texel-centre quadrature over every source texel,
// accumulated in double. Every other method is judged against it.
#pragma once

#include <functional>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "probe/cube_image.h"
#include "probe/ggx.h"
#include "probe/lobe.h"
#include "probe/roughness.h"

namespace probe {

// Progress callback: (work done, total work); called from one thread at a time.
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

// F(R) = sum_t L(t) K(R, l_t) dOmega_t / sum_t K(R, l_t) dOmega_t for every texel centre R of an
// output level of face size `outSize`, K the lobe's at lobeAlpha(lobe, alpha). A GGX alpha of 0 is a
// copy (point lookup of the source).
CubeImage referenceLevel(const CubeImage& source, int outSize, double alpha, Lobe lobe = Lobe::ggx);

// Every output level m = 0..levelCount-1 (face size source.size >> m, alpha from the mapping),
// all cores. Throws ProbeError for an impossible level count.
CubeLevels referenceFilter(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const ProgressCallback& progress = {},
                           Lobe lobe = Lobe::ggx);

// The seconds referenceFilter takes for these levels of a faceSize^2 source on this machine's
// threads: the time of one output texel measured on a small source (about 0.1 s) and scaled by the
// texel counts, since the reference is quadratic in them (a lower bound where a large source no
// longer fits the caches).
double estimateReferenceSeconds(int faceSize, int levelCount, const RoughnessMapping& mapping, Lobe lobe = Lobe::ggx);

// The reference's impulse response for output direction R: normalized weights k(R, t) over the
// source texels of `sourceSize` (indexed by texelIndex, summing to 1). A GGX alpha of 0 puts all
// weight on the texel that contains R.
std::vector<double> referenceKernel(const glm::dvec3& R, int sourceSize, const LevelLobe& lobe);
// The same with the source geometry computed once by the caller (for many output texels).
std::vector<double> referenceKernel(const glm::dvec3& R, const CubeGeometry& source, const LevelLobe& lobe);

// The same response texel by texel, for measuring without a vector over the whole cube:
// k(R, t) = K(R, l_t) dOmega_t / Z with Z = sum_s K(R, l_s) dOmega_s, K the level's lobe. Z costs one
// pass over the source texels in front of R (K vanishes behind it); a caller that knows it passes it.
// The source texels are symmetric under the cube's 48 symmetries, so Z is too: Z(g R) = Z(R).
class ReferenceLobe {
public:
    ReferenceLobe(const glm::dvec3& R, const CubeGeometry& source, const LevelLobe& lobe);
    ReferenceLobe(const glm::dvec3& R, const CubeGeometry& source, const LevelLobe& lobe, double normalization);

    double normalization() const { return normalization_; }
    double operator()(std::size_t t) const { // inline: the dense passes read every texel
        if (mirror_) return t == mirrorTexel_ ? 1.0 : 0.0;
        const glm::dvec3& l = source_->directions[t];
        const glm::dvec3 d = r_ - l;
        return kernel(glm::dot(r_, l), glm::dot(d, d)) * source_->solidAngles[t] * inverseNormalization_;
    }

private:
    double kernel(double cosRL, double distanceSquared) const {
        return charlie_ ? charlieKernel(cosRL, distanceSquared, constants_.exponent, constants_.cutoff)
                        : ggxKernel(cosRL, distanceSquared, constants_.alpha2);
    }

    const CubeGeometry* source_;
    glm::dvec3 r_;
    bool charlie_, mirror_;
    LobeConstants constants_;
    std::size_t mirrorTexel_; // a GGX alpha of 0: the texel that holds all the weight
    double normalization_, inverseNormalization_;
};

// The exact cosine convolution E(n) = sum_t L(t) max(n.l_t, 0) dOmega_t / pi at every texel centre
// of a level of `outSize` (so a constant radiance L gives E = L).
CubeImage exactIrradiance(const CubeImage& source, int outSize);

} // namespace probe
