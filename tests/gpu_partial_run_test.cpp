// A Filter that computes only some output levels, over a pyramid built only as deep as their taps
// read (probe::deepestPyramidLevelRead), gives exactly the bits of the same levels of a full run,
// for every method; the levels left out come back empty and nothing else is dispatched.
#include <algorithm>

#include <fmt/ranges.h>

#include "gpu_test_support.h"
#include "probe/error.h"
#include "probe/importance_sampling.h"
#include "probe/plan.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"

using namespace probe;
using probetest::GpuTest;

namespace {

constexpr int kSize = 16, kLevels = 4;

gpu::FilterSettings settingsFor(gpu::Method method, const TapTable* table) {
    gpu::FilterSettings s;
    s.method = method;
    s.faceSize = kSize;
    s.levelCount = kLevels;
    s.table = table;
    return s;
}

TapGenerator generatorFor(gpu::Method method, const TapTable& table) {
    if (method == gpu::Method::table) return tableTapGenerator(table);
    return importanceSampleTapGenerator(kSize, kLevels, RoughnessMapping::gltf, ImportanceSamplingSettings{});
}

// `depth`: the pyramid depth the levels needed.
void expectPartialEqualsFull(gpu::Method method, const std::vector<int>& levels, int& depth) {
    const TapTable table = readTable(PROBE_TEST_FIXTURES "/table_16_quad4_gltf.json");
    const CubeImage source = probetest::randomProbe(kSize, 7);
    gpu::Filter full(probetest::testDevice(), settingsFor(method, &table));
    const CubeLevels all = full.run(source);

    gpu::FilterSettings s = settingsFor(method, &table);
    s.levels = levels;
    if (method != gpu::Method::reference) s.pyramidDepth = deepestPyramidLevelRead(generatorFor(method, table), kSize, levels);
    depth = s.pyramidDepth;
    gpu::Filter partial(probetest::testDevice(), s);
    const CubeLevels some = partial.run(source);
    const std::string what = fmt::format("{} levels {}", gpu::methodName(method), fmt::join(levels, ","));

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

    // Exactly the dispatches asked for: the pyramid to the depth, two per level (its faces and edges,
    // level 0 only the source's border; then its border corners), then one per output level; the
    // reference's filtered levels one per chunk of source rows, here one per face.
    std::vector<std::pair<std::string, int>> expected;
    const bool copiesOnly = std::all_of(levels.begin(), levels.end(), [&](int m) { return levelAlpha(s.mapping, m, kLevels) == 0.0; });
    if (method != gpu::Method::reference && !copiesOnly)
        for (int k = 0; k <= s.pyramidDepth; ++k) expected.insert(expected.end(), 2, {"pyramid", k});
    for (int m : levels) {
        const bool chunked = method == gpu::Method::reference && levelAlpha(s.mapping, m, kLevels) > 0.0;
        expected.insert(expected.end(), chunked ? kFaceCount : 1, {std::string(gpu::methodName(method)), m});
    }
    std::vector<std::pair<std::string, int>> ran;
    for (const gpu::Dispatch& d : partial.dispatches()) ran.emplace_back(d.pass, d.level);
    EXPECT_EQ(ran, expected) << what;
    if (method != gpu::Method::reference && !copiesOnly) {
        EXPECT_EQ(partial.downloadPyramid().size(), std::size_t(s.pyramidDepth + 1)) << what;
    }

    // One time per level computed, named by it, adding up to the pass-2 time (when the queue has
    // timestamps at all).
    const std::vector<gpu::PassTime> passes = partial.timings(), perLevel = partial.levelTimings();
    if (passes.empty()) return;
    ASSERT_EQ(perLevel.size(), levels.size()) << what;
    double sum = 0.0;
    for (std::size_t k = 0; k < levels.size(); ++k) {
        EXPECT_EQ(perLevel[k].name, fmt::format("level {}", levels[k])) << what;
        EXPECT_GE(perLevel[k].medianMs, 0.0) << what;
        sum += perLevel[k].medianMs; // one run: the medians are the runs
    }
    const auto pass2 =
        std::find_if(passes.begin(), passes.end(), [&](const gpu::PassTime& p) { return p.name == gpu::methodName(method); });
    ASSERT_NE(pass2, passes.end()) << what;
    EXPECT_NEAR(sum, pass2->medianMs, 1e-9 + 1e-9 * pass2->medianMs) << what;
}

} // namespace

class PartialRun : public GpuTest {};

TEST_F(PartialRun, TableLevelsEqualTheFullRun) {
    int depth = 0;
    expectPartialEqualsFull(gpu::Method::table, {1}, depth);
    EXPECT_LT(depth, kLevels) << "level 1 needs less than the whole pyramid";
    expectPartialEqualsFull(gpu::Method::table, {0, 2}, depth);
}

TEST_F(PartialRun, FisLevelsEqualTheFullRun) {
    int depth = 0;
    expectPartialEqualsFull(gpu::Method::fis, {1, 2}, depth);
    expectPartialEqualsFull(gpu::Method::fis, {0}, depth);
    EXPECT_EQ(depth, 0) << "the mirror level reads no pyramid";
}

TEST_F(PartialRun, ReferenceLevelsEqualTheFullRun) {
    int depth = 0;
    expectPartialEqualsFull(gpu::Method::reference, {0, 3}, depth);
}

TEST_F(PartialRun, RefusesLevelsOutOfOrderOrRange) {
    for (const std::vector<int>& levels : {std::vector<int>{2, 1}, std::vector<int>{4}, std::vector<int>{-1}}) {
        gpu::FilterSettings s = settingsFor(gpu::Method::fis, nullptr);
        s.levels = levels;
        EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ProbeError) << fmt::format("{}", fmt::join(levels, ","));
    }
    gpu::FilterSettings s = settingsFor(gpu::Method::fis, nullptr);
    s.pyramidDepth = 5;
    EXPECT_THROW(gpu::Filter(probetest::testDevice(), s), ProbeError);
}
