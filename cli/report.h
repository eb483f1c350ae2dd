// report.json: what was run, on what, with which settings, how long it took and how wrong it is.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "probe/lobe.h"
#include "probe/probe_io.h"
#include "probe/roughness.h"
#include "probe/runtime.h"
#include "probe/sh.h"

namespace probefilter {

// The report format's version: a reader that meets a higher one was written for an older tool.
inline constexpr int kReportVersion = 2;

// What every report.json carries: the command, the format's version, when it was written (UTC, ISO
// 8601) and the command line that wrote it.
nlohmann::json reportHeader(std::string_view command);

// The settings block every report starts with: input, face size, levels and their roughness.
nlohmann::json describeLevels(int faceSize, int levelCount, const probe::RoughnessMapping& mapping, probe::Lobe lobe);
// A table method's level entries (each with its "level") get "method": "table", or "fis" with
// "fis_samples" where the table hands the level to FIS (TableLevel::fisSamples).
void markHandOffs(nlohmann::json& levels, const probe::TapTable& table);

// The Vulkan device a command ran on: index, name, driver, type, API version, validation.
nlohmann::json describeDevice(const probe::gpu::DeviceInfo& info, bool validation);

// One object per dispatch: pass, level ("all" for -1), workgroups.
nlohmann::json describeDispatches(const std::vector<probe::gpu::Dispatch>& dispatches);

// Each pass's median GPU time in ms, by name.
nlohmann::json medianTimes(const std::vector<probe::gpu::PassTime>& times);

// SH coefficients as a list of RGB triples, in the order of probe::kShConvention.
nlohmann::json describeSh(const probe::ShCoefficients& coefficients);

// The median of timings (the mean of the middle two for an even count; 0 for none).
double median(std::vector<double> values);

// Wall-clock stopwatch in seconds.
class Stopwatch {
public:
    Stopwatch();
    double seconds() const;

private:
    double start_;
};

// Warns on stderr, naming the file, about the pixels loading set to 0; returns the report's counts.
nlohmann::json reportPixelRepairs(const std::filesystem::path& input, const probe::PixelRepairs& repairs);

void writeJson(const std::filesystem::path& path, const nlohmann::json& json);

// The exact reference's time for `probes` probes of these levels, estimated before any work: printed
// when over a minute, and refused (ProbeError) when over an hour unless `allowLong` (--allow-long).
void checkReferenceTime(int faceSize, int levelCount, const probe::RoughnessMapping& mapping, probe::Lobe lobe, std::size_t probes,
                        bool allowLong);

// A one-line progress bar on stderr, redrawn in place.
void printProgress(const std::string& label, std::size_t done, std::size_t total);

} // namespace probefilter
