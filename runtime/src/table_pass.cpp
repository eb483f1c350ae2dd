// Pass 2 with a tap table (shaders/table_filter.comp): its upload in the published layout (then the
// tap groups each level uses), and one dispatch per group of output levels (FilterPlan::levelGroups;
// copy_level_pass.cpp does the levels with alpha = 0).
#include <array>
#include <cstdint>

#include <table_filter_exact_b10g11r11.spv.h>
#include <table_filter_exact_rgba16f.spv.h>
#include <table_filter_exact_rgba32f.spv.h>
#include <table_filter_hardware_b10g11r11.spv.h>
#include <table_filter_hardware_batch_b10g11r11.spv.h>
#include <table_filter_hardware_batch_rgba16f.spv.h>
#include <table_filter_hardware_batch_rgba32f.spv.h>
#include <table_filter_hardware_rgba16f.spv.h>
#include <table_filter_hardware_rgba32f.spv.h>
#include <table_filter_wide_exact_b10g11r11.spv.h>
#include <table_filter_wide_exact_rgba16f.spv.h>
#include <table_filter_wide_exact_rgba32f.spv.h>
#include <table_filter_wide_hardware_b10g11r11.spv.h>
#include <table_filter_wide_hardware_batch_b10g11r11.spv.h>
#include <table_filter_wide_hardware_batch_rgba16f.spv.h>
#include <table_filter_wide_hardware_batch_rgba32f.spv.h>
#include <table_filter_wide_hardware_rgba16f.spv.h>
#include <table_filter_wide_hardware_rgba32f.spv.h>

#include "filter_passes.h"
#include "probe/tap_table.h"

namespace probe::gpu {

namespace {

struct TableConstants {
    int32_t faceSize;
    int32_t pyramidLevels;
    int32_t firstLevel;
    uint32_t usageFirst;
    std::array<uint32_t, kWideWrittenMipCount> groupEnd; // shaders/table_filter.comp's PROBE_MAX_GROUP_LEVELS
};

} // namespace

TablePass::TablePass(const PassContext& context) : context_(context), usageFirst_(tableUsageFirst(*context.settings.method.table)) {
    const std::span<const uint32_t> spirv =
        context.plan.sampling == Sampling::hardware
            ? context.batchVariant(
                  context.groupVariant(
                      {kTableFilterHardwareRgba32fSpv, kTableFilterHardwareRgba16fSpv, kTableFilterHardwareB10g11r11Spv},
                      {kTableFilterWideHardwareRgba32fSpv, kTableFilterWideHardwareRgba16fSpv, kTableFilterWideHardwareB10g11r11Spv}),
                  context.groupVariant(
                      {kTableFilterHardwareBatchRgba32fSpv, kTableFilterHardwareBatchRgba16fSpv, kTableFilterHardwareBatchB10g11r11Spv},
                      {kTableFilterWideHardwareBatchRgba32fSpv, kTableFilterWideHardwareBatchRgba16fSpv,
                       kTableFilterWideHardwareBatchB10g11r11Spv}))
            : context.groupVariant({kTableFilterExactRgba32fSpv, kTableFilterExactRgba16fSpv, kTableFilterExactB10g11r11Spv},
                                   {kTableFilterWideExactRgba32fSpv, kTableFilterWideExactRgba16fSpv, kTableFilterWideExactB10g11r11Spv});
    // The shader's kCoefficientCount, kFixedTapGroups (0: the table's own) and kTaps.
    const TapTable& table = *context.settings.method.table;
    const std::array<int32_t, 3> specialization{coefficientCount(table.form), 0, table.taps};
    pipeline_ = context.pipeline(spirv, specialization);
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

void TablePass::record(const PassRecorder& recorder, std::span<const int> levels) const {
    const FilterSettings& s = context_.settings;
    // Hardware sampling: a face per workgroup layer; exact: the faces one after another (table_filter.comp);
    // either for each cube of a batch.
    const bool hardware = context_.plan.sampling == Sampling::hardware;
    const auto groupsOf = [&](int m) {
        const std::size_t size = std::size_t(s.faceSize >> m);
        return groupsFor(hardware ? size * size : kFaceCount * size * size);
    };
    const TableConstants constants{s.faceSize, context_.plan.pyramidDepth + 1, levels.front(), usageFirst_,
                                   levelGroupEnds(levels, groupsOf)};
    recorder.dispatch(*pipeline_, "table", levels.front(), constants, constants.groupEnd.back(),
                      uint32_t(hardware ? kFaceCount * s.batchSize : s.batchSize), int(levels.size()));
}

} // namespace probe::gpu
