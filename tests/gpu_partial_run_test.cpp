// A Filter that computes only some output levels, over a pyramid built only as deep as their taps
// read (probe::deepestPyramidLevelRead), gives exactly the bits of the same levels of a full run,
// for every method; the levels left out come back empty and nothing else is dispatched.
#include <algorithm>
#include <bit>

#include <fmt/ranges.h>

#include "gpu_test_support.h"
#include "probe/cpu_filter.h"
#include "probe/error.h"
#include "probe/fis.h"
#include "probe/plan.h"
#include "probe/shared_constants.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"

using namespace probe;
using probetest::GpuTest;

namespace {

constexpr int kSize = 16, kLevels = 4;

gpu::FilterSettings settingsFor(MethodKind method, const TapTable* table, gpu::Sampling sampling = gpu::Sampling::exact) {
    gpu::FilterSettings s;
    s.method = {method, table, {}};
    s.faceSize = kSize;
    s.levelCount = kLevels;
    s.sampling = sampling;
    return s;
}

// `depth`: the pyramid depth the levels needed.
void expectPartialEqualsFull(MethodKind method, const std::vector<int>& levels, int& depth, gpu::Sampling sampling) {
    const TapTable table = readTable(PROBE_TEST_FIXTURES "/table_16_quad4_gltf.json");
    const CubeImage source = probetest::randomProbe(kSize, 7);
    gpu::Filter full(probetest::testDevice(), settingsFor(method, &table, sampling));
    const CubeLevels all = full.run(source);

    gpu::FilterSettings s = settingsFor(method, &table, sampling);
    s.computedLevels = levels;
    if (method != MethodKind::reference)
        s.pyramidDepth = deepestPyramidLevelRead(methodTapGenerator(s.method, kSize, kLevels, s.mapping), kSize, levels);
    depth = s.pyramidDepth;
    gpu::Filter partial(probetest::testDevice(), s);
    const CubeLevels some = partial.run(source, 1, gpu::Timestamps::levels);
    const std::string what =
        fmt::format("{} {} levels {}", methodKindName(method), gpu::samplingName(partial.sampling()), fmt::join(levels, ","));

    ASSERT_EQ(some.size(), std::size_t(kLevels)) << what;
    for (int m = 0; m < kLevels; ++m) {
        const bool computed = std::find(levels.begin(), levels.end(), m) != levels.end();
        if (!computed) {
            EXPECT_EQ(some[m].size, 0) << what << ": level " << m << " was not asked for";
            continue;
        }
        ASSERT_EQ(some[m].size, kSize >> m) << what;
        EXPECT_EQ(some[m].rgb, all[m].rgb) << what << ": level " << m << " differs from the full run";
    }

    // Exactly the dispatches asked for: the pyramid to the depth (down to face size
    // PROBE_PYRAMID_TAIL_SIZE one per level, exact sampling's with its faces, edges and border corners,
    // hardware sampling's one mip; then one for the rest, named by its first; the reference: level 0,
    // the source, alone), then one per output level (the
    // reference's filtered levels: one per chunk of source rows, here one per face).
    std::vector<std::pair<std::string, int>> expected;
    const bool copiesOnly = std::all_of(levels.begin(), levels.end(), [&](int m) { return levelAlpha(s.mapping, m, kLevels) == 0.0; });
    if (method == MethodKind::reference && !copiesOnly) expected.emplace_back("pyramid", 0);
    if (method != MethodKind::reference && !copiesOnly) {
        const int tailLevel = std::max(1, std::countr_zero(unsigned(kSize / PROBE_PYRAMID_TAIL_SIZE)));
        for (int k = 0; k <= s.pyramidDepth && k <= tailLevel; ++k) expected.emplace_back("pyramid", k);
    }
    for (int m : levels) {
        const bool chunked = method == MethodKind::reference && levelAlpha(s.mapping, m, kLevels) > 0.0;
        expected.insert(expected.end(), chunked ? kFaceCount : 1, {std::string(methodKindName(method)), m});
    }
    std::vector<std::pair<std::string, int>> ran;
    for (const gpu::Dispatch& d : partial.dispatches()) ran.emplace_back(d.pass, d.level);
    EXPECT_EQ(ran, expected) << what;
    if (method != MethodKind::reference && !copiesOnly) {
        EXPECT_EQ(partial.downloadPyramid().size(), std::size_t(s.pyramidDepth + 1)) << what;
    }

    // Timed per level: one time per level computed, named by it, adding up to the pass-2 time (when
    // the queue has timestamps at all).
    const std::vector<gpu::PassTime> passes = partial.timings(), perLevel = partial.levelTimings();
    if (passes.empty()) return;
    ASSERT_EQ(perLevel.size(), levels.size()) << what;
    double sum = 0.0;
    for (std::size_t k = 0; k < levels.size(); ++k) {
        EXPECT_EQ(perLevel[k].name, fmt::format("level {}", levels[k])) << what;
        EXPECT_GE(perLevel[k].medianMs, 0.0) << what;
        sum += perLevel[k].medianMs; // one run: the medians are the runs
    }
    const auto pass2 = std::find_if(passes.begin(), passes.end(), [&](const gpu::PassTime& p) { return p.name == methodKindName(method); });
    ASSERT_NE(pass2, passes.end()) << what;
    EXPECT_NEAR(sum, pass2->medianMs, 1e-9 + 1e-9 * pass2->medianMs) << what;

    // Timed per pass (run()'s default): the same passes, no level times.
    partial.run(source);
    std::vector<std::string> names, perPassNames;
    for (const gpu::PassTime& p : passes) names.push_back(p.name);
    for (const gpu::PassTime& p : partial.timings()) perPassNames.push_back(p.name);
    EXPECT_EQ(perPassNames, names) << what;
    EXPECT_TRUE(partial.levelTimings().empty()) << what;
}

} // namespace

class PartialRun : public GpuTest {};

TEST_F(PartialRun, TableLevelsEqualTheFullRun) {
    for (const probetest::SamplingCase& c : probetest::kSamplingCases) {
        int depth = 0;
        expectPartialEqualsFull(MethodKind::table, {1}, depth, c.sampling);
        EXPECT_LT(depth, kLevels) << "level 1 needs less than the whole pyramid";
        expectPartialEqualsFull(MethodKind::table, {0, 2}, depth, c.sampling);
    }
}

TEST_F(PartialRun, FisLevelsEqualTheFullRun) {
    for (const probetest::SamplingCase& c : probetest::kSamplingCases) {
        int depth = 0;
        expectPartialEqualsFull(MethodKind::fis, {1, 2}, depth, c.sampling);
        expectPartialEqualsFull(MethodKind::fis, {0}, depth, c.sampling);
        EXPECT_EQ(depth, 0) << "the mirror level reads no pyramid";
    }
}

TEST_F(PartialRun, ReferenceLevelsEqualTheFullRun) {
    int depth = 0;
    expectPartialEqualsFull(MethodKind::reference, {0, 3}, depth, gpu::Sampling::exact);
}

TEST_F(PartialRun, RefusesLevelsOutOfOrderOrRange) {
    for (const std::vector<int>& levels : {std::vector<int>{2, 1}, std::vector<int>{4}, std::vector<int>{-1}}) {
        gpu::FilterSettings s = settingsFor(MethodKind::fis, nullptr);
        s.computedLevels = levels;
        EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ProbeError) << fmt::format("{}", fmt::join(levels, ","));
    }
    gpu::FilterSettings s = settingsFor(MethodKind::fis, nullptr);
    s.pyramidDepth = 5;
    EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ProbeError);
}
