// Pass 2 with a tap table (shaders/table_filter.comp): the table's fit with the settings, its
// upload in the published layout (then the tap groups each level uses), and one dispatch per output
// level computed (copy_level_pass.cpp does the levels with alpha = 0).
#include <cstdint>

#include <fmt/format.h>
#include <table_filter.spv.h>

#include "filter_impl.h"
#include "probe/error.h"
#include "probe/table_io.h"

namespace probe::gpu {

namespace {

struct TableConstants {
    int32_t baseSize;
    int32_t pyramidLevels;
    int32_t level;
    int32_t taps;
    uint32_t firstTexel;
    uint32_t endTexel;
    uint32_t usageFirst;
};

} // namespace

std::span<const uint32_t> tableSpirv() { return kTableFilterSpv; }

void checkTableFits(const TapTable& table, const FilterSettings& s) {
    validateTable(table, "tap table");
    std::vector<std::string> reasons;
    if (table.baseSize != s.faceSize) reasons.push_back(fmt::format("it is for base size {}, not {}", table.baseSize, s.faceSize));
    if (table.levelCount != s.levelCount) reasons.push_back(fmt::format("it has {} levels, not {}", table.levelCount, s.levelCount));
    if (table.mapping != s.mapping)
        reasons.push_back(fmt::format("it is for the {} roughness mapping, not {}", roughnessMappingName(table.mapping),
                                      roughnessMappingName(s.mapping)));
    if (!(table.pyramid == s.pyramid))
        reasons.push_back(fmt::format("it was fitted over the {} {} pyramid, not {} {}", pyramidKindName(table.pyramid.kind),
                                      pyramidWeightingName(table.pyramid.weighting), pyramidKindName(s.pyramid.kind),
                                      pyramidWeightingName(s.pyramid.weighting)));
    if (!reasons.empty()) {
        std::string text;
        for (const std::string& r : reasons) text += (text.empty() ? "" : "; ") + r;
        throw ProbeError(fmt::format("tap table does not fit: {}", text));
    }
}

std::vector<float> tableBufferData(const TapTable& table) {
    std::vector<float> data;
    for (int m = 0; m < table.levelCount; ++m) {
        const std::vector<float> level = publishedLevelLayout(table, m);
        data.insert(data.end(), level.begin(), level.end());
    }
    // Then per level the tap groups of four in use, so that padded levels stop early.
    for (int m = 0; m < table.levelCount; ++m)
        data.insert(data.end(), {static_cast<float>((tapsInUse(table, m) + 3) / 4), 0.0f, 0.0f, 0.0f});
    return data;
}

uint32_t tableUsageFirst(const TapTable& table) { return static_cast<uint32_t>(table.levelCount * table.coefficientsPerLevel() / 4); }

void recordTableLevel(Filter::Impl& impl, VkCommandBuffer commandBuffer, int m) {
    const FilterSettings& s = impl.settings;
    const TableConstants constants{
        s.faceSize, impl.pyramidLevels, m, impl.tableTaps, impl.outputOffsets[m], impl.outputOffsets[m + 1], impl.tableUsageFirst};
    dispatchPass(impl, commandBuffer, *impl.pass2, "table", m, constants, groupsFor(impl.outputOffsets[m + 1] - impl.outputOffsets[m]));
}

} // namespace probe::gpu
