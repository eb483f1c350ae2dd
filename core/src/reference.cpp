#include "probe/reference.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <omp.h>

#include "probe/ggx.h"
#include "probe/range_scale.h"

namespace probe {

namespace {

// The source in structure-of-arrays form for a vectorized inner loop: texel directions and
// radiance premultiplied by solid angle.
struct SourceTexels {
    int size;
    std::vector<float> x, y, z, solidAngle, r, g, b;

    explicit SourceTexels(const CubeImage& source) : size(source.size) {
        const CubeGeometry geometry(source.size);
        const std::size_t n = texelCount(size);
        for (auto* v : {&x, &y, &z, &solidAngle, &r, &g, &b}) v->resize(n);
        for (std::size_t t = 0; t < n; ++t) {
            const glm::dvec3& d = geometry.directions[t];
            const double w = geometry.solidAngles[t];
            const glm::vec3 radiance = source.texel(t);
            x[t] = static_cast<float>(d.x);
            y[t] = static_cast<float>(d.y);
            z[t] = static_cast<float>(d.z);
            solidAngle[t] = static_cast<float>(w);
            r[t] = static_cast<float>(radiance.r * w);
            g[t] = static_cast<float>(radiance.g * w);
            b[t] = static_cast<float>(radiance.b * w);
        }
    }
};

// True when every point of the face has R.l <= 0, where both kernels vanish. The face is convex,
// so checking its four corners is exact.
bool faceBehind(const glm::dvec3& R, int face) {
    for (double u : {-1.0, 1.0})
        for (double v : {-1.0, 1.0})
            if (glm::dot(R, faceUvToCubePoint(face, u, v)) > 0.0) return false;
    return true;
}

// The texels [first, last) of row j of a face of `size` where R.l > 0 may hold (both kernels vanish
// elsewhere): along a row R.l is linear in u, so they are one interval. It is widened by a texel for
// rounding; the kernels' own test decides within it, so the sums are those over the whole row.
std::pair<int, int> facingSpan(const glm::dvec3& R, int face, int j, int size) {
    const double v = texelCentreUv(j, size);
    const double left = glm::dot(R, faceUvToCubePoint(face, -1.0, v)), right = glm::dot(R, faceUvToCubePoint(face, 1.0, v));
    if (left <= 0.0 && right <= 0.0) return {0, 0};
    if (left > 0.0 && right > 0.0) return {0, size};
    // R.l = 0 at texel coordinate x (texel i's centre is at i + 0.5).
    const double x = size * left / (left - right);
    if (left > 0.0) return {0, std::min(size, static_cast<int>(std::ceil(x)) + 1)};
    return {std::max(0, static_cast<int>(std::floor(x)) - 1), size};
}

struct Convolution {
    glm::dvec3 weighted{0.0}; // sum L K dOmega
    double weight = 0.0;      // sum K dOmega
};

// Sums kernel(R.l, |R - l|^2) over all source texels. Each row is summed in float (vectorized),
// rows in double.
template <typename Kernel>
Convolution convolve(const SourceTexels& src, const glm::dvec3& R, Kernel kernel) {
    Convolution sum;
    const float rx = static_cast<float>(R.x), ry = static_cast<float>(R.y), rz = static_cast<float>(R.z);
    const std::size_t s = static_cast<std::size_t>(src.size);
    for (int f = 0; f < kFaceCount; ++f) {
        if (faceBehind(R, f)) continue;
        for (std::size_t row = 0; row < s; ++row) {
            const auto [first, last] = facingSpan(R, f, static_cast<int>(row), src.size);
            const std::size_t begin = (f * s + row) * s + first, end = (f * s + row) * s + last;
            float sr = 0.0f, sg = 0.0f, sb = 0.0f, sw = 0.0f;
#pragma omp simd reduction(+ : sr, sg, sb, sw)
            for (std::size_t t = begin; t < end; ++t) {
                const float dx = rx - src.x[t], dy = ry - src.y[t], dz = rz - src.z[t];
                const float cosRL = rx * src.x[t] + ry * src.y[t] + rz * src.z[t];
                const float k = kernel(cosRL, dx * dx + dy * dy + dz * dz);
                sr += k * src.r[t];
                sg += k * src.g[t];
                sb += k * src.b[t];
                sw += k * src.solidAngle[t];
            }
            sum.weighted += glm::dvec3(sr, sg, sb);
            sum.weight += sw;
        }
    }
    return sum;
}

CubeImage copyLevel(const CubeImage& source, int outSize) {
    CubeImage out(outSize);
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < outSize; ++j)
            for (int i = 0; i < outSize; ++i) {
                const Texel t{f, i, j};
                out.set(texelIndex(t, outSize),
                        source.texel(texelIndex(directionToTexel(texelDirection(t, outSize), source.size), source.size)));
            }
    return out;
}

template <typename PerTexel>
CubeImage forEachOutputTexel(int outSize, PerTexel perTexel) {
    CubeImage out(outSize);
    const CubeGeometry geometry(outSize);
#pragma omp parallel for schedule(dynamic, 16)
    for (std::size_t t = 0; t < texelCount(outSize); ++t) out.set(t, perTexel(geometry.directions[t]));
    return out;
}

} // namespace

CubeImage referenceLevel(const CubeImage& source, int outSize, double alpha, Lobe lobe) {
    alpha = lobeAlpha(lobe, alpha);
    if (alpha <= 0.0) return copyLevel(source, outSize);
    const SourceTexels src(source);
    return visitLobeKernel<float>(lobe, alpha, [&](auto kernel) {
        return forEachOutputTexel(outSize, [&](const glm::dvec3& R) {
            const Convolution c = convolve(src, R, kernel);
            return glm::vec3(c.weighted / c.weight);
        });
    });
}

CubeLevels referenceFilter(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const ProgressCallback& progress,
                           Lobe lobe) {
    validateSizeAndLevels(source.size, levelCount);
    const int shift = rangeShift(source); // rows are summed in float
    const CubeImage scaled = shifted(source, -shift);
    CubeLevels levels;
    std::size_t total = 0, done = 0;
    for (int m = 0; m < levelCount; ++m) total += texelCount(source.size >> m);
    for (int m = 0; m < levelCount; ++m) {
        levels.push_back(referenceLevel(scaled, source.size >> m, levelAlpha(mapping, m, levelCount), lobe));
        done += texelCount(source.size >> m);
        if (progress) progress(done, total);
    }
    shiftLevels(levels, shift);
    return levels;
}

double estimateReferenceSeconds(int faceSize, int levelCount, const RoughnessMapping& mapping, Lobe lobe) {
    validateSizeAndLevels(faceSize, levelCount);
    // Every filtered output texel sums over every source texel (less the faces behind it): the time
    // of one output texel grows with the source's texel count. Measured on one thread over a
    // 128^2 source at directions spread over the cube, then scaled. At alpha 0.3: Charlie's power
    // there, 1 / (2 alpha), is not 1, for which the math library takes a short path (timed at alpha
    // 0.5, a 128^2 Charlie reference would be estimated at a quarter of its time).
    constexpr int kSampleSize = 128, kSampleDirections = 24;
    constexpr double kSampleAlpha = 0.3;
    const SourceTexels src{CubeImage(kSampleSize)};
    const CubeGeometry sample(4);
    volatile double kept = 0.0; // the sums are used, so that the timed work is done
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < kSampleDirections; ++k) {
        const glm::dvec3& R = sample.directions[static_cast<std::size_t>(k) * sample.directions.size() / kSampleDirections];
        kept = kept + visitLobeKernel<float>(lobe, kSampleAlpha, [&](auto kernel) { return convolve(src, R, kernel).weight; });
    }
    const double perTexel = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kSampleDirections *
                            (static_cast<double>(faceSize) / kSampleSize) * (static_cast<double>(faceSize) / kSampleSize);
    double outputTexels = 0.0;
    for (int m = 0; m < levelCount; ++m)
        if (lobeAlpha(lobe, levelAlpha(mapping, m, levelCount)) > 0.0) outputTexels += static_cast<double>(texelCount(faceSize >> m));
    return outputTexels * perTexel / std::max(1, omp_get_max_threads());
}

std::vector<double> referenceKernel(const glm::dvec3& R, int sourceSize, const LevelLobe& levelLobe) {
    return referenceKernel(R, CubeGeometry(sourceSize), levelLobe);
}

std::vector<double> referenceKernel(const glm::dvec3& R, const CubeGeometry& geometry, const LevelLobe& levelLobe) {
    const ReferenceLobe lobe(R, geometry, levelLobe);
    std::vector<double> weights(texelCount(geometry.size));
    for (std::size_t t = 0; t < weights.size(); ++t) weights[t] = lobe(t);
    return weights;
}

ReferenceLobe::ReferenceLobe(const glm::dvec3& R, const CubeGeometry& source, const LevelLobe& lobe) : ReferenceLobe(R, source, lobe, 1.0) {
    if (mirror_) return;
    // In texel order, so the sum does not depend on how the caller visits texels.
    double sum = 0.0;
    for (int f = 0; f < kFaceCount; ++f) {
        if (faceBehind(r_, f)) continue;
        for (int j = 0; j < source.size; ++j) {
            const auto [first, last] = facingSpan(r_, f, j, source.size);
            for (std::size_t t = texelIndex({f, first, j}, source.size), end = t + static_cast<std::size_t>(last - first); t < end; ++t) {
                const glm::dvec3& l = source.directions[t];
                const glm::dvec3 d = r_ - l;
                sum += kernel(glm::dot(r_, l), glm::dot(d, d)) * source.solidAngles[t];
            }
        }
    }
    normalization_ = sum;
    inverseNormalization_ = 1.0 / sum;
}

ReferenceLobe::ReferenceLobe(const glm::dvec3& R, const CubeGeometry& source, const LevelLobe& lobe, double normalization)
    : source_(&source), r_(glm::normalize(R)), charlie_(lobe.lobe == Lobe::charlie), mirror_(!charlie_ && lobe.alpha <= 0.0),
      constants_(lobeConstants(lobe.lobe, lobe.alpha)),
      mirrorTexel_(mirror_ ? texelIndex(directionToTexel(r_, source.size), source.size) : 0), normalization_(normalization),
      inverseNormalization_(1.0 / normalization) {}

CubeImage exactIrradiance(const CubeImage& source, int outSize) {
    const SourceTexels src(source);
    return forEachOutputTexel(outSize, [&](const glm::dvec3& n) {
        const Convolution c = convolve(src, n, [](float cosNL, float) { return std::max(cosNL, 0.0f); });
        return glm::vec3(c.weighted / std::numbers::pi);
    });
}

} // namespace probe
