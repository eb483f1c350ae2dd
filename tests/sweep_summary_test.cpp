// The sweep's summary on rows whose answer is known: the Pareto front of the FIS methods, the front
// interpolated in log error against log time, the tables against it, and the CSV read back.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "probe/error.h"
#include "sweep_summary.h"

using namespace probefilter;

namespace {

void addMethod(std::vector<SweepRow>& rows, const SweepMethod& m, double imageError, double impulseError, double ms) {
    for (const char* probe : {"sky", "impulse-centre"})
        for (int level = 0; level < 3; ++level)
            rows.push_back({m, probe, level, level ? imageError : 0.0, level ? impulseError : 0.0, 0.0, ms});
}

// Uniform FIS of one setting: error halves and time doubles per doubling of N (from N = 8:
// `error8` at 10 ms); the impulse error is twice the image error.
void addFis(std::vector<SweepRow>& rows, double bias, const std::string& pyramid, double error8) {
    for (int n = 8; n <= 1024; n *= 2) {
        const double steps = std::log2(n / 8.0);
        const SweepMethod m{"fis" + std::to_string(n) + "-" + pyramid + std::to_string(bias), "fis", n, bias, pyramid, "", double(n)};
        addMethod(rows, m, error8 / std::exp2(steps), 2.0 * error8 / std::exp2(steps), 10.0 * std::exp2(steps));
    }
}

void addTable(std::vector<SweepRow>& rows, const std::string& name, double error, double ms) {
    addMethod(rows, {name, "table", 8, 0.0, "bspline", "quad", 20.0, 24.0}, error, 2.0 * error, ms);
}

std::vector<std::string> names(const std::vector<MethodScore>& front) {
    std::vector<std::string> out;
    for (const MethodScore& s : front) out.push_back(s.method.name);
    return out;
}

MethodScore point(const std::string& name, const std::string& family, double error, double ms) {
    return {{name, family, 0, 0.0, "bspline", "", 0.0}, error, 0.0, ms};
}

} // namespace

TEST(SweepSummary, FrontIsTheLowerEnvelopeOfEveryFisVariant) {
    const std::vector<MethodScore> scores{
        point("a-fast", "fis", 0.40, 10.0),    // on the front: the fastest
        point("b-fast", "fis", 0.50, 10.0),    // as fast, less accurate: off
        point("a-mid", "fis", 0.20, 20.0),     // on
        point("mix", "fis-mix", 0.15, 25.0),   // another family, on
        point("b-mid", "fis", 0.18, 30.0),     // slower than the mix and less accurate: off
        point("b-slow", "fis", 0.05, 80.0),    // on
        point("a-slow", "fis", 0.05, 90.0),    // as accurate as b-slow but slower: off
        point("table", "table", 0.01, 5.0),    // tables never join the FIS front
        point("a-slowest", "fis", 0.02, 160.0) // on
    };
    EXPECT_EQ(names(fisFront(scores, false)), (std::vector<std::string>{"a-fast", "a-mid", "mix", "b-slow", "a-slowest"}));
}

TEST(SweepSummary, FrontInterpolatesInLogErrorAgainstLogTime) {
    const std::vector<MethodScore> front{point("p", "fis", 0.4, 10.0), point("q", "fis", 0.1, 40.0), point("r", "fis", 0.05, 80.0)};
    // Halfway between 10 and 40 ms in log time (20 ms): halfway between 0.4 and 0.1 in log error.
    EXPECT_NEAR(frontErrorAtTime(front, 20.0, false), 0.2, 1e-12);
    EXPECT_NEAR(frontErrorAtTime(front, 40.0, false), 0.1, 1e-12);
    EXPECT_NEAR(frontErrorAtTime(front, 5.0, false), 0.4, 1e-12);    // before the front: its first point
    EXPECT_NEAR(frontErrorAtTime(front, 500.0, false), 0.05, 1e-12); // after it: its last point
    EXPECT_NEAR(*frontTimeAtError(front, 0.2, false), 20.0, 1e-9);
    EXPECT_NEAR(*frontTimeAtError(front, 0.05 * std::sqrt(2.0), false), 40.0 * std::sqrt(2.0), 1e-9);
    EXPECT_NEAR(*frontTimeAtError(front, 0.9, false), 10.0, 1e-12); // the first point already does better
    EXPECT_FALSE(frontTimeAtError(front, 0.01, false));             // never
}

TEST(SweepSummary, TablesAgainstTheFrontNotOneSetting) {
    std::vector<SweepRow> rows;
    addFis(rows, 0.0, "bspline", 0.4); // the best setting: FIS-32 0.1 at 40 ms
    addFis(rows, 1.0, "box", 0.8);     // worse everywhere: not on the front
    // A per-level mix ahead of uniform FIS at 30 ms: the front bends down to it.
    addMethod(rows, {"fismix8", "fis-mix", 8, 0.0, "bspline", "", 12.0}, 0.05, 0.4, 30.0);
    addTable(rows, "t", 0.025, 35.0);
    addTable(rows, "slow", 0.001, 500.0);
    const SweepSummary s = summarizeSweep(rows);
    EXPECT_EQ(s.bestFisSetting, "bias 0, bspline");
    EXPECT_EQ(names(s.imageFront),
              (std::vector<std::string>{"fis8-bspline0.000000", "fis16-bspline0.000000", "fismix8", "fis128-bspline0.000000",
                                        "fis256-bspline0.000000", "fis512-bspline0.000000", "fis1024-bspline0.000000"}));
    ASSERT_TRUE(s.imageRatios && s.impulseRatios);
    const Ratios& r = *s.imageRatios;
    EXPECT_EQ(r.fis32, "fis32-bspline0.000000");
    EXPECT_EQ(r.tableName, "t");
    EXPECT_TRUE(r.tableWithinFis32Time);
    EXPECT_NEAR(r.fis32Error, 0.1, 1e-12);
    // At 40 ms the front runs from the mix (30 ms, 0.05) to FIS-128 (160 ms, 0.025).
    const double frontAt40 = std::exp(std::log(0.05) + std::log(40.0 / 30.0) / std::log(160.0 / 30.0) * std::log(0.5));
    EXPECT_NEAR(r.frontErrorAtFis32Time, frontAt40, 1e-12);
    EXPECT_NEAR(r.errorAtFis32Time, 0.025 / frontAt40, 1e-12);
    // The front reaches 0.025 at FIS-128's 160 ms.
    ASSERT_TRUE(r.timeAtTableError);
    EXPECT_NEAR(*r.timeAtTableError, 160.0 / 35.0, 1e-9);
    // On impulses the mix (0.4 at 30 ms) is behind uniform FIS-16 (0.4 at 20 ms): off that front.
    EXPECT_EQ(s.impulseFront.size(), 8u);
    EXPECT_NEAR(s.impulseRatios->frontErrorAtFis32Time, 0.2, 1e-12);

    ASSERT_EQ(s.tableImages.size(), 2u);
    EXPECT_EQ(s.tableImages[0].table, "t"); // by time
    EXPECT_EQ(s.tableImages[1].table, "slow");
    EXPECT_FALSE(s.tableImages[1].fisTimeAtTableError); // below FIS-1024's 0.003125
    // At 500 ms, between FIS-256 (320 ms) and FIS-512 (640 ms): 0.4 * 10 / 500.
    EXPECT_NEAR(s.tableImages[1].errorAtTableTime, 0.001 / (0.4 * 10.0 / 500.0), 1e-12);
    EXPECT_DOUBLE_EQ(s.tableImages[0].readsPerTexel, 20.0);
}

TEST(SweepSummary, SaysWhenNoTableIsAsFastAsFis32) {
    std::vector<SweepRow> rows;
    addFis(rows, 0.0, "bspline", 0.4);  // FIS-32: 0.1 at 40 ms; FIS-64: 0.05 at 80 ms
    addTable(rows, "slow", 0.04, 60.0); // the fastest table, slower than FIS-32
    addTable(rows, "slower", 0.01, 900.0);
    const SweepSummary s = summarizeSweep(rows);
    ASSERT_TRUE(s.imageRatios);
    EXPECT_FALSE(s.imageRatios->tableWithinFis32Time);
    EXPECT_EQ(s.imageRatios->tableName, "slow");
    EXPECT_NEAR(s.imageRatios->errorAtFis32Time, 0.4, 1e-12);
    EXPECT_NEAR(s.imageRatios->errorAtTableTime, 0.04 / (0.1 * 40.0 / 60.0), 1e-9);
    EXPECT_NE(formatSummary(s).find("no table is as fast"), std::string::npos);
}

TEST(SweepSummary, CsvReadsBackWhatItWrote) {
    std::vector<SweepRow> rows;
    addFis(rows, 0.5, "box", 0.4);
    addTable(rows, "t", 0.025, 35.0);
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sweep_summary_test";
    std::filesystem::create_directories(dir);
    writeSweepCsv(dir / "sweep.csv", rows);
    const std::vector<SweepRow> back = readSweepCsv(dir / "sweep.csv");
    ASSERT_EQ(back.size(), rows.size());
    EXPECT_EQ(back.back().method.name, "t");
    EXPECT_EQ(back.back().method.form, "quad");
    EXPECT_DOUBLE_EQ(back.back().method.readsPerTexel, 20.0);
    EXPECT_DOUBLE_EQ(back.back().method.shaderTapsPerTexel, 24.0);
    EXPECT_EQ(back.front().method.pyramid, "box");
    EXPECT_DOUBLE_EQ(back.front().method.bias, 0.5);
    EXPECT_NEAR(summarizeSweep(back).imageRatios->errorAtTableTime, summarizeSweep(rows).imageRatios->errorAtTableTime, 1e-5);

    std::ofstream(dir / "bad.csv") << "method,family\nx,y\n";
    EXPECT_THROW(readSweepCsv(dir / "bad.csv"), probe::ProbeError);
    std::ifstream in(dir / "sweep.csv");
    std::string header;
    std::getline(in, header);
    std::ofstream(dir / "bad.csv") << header << "\nfis8,fis,8,0,bspline,,8,8,sky,1,nan,0.1,0.1,10,1\n";
    EXPECT_THROW(readSweepCsv(dir / "bad.csv"), probe::ProbeError);
    std::filesystem::remove_all(dir);
}
