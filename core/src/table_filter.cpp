#include "probe/table_filter.h"

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/fis.h"

namespace probe {

void tableTaps(const TapTable& table, int level, int used, const glm::dvec3& cubeVector, std::vector<Tap>& taps) {
    taps.clear();
    const std::vector<double>& coefficients = table.levels[level].coefficients;
    for (int axis = 0; axis < kFrameCount; ++axis) {
        const FrameSetup frame = frameSetup(cubeVector, axis);
        if (frame.weight <= 0.0) continue;
        for (int t = 0; t < used; ++t) {
            const TapSample<double> s = evaluateTap(frame, &coefficients[table.offset(axis, t)], coefficientCount(table.form));
            taps.push_back({{s.direction[0], s.direction[1], s.direction[2]}, s.level, s.weight});
        }
    }
}

TapGenerator tableTapGenerator(const TapTable& table) {
    // Counted once here, not per texel.
    std::vector<int> used;
    for (int m = 0; m < table.levelCount; ++m) used.push_back(tapsInUse(table, m));
    return [&table, used](int level, const Texel& texel, std::vector<Tap>& taps) {
        if (tableLevelAlpha(table, level) <= 0.0) return false;
        tableTaps(table, level, used[level], texelCubePoint(texel, table.faceSize >> level), taps);
        return true;
    };
}

std::vector<std::vector<Tap>> handOffSamples(const TapTable& table) {
    std::vector<std::vector<Tap>> samples(static_cast<std::size_t>(table.levelCount));
    for (int m = 0; m < table.levelCount; ++m)
        if (table.levels[m].fisSamples > 0)
            samples[m] = fisSamples(tableLevelAlpha(table, m), table.faceSize, table.levels[m].fisSamples, 0.0, table.lobe);
    return samples;
}

TapGenerator tableMethodTapGenerator(const TapTable& table) {
    return
        [&table, handedOff = handOffSamples(table), taps = tableTapGenerator(table)](int level, const Texel& texel, std::vector<Tap>& out) {
            if (handedOff[level].empty()) return taps(level, texel, out);
            fisTaps(texelDirection(texel, table.faceSize >> level), handedOff[level], out);
            return true;
        };
}

CubeLevels tableFilter(const CubeLevels& pyramid, const TapTable& table) {
    validateTable(table, "tap table");
    if (pyramid.empty() || pyramid[0].size != table.faceSize)
        throw ProbeError(
            fmt::format("tap table for face size {} applied to a probe of size {}", table.faceSize, pyramid.empty() ? 0 : pyramid[0].size));
    return filterWithTaps(pyramid, table.levelCount, tableTapGenerator(table));
}

CubeLevels tableFilter(const CubeImage& source, const TapTable& table) { return tableFilter(buildPyramid(source, table.pyramid), table); }

std::vector<double> tableImpulseResponse(const TapTable& table, const std::vector<DownsampleOperator>& operators, int level,
                                         const Texel& texel) {
    return impulseWithTaps(operators, table.faceSize, level, texel, tableTapGenerator(table));
}

} // namespace probe
