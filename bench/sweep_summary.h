// The sweep's numbers: rows per (method, probe, level), and the summary that answers "what does
// accuracy cost in time": per method the mean errors, the median time and the texture reads per
// texel; FIS as the Pareto front of every FIS variant in the sweep (lowest error at each time, per
// error measure), and each table against that front at FIS-32's time, at the table's time and at
// the table's error.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace probefilter {

struct SweepMethod {
    std::string name;
    // "table"; "fis" (one sample count), "fis-mix" (per level: probe::mixedLevelSamples) or
    // "fis-paraboloid"; "ggx-levels" (a Charlie sweep's stand-in: a GGX table read at the sheen roughness)
    std::string family;
    int count = 0; // taps per frame, or samples (at level 1 for a mix)
    double bias = 0.0;
    std::string pyramid;
    std::string form;           // tables: "quad" or "const"
    double readsPerTexel = 0.0; // trilinear pyramid reads per output texel of levels >= 1, averaged over those texels
    // The taps or samples that the filter shader's loop runs per output texel of levels >= 1: the reads, and a
    // table level's zero-weight taps up to the shader's groups of four (bench/shader_stats/shader_stats --sweep costs them).
    double shaderTapsPerTexel = 0.0;
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

// One method over a probe set: image L1 averaged over probes and the levels from the sweep's first
// (1 where level 0 is a copy, GGX; 0 for Charlie), impulse L1 averaged over those levels, median GPU
// time over probes.
struct MethodScore {
    SweepMethod method;
    double imageL1 = 0.0;
    double impulseL1 = 0.0;
    double gpuMs = 0.0;
};

bool isFisFamily(const std::string& family); // "fis", "fis-mix" and "fis-paraboloid"

// The Pareto front of the FIS methods on one error measure: ascending in time, strictly descending
// in error; every FIS method has a point of the front no slower and no less accurate.
std::vector<MethodScore> fisFront(const std::vector<MethodScore>& scores, bool impulse);

// The front's error at `ms`, interpolated between the two points around it in log error against
// log time; outside the front's times, the error of its nearer end.
double frontErrorAtTime(const std::vector<MethodScore>& front, double ms, bool impulse);

// The time at which the front reaches `error`, interpolated the same way; empty where even its most
// accurate point does not.
std::optional<double> frontTimeAtError(const std::vector<MethodScore>& front, double error, bool impulse);

// The most accurate table within FIS-32's time (else the fastest table) against the FIS front, on
// one error measure.
struct Ratios {
    std::string fis32;                 // the FIS-32 whose time is the budget (uniform, at the best setting)
    std::string tableName;             // the most accurate table no slower than FIS-32, else the fastest
    bool tableWithinFis32Time = false; // false: no table is as fast as FIS-32, and the fastest is compared
    double tableMs = 0.0, fis32Ms = 0.0;
    double tableError = 0.0;
    double fis32Error = 0.0;                // FIS-32's own error
    double frontErrorAtFis32Time = 0.0;     // the front's error at FIS-32's time
    double errorAtFis32Time = 0.0;          // table error / frontErrorAtFis32Time
    double errorAtTableTime = 0.0;          // table error / the front's error at the table's time
    std::optional<double> timeAtTableError; // the front's time / table time at the table's error; empty: never
    std::string frontMostAccurate;          // the front's last point
};

// One table (or stand-in) against the FIS front at the table's own time and its own error.
struct TableVersusFis {
    std::string table;
    double error = 0.0, gpuMs = 0.0, readsPerTexel = 0.0;
    double errorAtTableTime = 0.0;             // table error / the front's error at the table's time
    std::optional<double> fisTimeAtTableError; // the front's time / table time at the table's error; empty: never
};

struct SweepSummary {
    std::vector<MethodScore> images;                        // over the non-impulse probes
    std::vector<MethodScore> impulses;                      // over the impulse probes
    std::string bestFisSetting;                             // the best single (bias, pyramid) over the image probes
    std::vector<MethodScore> imageFront, impulseFront;      // fisFront of each measure
    std::optional<Ratios> imageRatios, impulseRatios;       // against the fronts
    std::vector<TableVersusFis> tableImages, tableImpulses; // every table and stand-in against the fronts, by time
};

// firstLevel: the first level the errors average over (1 where level 0 is a copy for every method).
SweepSummary summarizeSweep(const std::vector<SweepRow>& rows, int firstLevel = 1);

// What a sweep filtered with, for its reports: the lobe ("ggx", "charlie") and the first level measured.
struct SweepShape {
    int size = 0, levelCount = 0;
    std::string lobe = "ggx";
    int firstLevel = 1;
};

void writeSweepCsv(const std::filesystem::path& path, const std::vector<SweepRow>& rows);
// The rows of a sweep.csv that writeSweepCsv wrote; ProbeError naming the file and line otherwise.
std::vector<SweepRow> readSweepCsv(const std::filesystem::path& path);
// sweep.md: the summary, every table against the FIS front and every method; `header` (reportHeader)
// gives the command line and date it names.
void writeSweepMarkdown(const std::filesystem::path& path, const SweepSummary& summary, const std::vector<SweepRow>& rows,
                        const std::string& device, const SweepShape& shape, const nlohmann::json& header);
nlohmann::json sweepSummaryJson(const SweepSummary& summary, const std::string& device, const std::string& driver, const SweepShape& shape);
std::string formatSummary(const SweepSummary& summary);

} // namespace probefilter
