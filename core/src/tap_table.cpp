#include "probe/tap_table.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <thread>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"

namespace probe {

namespace {

// A weight sum below this fraction of the weights' magnitude is cancellation, not a filter.
constexpr double kMinWeightSumRatio = 1e-3;
// A tap direction shorter than this fraction of its coefficients' size has no direction: the GPU's
// float rounding, a few 1e-7 of it, could turn it anywhere or cancel it to zero.
constexpr double kMinDirectionRatio = 1e-6;

// The shortest the direction c0 + a c1 + b c2 gets over the polynomial domain, (a, b) = (theta^2,
// phi^2) in [0, 1]^2 (frame.h): its squared length is a convex quadratic in (a, b), least at its
// stationary point when that lies inside the square, else on one of the square's edges.
double shortestDirection(const glm::dvec3& c0, const glm::dvec3& c1, const glm::dvec3& c2) {
    // Along the edge from q (t = 0) to q + e (t = 1).
    const auto edge = [](const glm::dvec3& q, const glm::dvec3& e) {
        const double ee = glm::dot(e, e);
        const double t = ee > 0.0 ? std::clamp(-glm::dot(q, e) / ee, 0.0, 1.0) : 0.0;
        return glm::length(q + t * e);
    };
    double shortest = std::min({edge(c0, c1), edge(c0 + c2, c1), edge(c0, c2), edge(c0 + c1, c2)});
    const double g11 = glm::dot(c1, c1), g12 = glm::dot(c1, c2), g22 = glm::dot(c2, c2);
    const double det = g11 * g22 - g12 * g12;
    if (det > 0.0) {
        const double r1 = -glm::dot(c0, c1), r2 = -glm::dot(c0, c2);
        const double a = (r1 * g22 - r2 * g12) / det, b = (g11 * r2 - g12 * r1) / det;
        if (a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0) shortest = std::min(shortest, glm::length(c0 + a * c1 + b * c2));
    }
    return shortest;
}

// Tap `tap`'s direction coefficients in `frame` of `level`: their size (the sum of their terms'
// lengths), and whether the direction stays above kMinDirectionRatio of it over the whole domain,
// which spares the texels the check. (A fitted table's direction may pass through zero between
// texel centres, where no texel reads it: those taps are checked texel by texel.)
struct DirectionBound {
    double scale = 0.0;
    double shortest2 = 0.0; // (kMinDirectionRatio scale)^2, what a texel's squared length must pass
    bool everywhere = false;
};

DirectionBound directionBound(const TapTable& table, int level, int frame, int tap) {
    std::array<glm::dvec3, 3> terms{};
    for (int k = 0; k < coefficientCount(table.form); ++k)
        for (int axis = 0; axis < 3; ++axis)
            terms[k][axis] = table.levels[level].coefficients[table.offset(frame, tap, tapDirX + axis) + k];
    const double scale = glm::length(terms[0]) + glm::length(terms[1]) + glm::length(terms[2]);
    const double shortest = kMinDirectionRatio * scale;
    return {scale, shortest * shortest, shortestDirection(terms[0], terms[1], terms[2]) > shortest};
}

// What is wrong at output texel t of level m, in the frames that count there, or "": the weights of
// the first `used` taps (frame weights included, as tableTaps gives them) must sum to a positive
// fraction of their magnitude, and each of the first `read` taps (the GPU evaluates taps in groups
// of four, so a level's padding up to its group too) needs a direction that float rounding cannot
// cancel or turn.
std::string texelProblem(const TapTable& table, int m, int used, int read, const std::vector<DirectionBound>& bounds, const Texel& t) {
    const int n = coefficientCount(table.form);
    const std::vector<double>& c = table.levels[m].coefficients;
    const glm::dvec3 d = texelCubePoint(t, table.faceSize >> m);
    std::array<FrameSetup, kFrameCount> frames;
    double sum = 0.0, magnitude = 0.0;
    for (int frame = 0; frame < kFrameCount; ++frame) {
        frames[frame] = frameSetup(d, frame);
        if (frames[frame].weight <= 0.0) continue;
        for (int tap = 0; tap < used; ++tap) {
            const double w = tapPolynomial(&c[table.offset(frame, tap, tapWeight)], n, frames[frame]) * frames[frame].weight;
            sum += w;
            magnitude += std::abs(w);
        }
    }
    if (!(sum > kMinWeightSumRatio * magnitude))
        return fmt::format("level {} at texel (face {}, {}, {}): the tap weights sum to {:.3g} (of magnitude {:.3g}); the filter needs "
                           "a positive sum",
                           m, t.face, t.i, t.j, sum, magnitude);
    for (int frame = 0; frame < kFrameCount; ++frame) {
        const FrameSetup& f = frames[frame];
        if (f.weight <= 0.0) continue;
        for (int tap = 0; tap < read; ++tap) {
            const DirectionBound& bound = bounds[std::size_t(frame * read + tap)];
            if (bound.everywhere) continue;
            const glm::dvec3 p(tapPolynomial(&c[table.offset(frame, tap, tapDirX)], n, f),
                               tapPolynomial(&c[table.offset(frame, tap, tapDirY)], n, f),
                               tapPolynomial(&c[table.offset(frame, tap, tapDirZ)], n, f));
            if (!(glm::dot(p, p) > bound.shortest2))
                return fmt::format("level {} frame {} tap {} has no direction at texel (face {}, {}, {}) (its direction coefficients {})",
                                   m, frame, tap, t.face, t.i, t.j, bound.scale == 0.0 ? "are all 0" : "cancel there");
        }
    }
    return {};
}

// Every output texel of level m (texelProblem), rows in parallel on every core (threads of the
// standard library: the runtime, which checks tables, links no OpenMP); the first problem in texel
// order is the one reported, whatever the threads' order.
void checkTexels(const TapTable& table, int m, int used, int read, std::string_view what) {
    std::vector<DirectionBound> bounds;
    for (int frame = 0; frame < kFrameCount; ++frame)
        for (int tap = 0; tap < read; ++tap) bounds.push_back(directionBound(table, m, frame, tap));
    const int size = table.faceSize >> m, rows = kFaceCount * size;
    std::vector<std::string> problems(static_cast<std::size_t>(rows));
    std::atomic<int> next{0};
    const auto work = [&] {
        for (int row = next++; row < rows; row = next++)
            for (int i = 0; i < size && problems[row].empty(); ++i)
                problems[row] = texelProblem(table, m, used, read, bounds, {row / size, i, row % size});
    };
    const int threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, std::max(1, rows / 8));
    std::vector<std::jthread> helpers;
    for (int t = 1; t < threads; ++t) helpers.emplace_back(work);
    work();
    helpers.clear(); // joins
    for (const std::string& problem : problems)
        if (!problem.empty()) throw ProbeError(fmt::format("{}: {}", what, problem));
}

} // namespace

TableForm parseTableForm(std::string_view name) {
    if (name == "quad") return TableForm::quadratic;
    if (name == "const") return TableForm::constant;
    throw ProbeError(fmt::format("unknown table form '{}' (expected const or quad)", name));
}

std::string_view tableFormName(TableForm form) { return form == TableForm::quadratic ? "quad" : "const"; }

TapTable emptyTable(int faceSize, int levelCount, int taps, TableForm form, const RoughnessMapping& mapping, PyramidSettings pyramid) {
    TapTable table;
    table.faceSize = faceSize;
    table.levelCount = levelCount;
    table.taps = taps;
    table.form = form;
    table.mapping = mapping;
    table.pyramid = pyramid;
    validateSizeAndLevels(faceSize, levelCount);
    validateMappingLevels(mapping, levelCount);
    if (taps < 4 || taps % 4 != 0 || taps > kMaxTaps)
        throw ProbeError(fmt::format("tap count {} is not a multiple of 4 from 4 to {}", taps, kMaxTaps));
    table.levels.resize(static_cast<std::size_t>(levelCount));
    for (TableLevel& level : table.levels) {
        level.coefficients.assign(static_cast<std::size_t>(table.coefficientsPerLevel()), 0.0);
        level.stratified.mean = -1.0;
        level.all.mean = -1.0;
    }
    return table;
}

void validateTable(const TapTable& table, std::string_view what) {
    try {
        validateSizeAndLevels(table.faceSize, table.levelCount);
        validateMappingLevels(table.mapping, table.levelCount);
    } catch (const ProbeError& e) {
        throw ProbeError(fmt::format("{}: {}", what, e.what()));
    }
    if (table.taps < 4 || table.taps % 4 != 0 || table.taps > kMaxTaps)
        throw ProbeError(fmt::format("{}: tap count {} is not a multiple of 4 from 4 to {}", what, table.taps, kMaxTaps));
    if (table.levels.size() != static_cast<std::size_t>(table.levelCount))
        throw ProbeError(fmt::format("{}: {} levels of coefficients for a level count of {}", what, table.levels.size(), table.levelCount));
    for (std::size_t m = 0; m < table.levels.size(); ++m)
        if (table.levels[m].coefficients.size() != static_cast<std::size_t>(table.coefficientsPerLevel()))
            throw ProbeError(fmt::format("{}: level {} has {} coefficients, expected {} ({} taps x 3 frames x 5 x {})", what, m,
                                         table.levels[m].coefficients.size(), table.coefficientsPerLevel(), table.taps,
                                         coefficientCount(table.form)));
    for (int m = 0; m < table.levelCount; ++m) {
        const int samples = table.levels[m].fisSamples;
        if (samples == 0) continue;
        if (tableLevelAlpha(table, m) <= 0.0)
            throw ProbeError(fmt::format("{}: level {} is a copy of the source (alpha 0) and cannot be handed to FIS", what, m));
        if (samples < 1 || samples > kMaxSamples)
            throw ProbeError(
                fmt::format("{}: level {} is handed to FIS with {} samples: must be 0 or 1 to {}", what, m, samples, kMaxSamples));
    }
}

void validateTableValues(const TapTable& table, std::string_view what) {
    validateTable(table, what);
    for (int m = 0; m < table.levelCount; ++m)
        for (std::size_t k = 0; k < table.levels[m].coefficients.size(); ++k) {
            const double c = table.levels[m].coefficients[k];
            if (!(std::abs(c) <= kMaxTableCoefficient))
                throw ProbeError(
                    fmt::format("{}: level {} coefficient {} is {}, not a finite number within +-{}", what, m, k, c, kMaxTableCoefficient));
        }
    for (int m = 0; m < table.levelCount; ++m) {
        if (tableLevelAlpha(table, m) <= 0.0) continue; // a copy: the taps are not used
        const int used = tapsInUse(table, m);
        checkTexels(table, m, used, std::min(table.taps, (std::max(used, 1) + 3) / 4 * 4), what);
    }
}

int tapsInUse(const TapTable& table, int level) {
    const std::vector<double>& c = table.levels[level].coefficients;
    for (int tap = table.taps; tap > 0; --tap)
        for (int frame = 0; frame < kFrameCount; ++frame)
            for (int k = 0; k < coefficientCount(table.form); ++k)
                if (c[table.offset(frame, tap - 1, tapWeight) + k] != 0.0) return tap;
    return 0;
}

std::vector<float> publishedLevelLayout(const TapTable& table, int level) {
    const int k = coefficientCount(table.form);
    const std::vector<double>& c = table.levels[level].coefficients;
    std::vector<float> out;
    out.reserve(c.size());
    for (int p = 0; p < kTapParameterCount; ++p)
        for (int coefficient = 0; coefficient < k; ++coefficient)
            for (int frame = 0; frame < kFrameCount; ++frame)
                for (int tap = 0; tap < table.taps; ++tap) out.push_back(static_cast<float>(c[table.offset(frame, tap, p) + coefficient]));
    return out;
}

void setPublishedLayout(TapTable& table, const std::vector<double>& values) {
    const std::size_t perLevel = static_cast<std::size_t>(table.coefficientsPerLevel());
    if (values.size() != perLevel * table.levels.size())
        throw ProbeError(
            fmt::format("{} coefficients in the published layout, expected {}", values.size(), perLevel * table.levels.size()));
    const int k = coefficientCount(table.form);
    std::size_t n = 0;
    for (TableLevel& level : table.levels)
        for (int p = 0; p < kTapParameterCount; ++p)
            for (int coefficient = 0; coefficient < k; ++coefficient)
                for (int frame = 0; frame < kFrameCount; ++frame)
                    for (int tap = 0; tap < table.taps; ++tap) level.coefficients[table.offset(frame, tap, p) + coefficient] = values[n++];
}

} // namespace probe
