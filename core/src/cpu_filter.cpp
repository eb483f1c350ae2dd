#include "probe/cpu_filter.h"

#include "probe/limits.h"
#include "probe/paraboloid.h"
#include "probe/range_scale.h"
#include "probe/reference.h"
#include "probe/table_filter.h"

namespace probe {

TapGenerator methodTapGenerator(const FilterMethod& method, int faceSize, int levelCount, const RoughnessMapping& mapping) {
    switch (method.kind) {
    case MethodKind::table: return tableMethodTapGenerator(*method.table);
    case MethodKind::fis: return fisTapGenerator(faceSize, levelCount, mapping, method.fis, method.lobe);
    case MethodKind::reference: break;
    }
    return {};
}

CubeLevels filterOnCpu(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const FilterMethod& method) {
    validateMethod(method, source.size, levelCount, mapping);
    if (method.kind == MethodKind::reference) return referenceFilter(source, levelCount, mapping, {}, method.lobe);
    const int shift = rangeShift(source);
    CubeLevels levels = method.kind == MethodKind::fis && method.fis.map == FisMap::paraboloid
                            ? paraboloidFilter(shifted(source, -shift), levelCount, mapping, method.fis)
                            : filterWithTaps(buildPyramid(shifted(source, -shift), method.pyramid()), levelCount,
                                             methodTapGenerator(method, source.size, levelCount, mapping));
    shiftLevels(levels, shift);
    return levels;
}

CubeLevels fisFilter(const CubeImage& source, int levelCount, const RoughnessMapping& mapping, const FisSettings& settings) {
    validateSizeAndLevels(source.size, levelCount);
    return filterWithTaps(buildPyramid(source, settings.pyramid), levelCount, fisTapGenerator(source.size, levelCount, mapping, settings));
}

std::vector<double> fisImpulseResponse(const std::vector<DownsampleOperator>& operators, int faceSize, int levelCount,
                                       const RoughnessMapping& mapping, const FisSettings& settings, int level, const Texel& texel) {
    return impulseWithTaps(operators, faceSize, level, texel, fisTapGenerator(faceSize, levelCount, mapping, settings));
}

} // namespace probe
