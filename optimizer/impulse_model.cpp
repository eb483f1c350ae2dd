#include "impulse_model.h"

#include <algorithm>
#include <cmath>

#include <ceres/jet.h>

#include "probe/cube_sampling.h"
#include "probe/reference.h"

namespace probefit {

using namespace probe;

OutputTexel makeOutputTexel(const WeightedTexel& texel, const CubeGeometry& geometry, int level, double alpha) {
    const int size = geometry.size >> level;
    OutputTexel t;
    t.texel = texel.texel;
    t.weight = texel.weight;
    t.cubeVector = faceUvToCubePoint(t.texel.face, texelCentreUv(t.texel.i, size), texelCentreUv(t.texel.j, size));
    for (int a = 0; a < kFrameCount; ++a) t.frames[a] = frameSetup(t.cubeVector, a);
    const std::vector<double> k = referenceKernel(t.cubeVector, geometry, alpha);
    t.kernel.assign(k.begin(), k.end());
    return t;
}

std::vector<OutputTexel> prepareTexels(const std::vector<WeightedTexel>& texels, int baseSize, int level, double alpha) {
    const CubeGeometry geometry(baseSize);
    std::vector<OutputTexel> out(texels.size());
#pragma omp parallel for schedule(dynamic, 4)
    for (std::size_t n = 0; n < texels.size(); ++n) out[n] = makeOutputTexel(texels[n], geometry, level, alpha);
    return out;
}

ImpulseModel::ImpulseModel(int baseSize, PyramidSettings pyramid, int taps, TableForm form)
    : baseSize_(baseSize), pyramidLevels_(pyramidLevelCount(baseSize)), taps_(taps), form_(form),
      operators_(pyramidOperators(baseSize, pyramid)) {}

ImpulseModel::Workspace ImpulseModel::workspace() const {
    Workspace ws;
    for (int k = 0; k < pyramidLevels_; ++k) {
        ws.weights.emplace_back(texelCount(baseSize_ >> k), 0.0);
        ws.adjoint.emplace_back(texelCount(baseSize_ >> k), 0.0);
    }
    return ws;
}

ImpulseModel::Result ImpulseModel::evaluate(const double* const* blocks, const OutputTexel& texel, Workspace& ws,
                                            double* gradient, double* weightSumGradient) const {
    return form_ == TableForm::quadratic ? evaluateForm<3>(blocks, texel, ws, gradient, weightSumGradient)
                                         : evaluateForm<1>(blocks, texel, ws, gradient, weightSumGradient);
}

template <int K>
ImpulseModel::Result ImpulseModel::evaluateForm(const double* const* blocks, const OutputTexel& texel, Workspace& ws,
                                                double* gradient, double* weightSumGradient) const {
    constexpr int B = kTapParameterCount * K;
    using J = ceres::Jet<double, B>;
    struct TapRecord {
        int block;
        J weight;
        TrilinearFootprintT<J> footprint;
    };
    std::vector<TapRecord> records;
    records.reserve(static_cast<std::size_t>(blockCount()));
    Result result;
    int top = 0;
    for (int a = 0; a < kFrameCount; ++a) {
        const FrameSetup& frame = texel.frames[a];
        if (frame.weight <= 0.0) continue;
        for (int t = 0; t < taps_; ++t) {
            const int block = a * taps_ + t;
            std::array<J, B> c;
            for (int q = 0; q < B; ++q) c[q] = J(blocks[block][q], q);
            const TapSample<J> s = evaluateTap(frame, c.data(), K);
            TapRecord r{block, s.weight, trilinearFootprint(baseSize_, pyramidLevels_, s.direction, s.level)};
            for (int k = 0; k < r.footprint.count; ++k) top = std::max(top, r.footprint.taps[k].level);
            result.weightSum += s.weight.a;
            records.push_back(r);
        }
    }
    if (gradient) std::fill(gradient, gradient + static_cast<std::ptrdiff_t>(blockCount()) * B, 0.0);
    if (weightSumGradient) {
        std::fill(weightSumGradient, weightSumGradient + static_cast<std::ptrdiff_t>(blockCount()) * B, 0.0);
        for (const TapRecord& r : records)
            for (int q = 0; q < B; ++q) weightSumGradient[r.block * B + q] += r.weight.v[q];
    }
    if (result.weightSum == 0.0) {
        result.error = 2.0;
        return result;
    }

    // w = pushed-back normalized weights on pyramid texels.
    for (int k = 0; k <= top; ++k) std::fill(ws.weights[k].begin(), ws.weights[k].end(), 0.0);
    const double inverseSum = 1.0 / result.weightSum;
    for (const TapRecord& r : records)
        for (int k = 0; k < r.footprint.count; ++k) {
            const auto& p = r.footprint.taps[k];
            ws.weights[p.level][p.index] += r.weight.a * inverseSum * p.weight.a;
        }
    pushBackToBase(operators_, ws.weights, top);

    const std::vector<double>& w = ws.weights[0];
    std::vector<double>& sign = ws.adjoint[0];
    double e = 0.0;
    for (std::size_t t = 0; t < w.size(); ++t) {
        const double d = w[t] - static_cast<double>(texel.kernel[t]);
        e += std::abs(d);
        sign[t] = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
    }
    result.error = e;
    if (!gradient) return result;

    // d e / d c_p = G_p (the pulled-up sign); c_p = sum_i W_i b_ip / S, so
    // d e / d theta_i = (d(W_i A_i) - Ebar dW_i) / S with A_i = sum_p G_p b_ip and Ebar = sum_i W_i A_i / S.
    pullUpFromBase(operators_, ws.adjoint, top);
    std::vector<J> adjointOfTap(records.size());
    double eBar = 0.0;
    for (std::size_t n = 0; n < records.size(); ++n) {
        J sum(0.0);
        for (int k = 0; k < records[n].footprint.count; ++k) {
            const auto& p = records[n].footprint.taps[k];
            sum += ws.adjoint[p.level][p.index] * p.weight;
        }
        adjointOfTap[n] = sum;
        eBar += records[n].weight.a * sum.a;
    }
    eBar *= inverseSum;
    for (std::size_t n = 0; n < records.size(); ++n) {
        const J g = (records[n].weight * adjointOfTap[n] - records[n].weight * eBar) * inverseSum;
        for (int q = 0; q < B; ++q) gradient[records[n].block * B + q] += g.v[q];
    }
    return result;
}

std::vector<const double*> levelBlocks(const TapTable& table, int level) {
    std::vector<const double*> blocks;
    for (int a = 0; a < kFrameCount; ++a)
        for (int t = 0; t < table.taps; ++t) blocks.push_back(&table.levels[level].coefficients[table.offset(a, t)]);
    return blocks;
}

} // namespace probefit
