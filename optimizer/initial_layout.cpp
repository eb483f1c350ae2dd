#include "initial_layout.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "probe/fis.h"

namespace probefit {

using namespace probe;

double lobeAngle(double alpha) { return std::min(2.0 * std::atan(alpha), 0.9); }

namespace {

void setConstant(TapTable& table, int level, int frame, int tap, int parameter, double value) {
    double* c = &table.levels[level].coefficients[table.offset(frame, tap, parameter)];
    c[0] = value;
    for (int k = 1; k < coefficientCount(table.form); ++k) c[k] = 0.0;
}

} // namespace

void lobeLayout(TapTable& table, int level, double alpha) {
    // Charlie's lobe is a ring about R, not a peak: its samples lie on it.
    if (table.lobe != Lobe::ggx) return importanceLayout(table, level, alpha, 0.0);
    const double angle = lobeAngle(alpha);
    const double texelAngle = 2.0 / table.faceSize; // at a face centre; the model adds the cube's distortion
    const int ring = table.taps - 1;
    const int inner = table.taps < 8 ? 0 : ring / 2, outer = ring - inner;
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < table.taps; ++t) {
            double radius = 0.0, phi = 0.0, spacing = 0.7 * angle, weight = 1.0;
            if (t > 0 && t <= inner) {
                radius = 0.5 * angle;
                phi = 2.0 * std::numbers::pi * (t - 1) / inner;
                spacing = 2.0 * std::numbers::pi * std::sin(radius) / inner;
            } else if (t > inner) {
                radius = (inner > 0 ? 1.1 : 0.8) * angle;
                phi = 2.0 * std::numbers::pi * (t - inner - 0.5) / outer;
                spacing = 2.0 * std::numbers::pi * std::sin(radius) / outer;
                weight = inner > 0 ? 0.6 : 1.0;
            }
            setConstant(table, level, frame, t, tapDirX, std::tan(radius) * std::cos(phi));
            setConstant(table, level, frame, t, tapDirY, std::tan(radius) * std::sin(phi));
            setConstant(table, level, frame, t, tapDirZ, 1.0);
            setConstant(table, level, frame, t, tapLevel, std::log2(std::max(spacing, 1e-6) / texelAngle));
            setConstant(table, level, frame, t, tapWeight, weight);
        }
}

void importanceLayout(TapTable& table, int level, double alpha, double rotation) {
    const std::vector<Tap> samples = fisSamples(alpha, table.faceSize, table.taps, 0.0, table.lobe);
    const double c = std::cos(rotation), s = std::sin(rotation);
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < table.taps; ++t) {
            const bool kept = t < static_cast<int>(samples.size());
            const glm::dvec3 d = kept ? samples[t].direction : glm::dvec3(0.0, 0.0, 1.0);
            setConstant(table, level, frame, t, tapDirX, c * d.x - s * d.y);
            setConstant(table, level, frame, t, tapDirY, s * d.x + c * d.y);
            setConstant(table, level, frame, t, tapDirZ, d.z);
            setConstant(table, level, frame, t, tapLevel, kept ? samples[t].level : 0.0);
            setConstant(table, level, frame, t, tapWeight, kept ? samples[t].weight : 0.0);
        }
}

void hopLayout(TapTable& table, int level, double alpha, unsigned seed) {
    std::mt19937 rng(seed);
    // In [-1, 1), from the generator's bits alone, so that every standard library gives the same hop.
    auto uniform = [&rng] { return 2.0 * static_cast<double>(rng()) / 4294967296.0 - 1.0; };
    const double spread = 0.25 * std::tan(lobeAngle(alpha));
    double* c = table.levels[level].coefficients.data();
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < table.taps; ++t) {
            const double z = std::abs(c[table.offset(frame, t, tapDirZ)]);
            c[table.offset(frame, t, tapDirX)] += spread * z * uniform();
            c[table.offset(frame, t, tapDirY)] += spread * z * uniform();
            c[table.offset(frame, t, tapLevel)] += 0.5 * uniform();
            c[table.offset(frame, t, tapWeight)] *= 1.0 + 0.2 * uniform();
        }
}

void warmStartFromLevel(TapTable& table, int level, int from) { startFromBank(table, level, table, from); }

void startFromBank(TapTable& table, int level, const TapTable& bank, int from) {
    const double a = lobeAngle(tableLevelAlpha(table, level)), b = lobeAngle(tableLevelAlpha(bank, from));
    const double widen = std::tan(a) / std::tan(b);
    const double levelShift = std::log2(a / b) + std::log2(static_cast<double>(table.faceSize) / bank.faceSize);
    const int k = coefficientCount(table.form), kBank = coefficientCount(bank.form);
    const std::vector<double> source = bank.levels[from].coefficients; // bank may be table itself
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < table.taps; ++t) {
            const double* b0 = &source[bank.offset(frame, t)];
            double* c = &table.levels[level].coefficients[table.offset(frame, t)];
            for (int p = 0; p < kTapParameterCount; ++p)
                for (int q = 0; q < k; ++q) c[p * k + q] = q < kBank ? b0[p * kBank + q] : 0.0;
            for (int q = 0; q < k; ++q) {
                c[tapDirX * k + q] *= widen;
                c[tapDirY * k + q] *= widen;
            }
            c[tapLevel * k] += levelShift;
        }
}

void startFromTable(TapTable& table, int level, const TapTable& init, double spread) {
    const int k = coefficientCount(table.form), kInit = coefficientCount(init.form);
    const bool split = init.taps * 2 == table.taps;
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int t = 0; t < table.taps; ++t) {
            const int source = split ? t % init.taps : t;
            const double* from = &init.levels[level].coefficients[init.offset(frame, source)];
            double* to = &table.levels[level].coefficients[table.offset(frame, t)];
            for (int p = 0; p < kTapParameterCount; ++p)
                for (int q = 0; q < k; ++q) to[p * k + q] = q < kInit ? from[p * kInit + q] : 0.0;
            if (!split) continue;
            const bool second = t >= init.taps;
            if (spread <= 0.0) {
                // Same place, weights 0.6 : 0.4 of the tap's own: the filter is exactly init's.
                for (int q = 0; q < k; ++q) to[tapWeight * k + q] *= second ? 0.4 : 0.6;
                continue;
            }
            // Half the weight each, moved apart by +-spread texels of the tap's own pyramid level, across
            // the frame's x or y (alternating), relative to the length of the tap's direction vector.
            for (int q = 0; q < k; ++q) to[tapWeight * k + q] *= 0.5;
            const double length = std::hypot(to[tapDirX * k], to[tapDirY * k], to[tapDirZ * k]);
            const double texelAngle = 2.0 / table.faceSize * std::exp2(std::clamp(to[tapLevel * k], 0.0, 12.0));
            to[(source % 2 == 0 ? tapDirX : tapDirY) * k] += (second ? -1.0 : 1.0) * spread * texelAngle * length;
        }
}

void oneFrameLayout(TapTable& table, int level, int frame) {
    std::vector<double>& c = table.levels[level].coefficients;
    const std::ptrdiff_t frameSize = static_cast<std::ptrdiff_t>(c.size()) / kFrameCount;
    const auto from = c.begin() + frame * frameSize;
    for (int f = 0; f < kFrameCount; ++f)
        if (f != frame) std::copy(from, from + frameSize, c.begin() + f * frameSize);
}

} // namespace probefit
