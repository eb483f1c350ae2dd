// The sweep's ratios on rows whose answer is known: the best FIS setting, the table compared at
// FIS-32's time, and FIS's time at the table's error interpolated in log N.
#include <cmath>

#include <gtest/gtest.h>

#include "sweep_summary.h"

using namespace probefilter;

namespace {

// FIS of one setting: error halves and time doubles per doubling of N (from N = 8: error 0.4, 10 ms).
void addFis(std::vector<SweepRow>& rows, double bias, const std::string& pyramid, double errorScale, const std::string& probe) {
    for (int n = 8; n <= 1024; n *= 2) {
        const double steps = std::log2(n / 8.0);
        const SweepMethod m{"fis" + std::to_string(n) + pyramid + std::to_string(bias), "fis", n, bias, pyramid, ""};
        for (int level = 0; level < 3; ++level)
            rows.push_back({m, probe, level, level ? errorScale * 0.4 / std::exp2(steps) : 0.0,
                            level ? errorScale * 0.8 / std::exp2(steps) : 0.0, 0.0, 10.0 * std::exp2(steps)});
    }
}

// Per-level FIS mixes of one setting at N = 8, 16, 32: errors and times given.
void addFisMix(std::vector<SweepRow>& rows, const std::vector<std::pair<double, double>>& errorAndMs, const std::string& probe) {
    int n = 8;
    for (const auto& [error, ms] : errorAndMs) {
        const SweepMethod m{"fismix" + std::to_string(n), "fis-mix", n, 0.0, "bspline", ""};
        for (int level = 0; level < 3; ++level) rows.push_back({m, probe, level, level ? error : 0.0, level ? error : 0.0, 0.0, ms});
        n *= 2;
    }
}

void addTable(std::vector<SweepRow>& rows, const std::string& name, double error, double ms, const std::string& probe) {
    const SweepMethod m{name, "table", 8, 0.0, "bspline", "quad"};
    for (int level = 0; level < 3; ++level) rows.push_back({m, probe, level, level ? error : 0.0, level ? 2.0 * error : 0.0, 0.0, ms});
}

} // namespace

TEST(SweepSummary, RatiosAgainstTheBestAndThePapersSetting) {
    std::vector<SweepRow> rows;
    for (const char* probe : {"sky", "impulse-centre"}) {
        addFis(rows, 0.0, "bspline", 1.0, probe); // the best setting
        addFis(rows, 1.0, "box", 2.0, probe);     // the paper's, twice the error
        // FIS-32 takes 40 ms and has error 0.1 (image) at the best setting.
        addTable(rows, "fast", 0.05, 30.0, probe);  // no slower than FIS-32: compared
        addTable(rows, "slow", 0.01, 500.0, probe); // more accurate but slower
    }
    const SweepSummary s = summarizeSweep(rows);
    EXPECT_EQ(s.bestFisSetting, "bias 0, bspline");
    ASSERT_TRUE(s.best && s.paper && s.impulseBest);
    EXPECT_EQ(s.best->tableName, "fast");
    EXPECT_NEAR(s.best->errorAtFis32Time, 0.5, 1e-12);
    EXPECT_NEAR(s.paper->errorAtFis32Time, 0.25, 1e-12);
    // FIS reaches 0.05 at N = 64 (80 ms): 80 / 30.
    ASSERT_TRUE(s.best->timeAtTableError);
    EXPECT_NEAR(*s.best->timeAtTableError, 80.0 / 30.0, 1e-9);
    // The paper's setting reaches 0.05 between N = 128 and 256, at N = 128 exactly: 160 / 30.
    EXPECT_NEAR(*s.paper->timeAtTableError, 160.0 / 30.0, 1e-9);
    // At 30 ms, between FIS-16 (20 ms, 0.2) and FIS-32 (40 ms, 0.1), FIS's error is
    // 0.2 * (30 / 20)^-1 = 0.1333: 0.05 / 0.1333.
    EXPECT_TRUE(s.best->tableWithinFis32Time);
    EXPECT_NEAR(s.best->errorAtTableTime, 0.05 / (0.2 * 20.0 / 30.0), 1e-9);
}

TEST(SweepSummary, EveryTableAgainstFisAtItsTimeAndItsError) {
    std::vector<SweepRow> rows;
    addFis(rows, 0.0, "bspline", 1.0, "sky"); // error 0.4 at 10 ms, halving per doubling of time
    addTable(rows, "b", 0.0125, 60.0, "sky"); // FIS at 60 ms: 0.4 / 6 = 0.0667; FIS reaches 0.0125 at 320 ms
    addTable(rows, "a", 0.05, 30.0, "sky");   // FIS at 30 ms: 0.1333; FIS reaches 0.05 at 80 ms
    addTable(rows, "c", 1e-4, 20.0, "sky");   // FIS never gets there
    const SweepSummary s = summarizeSweep(rows);
    ASSERT_EQ(s.tableImages.size(), 3u);
    EXPECT_EQ(s.tableImages[0].table, "c"); // by time
    EXPECT_FALSE(s.tableImages[0].fisTimeAtTableError);
    EXPECT_EQ(s.tableImages[1].table, "a");
    EXPECT_NEAR(s.tableImages[1].errorAtTableTime, 0.05 / (0.4 / 3.0), 1e-9);
    EXPECT_NEAR(*s.tableImages[1].fisTimeAtTableError, 80.0 / 30.0, 1e-9);
    EXPECT_EQ(s.tableImages[2].table, "b");
    EXPECT_NEAR(s.tableImages[2].errorAtTableTime, 0.0125 / (0.4 / 6.0), 1e-9);
    EXPECT_NEAR(*s.tableImages[2].fisTimeAtTableError, 320.0 / 60.0, 1e-9);
    EXPECT_TRUE(s.tableImpulses.empty()); // no impulse probes
}

TEST(SweepSummary, SaysWhenNoTableIsAsFastAsFis32) {
    std::vector<SweepRow> rows;
    addFis(rows, 0.0, "bspline", 1.0, "sky");  // FIS-32: 0.1 at 40 ms; FIS-64: 0.05 at 80 ms
    addTable(rows, "slow", 0.04, 60.0, "sky"); // the fastest table, slower than FIS-32
    addTable(rows, "slower", 0.01, 900.0, "sky");
    const SweepSummary s = summarizeSweep(rows);
    ASSERT_TRUE(s.best);
    EXPECT_FALSE(s.best->tableWithinFis32Time);
    EXPECT_EQ(s.best->tableName, "slow");
    EXPECT_NEAR(s.best->errorAtFis32Time, 0.4, 1e-12);
    // FIS at 60 ms: 0.1 * (60 / 40)^-1 = 0.0667.
    EXPECT_NEAR(s.best->errorAtTableTime, 0.04 / (0.1 * 40.0 / 60.0), 1e-9);
    EXPECT_NE(formatSummary(s).find("no table is as fast as FIS-32"), std::string::npos);
}

TEST(SweepSummary, InterpolatesInLogNAndSaysWhenFisNeverGetsThere) {
    std::vector<SweepRow> rows;
    addFis(rows, 0.0, "bspline", 1.0, "sky");
    addTable(rows, "t", 0.1 / std::sqrt(2.0), 40.0, "sky"); // FIS reaches it halfway between N = 32 and 64
    SweepSummary s = summarizeSweep(rows);
    ASSERT_TRUE(s.best && s.best->timeAtTableError);
    EXPECT_NEAR(*s.best->timeAtTableError, 40.0 * std::sqrt(2.0) / 40.0, 1e-9);

    rows.clear();
    addFis(rows, 0.0, "bspline", 1.0, "sky");
    addTable(rows, "t", 1e-4, 40.0, "sky"); // below FIS-1024's 0.003125
    s = summarizeSweep(rows);
    ASSERT_TRUE(s.best);
    EXPECT_FALSE(s.best->timeAtTableError);
    EXPECT_EQ(s.best->fisMaxSamples, 1024);
}

TEST(SweepSummary, AgainstPerLevelFisMixesWithinFis32sTime) {
    std::vector<SweepRow> rows;
    addFis(rows, 0.0, "bspline", 1.0, "sky"); // FIS-32: error 0.1 at 40 ms
    addFisMix(rows, {{0.08, 20.0}, {0.04, 38.0}, {0.02, 70.0}}, "sky");
    addTable(rows, "t", 0.02, 35.0, "sky");
    const SweepSummary s = summarizeSweep(rows);
    ASSERT_TRUE(s.best && s.bestMix);
    EXPECT_NEAR(s.best->errorAtFis32Time, 0.2, 1e-12);
    // The most accurate mix within 40 ms is N = 16 (0.04): 0.02 / 0.04; the mixes reach 0.02 at 70 ms.
    EXPECT_EQ(s.bestMix->fisCompared, "fismix16");
    EXPECT_NEAR(s.bestMix->errorAtFis32Time, 0.5, 1e-12);
    ASSERT_TRUE(s.bestMix->timeAtTableError);
    EXPECT_NEAR(*s.bestMix->timeAtTableError, 70.0 / 35.0, 1e-9);
    EXPECT_NE(formatSummary(s).find("images, best FIS per-level mix"), std::string::npos);
}
