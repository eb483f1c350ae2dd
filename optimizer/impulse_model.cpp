#include "impulse_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <ceres/jet.h>

#include "probe/cube_footprint.h"
#include "probe/reference.h"
#include "probe/sh.h"
#include "probe/synthetic.h"
#include "tail_check.h"

namespace probefit {

using namespace probe;

namespace {
// The taps' reach (in base texels) above which the model runs dense passes over every texel
// instead of lists of the touched ones, as a fraction of the base texel count (measured at 128^2:
// lists are 3-5x faster at level 1, 2x slower where the taps reach most of the cube).
constexpr double kSparseReach = 0.25;

// An output texel's place: its cube point and frames, without a kernel.
OutputTexel placedTexel(const WeightedTexel& texel, int size) {
    OutputTexel t;
    t.texel = texel.texel;
    t.weight = texel.weight;
    t.cubeVector = texelCubePoint(t.texel, size);
    for (int a = 0; a < kFrameCount; ++a) t.frames[a] = frameSetup(t.cubeVector, a);
    return t;
}

} // namespace

OutputTexel makeMeasuredTexel(const WeightedTexel& texel, const CubeGeometry& geometry, int level, const LevelLobe& lobe,
                              double normalization) {
    OutputTexel t = placedTexel(texel, geometry.size >> level);
    t.lobe.emplace(t.cubeVector, geometry, lobe, normalization);
    t.kernelSum = 1.0;
    return t;
}

OutputTexel makeOutputTexel(const WeightedTexel& texel, const CubeGeometry& geometry, int level, const LevelLobe& lobe, bool tail) {
    const int size = geometry.size >> level;
    OutputTexel t = placedTexel(texel, size);
    const std::vector<double> k = referenceKernel(t.cubeVector, geometry, lobe);
    t.kernel.assign(k.begin(), k.end());
    for (const float v : t.kernel) t.kernelSum += static_cast<double>(v);
    if (!tail) return t;
    const glm::dvec3 R = glm::normalize(t.cubeVector);
    const double cosRadius = std::cos(tailRadius(size));
    t.tail.assign((k.size() + 63) / 64, 0);
    for (std::size_t n = 0; n < k.size(); ++n)
        if (glm::dot(geometry.directions[n], R) < cosRadius) {
            t.tail[n / 64] |= std::uint64_t{1} << (n % 64);
            t.kernelTail += static_cast<double>(t.kernel[n]);
        }
    return t;
}

OutputTexel makeCellTexel(const WeightedTexel& texel, int faceSize, int level, const LevelLobe& lobe, bool tail) {
    const int size = faceSize >> level;
    OutputTexel t = placedTexel(texel, size);
    const glm::dvec3 R = glm::normalize(t.cubeVector);
    LobeCells cells = lobeCells(R, faceSize, lobeDensity(R, lobe), tail ? tailRadius(size) : 0.0);
    t.cells = std::move(cells.cells);
    t.cellTree = std::move(cells.tree);
    t.kernelTail = cells.kernelTail;
    for (const LobeCell& c : t.cells) t.kernelSum += static_cast<double>(c.kernel);
    return t;
}

std::vector<OutputTexel> prepareTexels(const std::vector<WeightedTexel>& texels, int faceSize, int level, const LevelLobe& lobe, bool tail,
                                       Measure measure) {
    std::vector<OutputTexel> out(texels.size());
    if (measure == Measure::cells) {
#pragma omp parallel for schedule(dynamic, 4)
        for (std::size_t n = 0; n < texels.size(); ++n) out[n] = makeCellTexel(texels[n], faceSize, level, lobe, tail);
        return out;
    }
    const CubeGeometry geometry(faceSize);
#pragma omp parallel for schedule(dynamic, 4)
    for (std::size_t n = 0; n < texels.size(); ++n) out[n] = makeOutputTexel(texels[n], geometry, level, lobe, tail);
    return out;
}

ImpulseModel::ImpulseModel(int faceSize, PyramidSettings pyramid, int taps, TableForm form, double tailWeight)
    : faceSize_(faceSize), pyramidLevels_(pyramidLevelCount(faceSize)), taps_(taps), form_(form), tailWeight_(tailWeight),
      operators_(pyramidOperators(faceSize, pyramid)), dense_(operators_), spread_(responseSpread(faceSize, operators_)) {}

std::vector<std::array<double, 9>> responseSpread(int faceSize, const std::vector<DownsampleOperator>& operators) {
    const int levels = pyramidLevelCount(faceSize);
    std::vector<std::array<double, 9>> spread(static_cast<std::size_t>(levels), std::array<double, 9>{0, 0, 0, 0, 1, 0, 0, 0, 0});
    std::vector<std::vector<double>> weights(static_cast<std::size_t>(levels));
    for (int k = 1; k < levels && (faceSize >> k) >= 3; ++k) {
        const int size = faceSize >> k, centre = size / 2, span = 1 << k;
        for (int a = 0; a <= k; ++a) weights[static_cast<std::size_t>(a)].assign(texelCount(faceSize >> a), 0.0);
        weights[static_cast<std::size_t>(k)][texelIndex({0, centre, centre}, size)] = 1.0;
        pushBackToBase(operators, weights, k);
        std::array<double, 9>& s = spread[static_cast<std::size_t>(k)];
        s.fill(0.0);
        for (int y = (centre - 1) * span; y < (centre + 2) * span; ++y)
            for (int x = (centre - 1) * span; x < (centre + 2) * span; ++x)
                s[static_cast<std::size_t>((y / span - centre + 1) * 3 + (x / span - centre + 1))] +=
                    weights[0][texelIndex({0, x, y}, faceSize)];
    }
    return spread;
}

ImpulseModel::Workspace ImpulseModel::workspace() const {
    Workspace ws;
    for (int k = 0; k < pyramidLevels_; ++k) {
        ws.weights.emplace_back(texelCount(faceSize_ >> k), 0.0);
        ws.adjoint.emplace_back(texelCount(faceSize_ >> k), 0.0);
        ws.stamp.emplace_back(texelCount(faceSize_ >> k), 0u);
        ws.touched.emplace_back();
        ws.nodeTouched.emplace_back();
    }
    return ws;
}

namespace {

// e = sum_t |w_t - k_t| over the touched base texels (the lists' pass). visit() sees every base texel
// where w may be non-zero and returns d e / d w_t there; where w = 0 (texels not visited), |w - k| = k.
struct L1Measure {
    const OutputTexel& texel;
    double sum = 0.0, kernelVisited = 0.0;
    double visit(std::uint32_t t, double w) {
        const double k = texel.kernelAt(t);
        const double d = w - k;
        sum += std::abs(d);
        kernelVisited += k;
        return d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
    }
    double value() const { return sum + std::max(0.0, texel.kernelSum - kernelVisited); }
};

// Every tap of the output texel (frames with weight > 0), with derivatives in its block's coefficients:
// visit(block, weight, footprint).
template <int K, typename Visit>
void forEachTap(const OutputTexel& texel, const double* const* blocks, int taps, int faceSize, int pyramidLevels, Visit&& visit) {
    constexpr int B = kTapParameterCount * K;
    using J = ceres::Jet<double, B>;
    for (int f = 0; f < kFrameCount; ++f) {
        const FrameSetup& frame = texel.frames[f];
        if (frame.weight <= 0.0) continue;
        for (int t = 0; t < taps; ++t) {
            const int block = f * taps + t;
            std::array<J, B> coefficients;
            for (int q = 0; q < B; ++q) coefficients[q] = J(blocks[block][q], q);
            const TapSample<J> s = evaluateTap(frame, coefficients.data(), K);
            visit(block, s.weight, trilinearFootprint(faceSize, pyramidLevels, s.direction, s.level));
        }
    }
}

// The checkerboards of MomentBasis at texel t of a face of `size`: +1 or -1 each.
std::array<double, kMomentCount> checkerValues(const Texel& t, int size) {
    std::array<double, kMomentCount> y{};
    for (int n = 0; n < kMomentCount / 2; ++n) {
        const int square = std::max(1, size >> (n + 2));
        for (int shift = 0; shift < 2; ++shift) y[2 * n + shift] = onLightSquare(t, square, shift * square / 2) ? 1.0 : -1.0;
    }
    return y;
}

} // namespace

MomentBasis::MomentBasis(int faceSize, PyramidSettings pyramid, MomentFunctions functions) {
    const CubeGeometry geometry(faceSize);
    const std::vector<DownsampleOperator> operators = pyramidOperators(faceSize, pyramid);
    const int top = pyramidLevelCount(faceSize) - 1;
    std::vector<std::vector<double>> component(static_cast<std::size_t>(top) + 1);
    for (int k = 0; k <= top; ++k) {
        component[k].assign(texelCount(faceSize >> k), 0.0);
        levels_.emplace_back(component[k].size() * kMomentCount);
    }
    for (int f = 0; f < kFaceCount; ++f)
        for (int j = 0; j < faceSize; ++j)
            for (int i = 0; i < faceSize; ++i) {
                const std::size_t t = texelIndex({f, i, j}, faceSize);
                const auto at = levels_[0].begin() + static_cast<std::ptrdiff_t>(t * kMomentCount);
                if (functions == MomentFunctions::checkers) {
                    const std::array<double, kMomentCount> y = checkerValues({f, i, j}, faceSize);
                    std::copy(y.begin(), y.end(), at);
                } else {
                    const std::array<double, kShCount> y = shBasis(geometry.directions[t]);
                    std::copy(y.begin() + 1, y.end(), at);
                }
            }
    // Each function pulled up on its own: the pyramid operators act on one value per texel.
    for (int j = 0; j < kMomentCount; ++j) {
        for (std::size_t t = 0; t < component[0].size(); ++t) component[0][t] = levels_[0][t * kMomentCount + j];
        pullUpFromBase(operators, component, top);
        for (int k = 1; k <= top; ++k)
            for (std::size_t p = 0; p < component[k].size(); ++p) levels_[k][p * kMomentCount + j] = component[k][p];
    }
}

std::array<double, kMomentCount> kernelMoments(const OutputTexel& texel, const MomentBasis& basis) {
    std::array<double, kMomentCount> m{};
    // Over cells, each cell's mass times the basis pulled up to its level (its mean there).
    for (const LobeCell& c : texel.cells) {
        const double* y = basis.at(c.level, c.index);
        for (int j = 0; j < kMomentCount; ++j) m[j] += static_cast<double>(c.kernel) * y[j];
    }
    for (std::size_t t = 0; t < texel.kernel.size(); ++t) {
        const double k = static_cast<double>(texel.kernel[t]);
        if (k == 0.0) continue;
        const double* y = basis.at(static_cast<std::uint32_t>(t));
        for (int j = 0; j < kMomentCount; ++j) m[j] += k * y[j];
    }
    return m;
}

ImpulseModel::Result ImpulseModel::evaluate(const double* const* blocks, const OutputTexel& texel, Workspace& ws, double* gradient,
                                            double* weightSumGradient) const {
    return form_ == TableForm::quadratic ? evaluateWith<3>(blocks, texel, ws, gradient, weightSumGradient)
                                         : evaluateWith<1>(blocks, texel, ws, gradient, weightSumGradient);
}

void ImpulseModel::moments(const double* const* blocks, const OutputTexel& texel, const MomentBasis& basis, double* moments,
                           const double* c, double* gradient) const {
    if (form_ == TableForm::quadratic) momentsWith<3>(blocks, texel, basis, moments, c, gradient);
    else momentsWith<1>(blocks, texel, basis, moments, c, gradient);
}

template <int K>
void ImpulseModel::momentsWith(const double* const* blocks, const OutputTexel& texel, const MomentBasis& basis, double* moments,
                               const double* c, double* gradient) const {
    constexpr int B = kTapParameterCount * K;
    using J = ceres::Jet<double, B>;
    // Per tap i: its weight W_i, and A_i = sum over its footprint of b_ip Y(p) (the pulled-up basis),
    // as sum_j c_j A_ij with c's slope; m_j = sum_i W_i A_ij / S with S = sum_i W_i.
    struct TapMoments {
        int block;
        J weight, slope;
        std::array<double, kMomentCount> a{};
    };
    std::vector<TapMoments> records;
    records.reserve(static_cast<std::size_t>(blockCount()));
    double weightSum = 0.0;
    auto visit = [&](int block, const J& weight, const TrilinearFootprintT<J>& footprint) {
        TapMoments r{block, weight, J(0.0)};
        for (int k = 0; k < footprint.count; ++k) {
            const auto& p = footprint.taps[k];
            const double* y = basis.at(p.level, p.index);
            for (int j = 0; j < kMomentCount; ++j) r.a[j] += p.weight.a * y[j];
            if (c) {
                double cy = 0.0;
                for (int j = 0; j < kMomentCount; ++j) cy += c[j] * y[j];
                r.slope += p.weight * cy;
            }
        }
        weightSum += weight.a;
        records.push_back(r);
    };
    forEachTap<K>(texel, blocks, taps_, faceSize_, pyramidLevels_, visit);
    if (moments) std::fill(moments, moments + kMomentCount, 0.0);
    if (gradient) std::fill(gradient, gradient + static_cast<std::ptrdiff_t>(blockCount()) * B, 0.0);
    if (weightSum == 0.0) return;
    const double inverseSum = 1.0 / weightSum;
    if (moments)
        for (const TapMoments& r : records)
            for (int j = 0; j < kMomentCount; ++j) moments[j] += r.weight.a * r.a[j] * inverseSum;
    if (gradient) {
        // As in evaluateWith: d/d theta_i = (d(W_i A_i) - mbar dW_i) / S with mbar = sum_i W_i A_i / S.
        double mBar = 0.0;
        for (const TapMoments& r : records) mBar += r.weight.a * r.slope.a;
        mBar *= inverseSum;
        for (const TapMoments& r : records) {
            const J g = (r.weight * r.slope - r.weight * mBar) * inverseSum;
            for (int q = 0; q < B; ++q) gradient[r.block * B + q] += g.v[q];
        }
    }
}

template <int K>
ImpulseModel::Result ImpulseModel::evaluateWith(const double* const* blocks, const OutputTexel& texel, Workspace& ws, double* gradient,
                                                double* weightSumGradient) const {
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
    auto visit = [&](int block, const J& weight, const TrilinearFootprintT<J>& footprint) {
        for (int k = 0; k < footprint.count; ++k) top = std::max(top, footprint.taps[k].level);
        result.weightSum += weight.a;
        records.push_back({block, weight, footprint});
    };
    if (texel.lobe && gradient) throw std::logic_error("ImpulseModel::evaluate: a measured texel has no gradient");
    forEachTap<K>(texel, blocks, taps_, faceSize_, pyramidLevels_, visit);
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

    // The normalized weights on the footprints' pyramid texels, measured over the cells or the base
    // texels; with a gradient, the slope d e / d w pulled up to each of them.
    const double inverseSum = 1.0 / result.weightSum;
    ws.footprint.clear();
    for (const TapRecord& r : records)
        for (int k = 0; k < r.footprint.count; ++k) {
            const auto& p = r.footprint.taps[k];
            ws.footprint.push_back({p.level, static_cast<std::uint32_t>(p.index), r.weight.a * inverseSum * p.weight.a});
        }
    result.error = texel.cells.empty() ? measureBase(texel, ws, top, gradient != nullptr, &result.tail)
                                       : measureCells(texel, ws, gradient != nullptr, &result.tail);
    if (gradient) {
        // d e / d c_p = G_p (the pulled-up slope); c_p = sum_i W_i b_ip / S, so d e / d theta_i =
        // (d(W_i A_i) - Ebar dW_i) / S with A_i = sum_p G_p b_ip and Ebar = sum_i W_i A_i / S.
        std::vector<J> adjointOfTap(records.size());
        double eBar = 0.0;
        for (std::size_t n = 0, e = 0; n < records.size(); ++n) {
            J sum(0.0);
            for (int k = 0; k < records[n].footprint.count; ++k) sum += ws.footprintAdjoint[e++] * records[n].footprint.taps[k].weight;
            adjointOfTap[n] = sum;
            eBar += records[n].weight.a * sum.a;
        }
        eBar *= inverseSum;
        for (std::size_t n = 0; n < records.size(); ++n) {
            const J g = (records[n].weight * adjointOfTap[n] - records[n].weight * eBar) * inverseSum;
            for (int q = 0; q < B; ++q) gradient[records[n].block * B + q] += g.v[q];
        }
    }
    return result;
}

double ImpulseModel::measureBase(const OutputTexel& texel, Workspace& ws, int top, bool adjoint, double* tailError) const {
    // Where the taps reach little of the cube, on the touched texels only (listed per level), the L1
    // visiting the touched base texels; else dense passes over every texel.
    if (++ws.generation == 0) { // wrapped: clear the stamps once
        for (auto& s : ws.stamp) std::fill(s.begin(), s.end(), 0u);
        ws.generation = 1;
    }
    const std::uint32_t generation = ws.generation;
    auto touch = [&](int k, std::uint32_t index) {
        if (ws.stamp[k][index] != generation) {
            ws.stamp[k][index] = generation;
            ws.touched[k].push_back(index);
        }
    };
    for (int k = 0; k <= top; ++k) ws.touched[k].clear();
    for (const Workspace::FootprintWeight& f : ws.footprint) {
        touch(f.level, f.index);
        ws.weights[f.level][f.index] += f.weight;
    }
    // The distinct texels of level k that the taps read reach about 2 * 4^k base texels each (their
    // pushed-back supports overlap); where that is a large part of the cube, walking lists costs
    // more than the dense passes over every texel.
    double reach = 0.0;
    for (int k = 0; k <= top; ++k) reach += 2.0 * std::ldexp(static_cast<double>(ws.touched[k].size()), 2 * k);
    const bool dense = reach > kSparseReach * static_cast<double>(ws.weights[0].size());

    const TailTerm tail{texel.tail.empty() ? nullptr : texel.tail.data(), texel.kernelTail, adjoint ? tailWeight_ : 0.0};
    double error = 0.0;
    if (dense && texel.lobe) error = dense_.measure(operators_, ws.weights, top, *texel.lobe);
    else if (dense) error = dense_.measure(operators_, ws.weights, top, texel.kernel, tail, adjoint ? &ws.adjoint : nullptr, tailError);
    else {
        const std::vector<double>& w = ws.weights[0];
        std::vector<double>& slope = ws.adjoint[0];
        L1Measure measure{texel};
        for (int k = top; k > 0; --k) {
            const DownsampleOperator& op = operators_[k - 1];
            std::vector<double>& fine = ws.weights[k - 1];
            for (const std::uint32_t p : ws.touched[k]) {
                const double v = ws.weights[k][p];
                for (std::uint32_t n = op.rowStart[p]; n < op.rowStart[p + 1]; ++n) {
                    const TexelWeight& entry = op.entries[n];
                    touch(k - 1, entry.index);
                    fine[entry.index] += entry.weight * v;
                }
            }
        }
        double tailMass = 0.0;
        for (const std::uint32_t t : ws.touched[0]) {
            slope[t] = measure.visit(t, w[t]);
            if (tail.contains(t)) tailMass += w[t];
        }
        error = measure.value();
        *tailError = std::abs(tailMass - tail.kernelMass);
        if (tail.weight > 0.0) {
            const double step = tail.slope(tailMass);
            for (const std::uint32_t t : ws.touched[0])
                if (tail.contains(t)) slope[t] += step;
        }
        if (adjoint) // every row of a touched texel lies in the touched texels of the level below
            for (int k = 1; k <= top; ++k) {
                const DownsampleOperator& op = operators_[k - 1];
                const std::vector<double>& fine = ws.adjoint[k - 1];
                for (const std::uint32_t p : ws.touched[k]) {
                    double sum = 0.0;
                    for (std::uint32_t n = op.rowStart[p]; n < op.rowStart[p + 1]; ++n)
                        sum += op.entries[n].weight * fine[op.entries[n].index];
                    ws.adjoint[k][p] = sum;
                }
            }
        // Leave the weights zero for the next call (the dense passes do; the adjoint is only read where it was written).
        for (int k = 0; k <= top; ++k)
            for (const std::uint32_t p : ws.touched[k]) ws.weights[k][p] = 0.0;
    }
    if (adjoint) {
        ws.footprintAdjoint.clear();
        for (const Workspace::FootprintWeight& f : ws.footprint) ws.footprintAdjoint.push_back(ws.adjoint[f.level][f.index]);
    }
    return error;
}

std::int32_t ImpulseModel::routeOf(const OutputTexel& texel, int k, std::uint32_t p) const {
    CellRoutes& routes = texel.routes;
    const std::uint32_t key = CellRoutes::key(k, p);
    if (const std::int32_t id = routes.find(key); id >= 0) return id;
    // A texel's weight spreads over the cells of its 3x3 neighbourhood (across face edges as the
    // sampler steps) as its response spreads over their base texels (spread_), where all of them lie
    // in cells of its level or coarser; else (finer cells near it, or a cube corner) it is pushed
    // down to the level below.
    const int size = faceSize_ >> k, shift = log2Exact(size);
    const std::uint32_t mask = static_cast<std::uint32_t>(size) - 1u;
    // size is a power of two: shifts and masks, not divisions.
    const int face = static_cast<int>(p >> (2 * shift));
    const int i = static_cast<int>(p & mask), j = static_cast<int>((p >> shift) & mask);
    std::array<std::int32_t, 9> cells{};
    int count = 0;
    if (k == 0) {
        cells[0] = texel.cellTree.cellAt(0, face, i, j);
        count = 1;
    } else if (size >= 3) {
        // Inside the face the neighbours are plain steps; at its edge the sampler's steps.
        const bool inside = i > 0 && j > 0 && i < size - 1 && j < size - 1;
        for (; count < 9; ++count) {
            Texel neighbour{face, i + count % 3 - 1, j + count / 3 - 1};
            const bool exists = inside || texelNeighbour({face, i, j}, count % 3 - 1, count / 3 - 1, size, neighbour);
            cells[static_cast<std::size_t>(count)] = exists ? texel.cellTree.cellAt(k, neighbour.face, neighbour.i, neighbour.j) : -1;
            if (cells[static_cast<std::size_t>(count)] < 0) {
                count = 0;
                break;
            }
        }
    }
    const std::int32_t id = routes.add(key);
    if (count > 0) {
        routes.nodes[static_cast<std::size_t>(id)].begin = static_cast<std::uint32_t>(routes.cells.size());
        routes.nodes[static_cast<std::size_t>(id)].count = static_cast<std::uint8_t>(count);
        routes.cells.insert(routes.cells.end(), cells.begin(), cells.begin() + count);
        return id;
    }
    // The children first (each made where new), then their place in the lists.
    const DownsampleOperator& op = operators_[k - 1];
    std::vector<std::int32_t> children;
    for (std::uint32_t n = op.rowStart[p]; n < op.rowStart[p + 1]; ++n) children.push_back(routeOf(texel, k - 1, op.entries[n].index));
    CellRoutes::Node& node = routes.nodes[static_cast<std::size_t>(id)];
    node.begin = static_cast<std::uint32_t>(routes.children.size());
    node.count = static_cast<std::uint8_t>(children.size());
    node.pushed = true;
    for (std::uint32_t n = op.rowStart[p]; n < op.rowStart[p + 1]; ++n)
        routes.children.push_back({children[n - op.rowStart[p]], static_cast<float>(op.entries[n].weight)});
    return id;
}

double ImpulseModel::measureCells(const OutputTexel& texel, Workspace& ws, bool adjoint, double* tailError) const {
    if (++ws.generation == 0) { // wrapped: clear the stamps once
        std::fill(ws.nodeStamp.begin(), ws.nodeStamp.end(), 0u);
        ws.generation = 1;
    }
    const std::uint32_t generation = ws.generation;
    const CellRoutes& routes = texel.routes;
    auto touch = [&](std::int32_t id, double weight) {
        const std::size_t n = static_cast<std::size_t>(id);
        if (n >= ws.nodeStamp.size()) {
            ws.nodeStamp.resize(routes.nodes.size(), 0u);
            ws.nodeWeight.resize(routes.nodes.size());
            ws.nodeAdjoint.resize(routes.nodes.size());
        }
        if (ws.nodeStamp[n] != generation) {
            ws.nodeStamp[n] = generation;
            ws.nodeWeight[n] = 0.0;
            ws.nodeTouched[routes.nodes[n].key >> 28].push_back(id);
        }
        ws.nodeWeight[n] += weight;
    };
    for (auto& touched : ws.nodeTouched) touched.clear();
    ws.footprintNodes.clear();
    int top = 0;
    for (const Workspace::FootprintWeight& f : ws.footprint) {
        const std::int32_t id = routeOf(texel, f.level, f.index);
        ws.footprintNodes.push_back(id);
        touch(id, f.weight);
        top = std::max(top, f.level);
    }
    // Top down: each texel's weight onto its cells, or its children's weights.
    const std::vector<LobeCell>& cells = texel.cells;
    ws.cellMass.assign(cells.size(), 0.0);
    for (int k = top; k >= 0; --k) {
        const std::array<double, 9>& stencil = spread_[static_cast<std::size_t>(k)];
        // The list grows while it is walked only below level k, so the indices stay valid.
        for (std::size_t t = 0; t < ws.nodeTouched[static_cast<std::size_t>(k)].size(); ++t) {
            const std::int32_t id = ws.nodeTouched[static_cast<std::size_t>(k)][t];
            const CellRoutes::Node& node = routes.nodes[static_cast<std::size_t>(id)];
            const double v = ws.nodeWeight[static_cast<std::size_t>(id)];
            if (node.pushed)
                for (std::uint32_t n = node.begin; n < node.begin + node.count; ++n)
                    touch(routes.children[n].node, static_cast<double>(routes.children[n].weight) * v);
            else if (node.count == 1) ws.cellMass[static_cast<std::size_t>(routes.cells[node.begin])] += v;
            else
                for (int n = 0; n < 9; ++n)
                    ws.cellMass[static_cast<std::size_t>(routes.cells[node.begin + static_cast<std::uint32_t>(n)])] +=
                        stencil[static_cast<std::size_t>(n)] * v;
        }
    }
    double error = 0.0, tailMass = 0.0;
    ws.cellSlope.resize(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
        const double d = ws.cellMass[c] - static_cast<double>(cells[c].kernel);
        error += std::abs(d);
        ws.cellSlope[c] = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
        if (cells[c].tail) tailMass += ws.cellMass[c];
    }
    *tailError = std::abs(tailMass - texel.kernelTail);
    if (!adjoint) return error;
    const TailTerm term{nullptr, texel.kernelTail, tailWeight_};
    const double step = term.slope(tailMass);
    for (std::size_t c = 0; c < cells.size(); ++c)
        if (cells[c].tail) ws.cellSlope[c] += step;
    // Bottom up: a texel's slope is its cells' (the transpose of its spread), or its children's.
    for (int k = 0; k <= top; ++k) {
        const std::array<double, 9>& stencil = spread_[static_cast<std::size_t>(k)];
        for (const std::int32_t id : ws.nodeTouched[static_cast<std::size_t>(k)]) {
            const CellRoutes::Node& node = routes.nodes[static_cast<std::size_t>(id)];
            double sum = 0.0;
            if (node.pushed)
                for (std::uint32_t n = node.begin; n < node.begin + node.count; ++n)
                    sum +=
                        static_cast<double>(routes.children[n].weight) * ws.nodeAdjoint[static_cast<std::size_t>(routes.children[n].node)];
            else if (node.count == 1) sum = ws.cellSlope[static_cast<std::size_t>(routes.cells[node.begin])];
            else
                for (int n = 0; n < 9; ++n)
                    sum += stencil[static_cast<std::size_t>(n)] *
                           ws.cellSlope[static_cast<std::size_t>(routes.cells[node.begin + static_cast<std::uint32_t>(n)])];
            ws.nodeAdjoint[static_cast<std::size_t>(id)] = sum;
        }
    }
    ws.footprintAdjoint.clear();
    for (const std::int32_t id : ws.footprintNodes) ws.footprintAdjoint.push_back(ws.nodeAdjoint[static_cast<std::size_t>(id)]);
    return error;
}

std::vector<const double*> levelBlocks(const TapTable& table, int level) {
    std::vector<const double*> blocks;
    for (int a = 0; a < kFrameCount; ++a)
        for (int t = 0; t < table.taps; ++t) blocks.push_back(&table.levels[level].coefficients[table.offset(a, t)]);
    return blocks;
}

} // namespace probefit
