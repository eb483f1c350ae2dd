#include "probe/error_measures.h"

#include <cmath>
#include <numeric>

#include "probe/error.h"

namespace probe {

double impulseL1(const std::vector<double>& w, const std::vector<double>& k) {
    if (w.size() != k.size()) throw ProbeError("impulse L1: weight vectors of different sizes");
    const double sw = std::accumulate(w.begin(), w.end(), 0.0), sk = std::accumulate(k.begin(), k.end(), 0.0);
    double e = 0.0;
    for (std::size_t t = 0; t < w.size(); ++t) e += std::abs(w[t] / sw - k[t] / sk);
    return e;
}

void ImpulseErrorAccumulator::add(const Texel& texel, double solidAngle, double error) {
    weightedSum_ += solidAngle * error;
    solidAngleSum_ += solidAngle;
    if (error > worst_.max) {
        worst_.max = error;
        worst_.worst = texel;
    }
}

ImpulseError ImpulseErrorAccumulator::result() const {
    ImpulseError r = worst_;
    r.mean = solidAngleSum_ > 0.0 ? weightedSum_ / solidAngleSum_ : 0.0;
    return r;
}

double imageL1(const CubeImage& out, const CubeImage& ref) {
    if (out.size != ref.size) throw ProbeError("image L1: levels of different sizes");
    const CubeGeometry geometry(ref.size);
    double difference = 0.0, magnitude = 0.0;
    for (std::size_t t = 0; t < texelCount(ref.size); ++t)
        for (int c = 0; c < 3; ++c) {
            difference += std::abs(double(out.rgb[3 * t + c]) - ref.rgb[3 * t + c]) * geometry.solidAngles[t];
            magnitude += std::abs(double(ref.rgb[3 * t + c])) * geometry.solidAngles[t];
        }
    return magnitude > 0.0 ? difference / magnitude : 0.0;
}

} // namespace probe
