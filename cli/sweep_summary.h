// The sweep's numbers: rows per (method, probe, level), and the summary that answers "what does
// accuracy cost in time": per method the mean errors and the median time, FIS at its best single
// setting and at the paper's (bias 1, box), and the ratios at equal time and at equal error; the same ratios against
// per-level FIS mixes, the fair match for tables whose levels use different tap counts.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace probefilter {

struct SweepMethod {
    std::string name;
    std::string family; // "table", "fis" (one sample count) or "fis-mix" (per level: probe::mixedLevelSamples)
    int count = 0;      // taps per frame, or samples (at level 1 for a mix)
    double bias = 0.0;
    std::string pyramid;
    std::string form; // tables: "quad" or "const"
};

struct SweepRow {
    SweepMethod method;
    std::string probe;
    int level = 0;
    double imageL1 = 0.0;
    double impulseL1Mean = 0.0;
    double impulseL1Max = 0.0;
    double gpuMs = 0.0;      // the method's GPU time for all levels, median of the repeats
    double levelGpuMs = 0.0; // the part of it that this level's pass-2 dispatch takes, median of the repeats
};

// One method over a probe set: image L1 averaged over probes and levels >= 1, impulse L1 averaged
// over levels >= 1, median GPU time over probes.
struct MethodScore {
    SweepMethod method;
    double imageL1 = 0.0;
    double impulseL1 = 0.0;
    double gpuMs = 0.0;
};

// The two ratios against one FIS family at one setting, on one error measure, and the same
// comparison at the table's own time.
struct Ratios {
    std::string fisSetting;            // e.g. "bias 0, bspline"
    std::string fisFamily;             // "fis" or "fis-mix"
    std::string fisCompared;           // FIS-32, or the most accurate mix no slower than FIS-32
    std::string tableName;             // the table compared: the most accurate one no slower than FIS-32, else the fastest
    bool tableWithinFis32Time = false; // false: no table is as fast as FIS-32, and the fastest is compared
    double tableMs = 0.0, fis32Ms = 0.0;
    double errorAtFis32Time = 0.0;          // table error / the compared FIS's error
    std::optional<double> timeAtTableError; // FIS time / table time at the table's error; empty: FIS never gets there
    // Table error / FIS error at the table's time, FIS interpolated between the counts around that
    // time (log error against log time); the nearest end of the curve outside it.
    double errorAtTableTime = 0.0;
    int fisMaxSamples = 0;
};

// One table against uniform FIS at one setting, at the table's own time and its own error.
struct TableVersusFis {
    std::string table;
    double error = 0.0, gpuMs = 0.0;
    double errorAtTableTime = 0.0;             // table error / FIS error at the table's time
    std::optional<double> fisTimeAtTableError; // FIS time / table time at the table's error; empty: never
};

struct SweepSummary {
    std::vector<MethodScore> images;   // over the non-impulse probes
    std::vector<MethodScore> impulses; // over the impulse probes
    std::string bestFisSetting;        // the best single (bias, pyramid) over the image probes
    std::optional<Ratios> best, paper, impulseBest;
    std::optional<Ratios> bestMix, impulseBestMix;          // against the per-level FIS mixes at the best setting
    std::vector<TableVersusFis> tableImages, tableImpulses; // every table against FIS at the best setting, by time
};

SweepSummary summarizeSweep(const std::vector<SweepRow>& rows);

void writeSweepCsv(const std::filesystem::path& path, const std::vector<SweepRow>& rows);
void writeSweepMarkdown(const std::filesystem::path& path, const SweepSummary& summary, const std::vector<SweepRow>& rows,
                        const std::string& device, int size, int levelCount);
nlohmann::json sweepSummaryJson(const SweepSummary& summary, const std::string& device, const std::string& driver, int size,
                                int levelCount);
std::string formatSummary(const SweepSummary& summary);

} // namespace probefilter
