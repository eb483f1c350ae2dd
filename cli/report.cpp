#include "report.h"

#include <algorithm>
#include <chrono>

#include <ctime>

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <unistd.h>

#include "command_line.h"

#include "probe/error.h"
#include "probe/output_file.h"
#include "probe/reference.h"

namespace probefilter {

nlohmann::json reportHeader(std::string_view command) {
    return {{"command", command},
            {"report_version", kReportVersion},
            {"date", fmt::format("{:%Y-%m-%dT%H:%M:%SZ}", fmt::gmtime(std::time(nullptr)))},
            {"command_line", invocation()}};
}

nlohmann::json describeLevels(int faceSize, int levelCount, const probe::RoughnessMapping& mapping, probe::Lobe lobe) {
    nlohmann::json levels = nlohmann::json::array();
    for (int m = 0; m < levelCount; ++m)
        levels.push_back({{"level", m},
                          {"face_size", faceSize >> m},
                          {"roughness", probe::levelRoughness(mapping, m, levelCount)},
                          {"alpha", probe::lobeAlpha(lobe, probe::levelAlpha(mapping, m, levelCount))},
                          {"file", fmt::format("level_{}.exr", m)}});
    return {{"face_size", faceSize},
            {"level_count", levelCount},
            {"mapping", probe::describeRoughnessMapping(mapping)},
            {"lobe", probe::lobeName(lobe)},
            {"levels", levels}};
}

void markHandOffs(nlohmann::json& levels, const probe::TapTable& table) {
    for (nlohmann::json& level : levels) {
        const int samples = table.levels[level["level"].get<std::size_t>()].fisSamples;
        if (samples > 0) level["fis_samples"] = samples;
        level["method"] = samples > 0 ? "fis" : "table";
    }
}

nlohmann::json describeDevice(const probe::gpu::DeviceInfo& info, bool validation) {
    return {{"kind", "vulkan"},
            {"index", info.index},
            {"name", info.name},
            {"driver", info.driver},
            {"type", info.type},
            {"api", fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(info.apiVersion), VK_API_VERSION_MINOR(info.apiVersion),
                                VK_API_VERSION_PATCH(info.apiVersion))},
            {"validation", validation}};
}

nlohmann::json describeDispatches(const std::vector<probe::gpu::Dispatch>& dispatches) {
    nlohmann::json list = nlohmann::json::array();
    for (const probe::gpu::Dispatch& d : dispatches) {
        nlohmann::json entry = {{"pass", d.pass}, {"level", d.level}, {"workgroups", d.groups}};
        if (d.levels > 1) entry["levels"] = d.levels;
        list.push_back(std::move(entry));
    }
    return list;
}

static double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n == 0 ? 0.0 : n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Stopwatch::Stopwatch() : start_(now()) {}
double Stopwatch::seconds() const { return now() - start_; }

nlohmann::json reportPixelRepairs(const std::filesystem::path& input, const probe::PixelRepairs& repairs) {
    if (repairs.negative)
        probe::printToStderr(
            fmt::format("probefilter: warning: {}: {} pixel(s) with negative values clamped to 0\n", input.string(), repairs.negative));
    if (repairs.nonFinite)
        probe::printToStderr(fmt::format("probefilter: warning: {}: {} NaN or Inf pixel(s) set to 0 (--repair-pixels)\n", input.string(),
                                         repairs.nonFinite));
    return {{"clamped_negative_pixels", repairs.negative}, {"repaired_pixels", repairs.nonFinite}};
}

void writeJson(const std::filesystem::path& path, const nlohmann::json& json) { probe::writeFile(path, json.dump(2) + "\n"); }

void printProgress(const std::string& label, std::size_t done, std::size_t total) {
    // Redrawn in place on a terminal; in logs one line per tenth of the work.
    if (!::isatty(STDERR_FILENO)) {
        if (total && done > 0 && done * 10 / total != (done - 1) * 10 / total)
            probe::printToStderr(fmt::format("{:<12} {:3}% ({}/{})\n", label, 100 * done / total, done, total));
        return;
    }
    const int width = 30;
    const int filled = total ? static_cast<int>(width * done / total) : width;
    probe::printToStderr(fmt::format("\r{:<12} [{:<{}}] {:3}%", label, std::string(static_cast<std::size_t>(filled), '#'), width,
                                     total ? 100 * done / total : 100));
    if (done >= total) probe::printToStderr("\n");
}

void checkReferenceTime(int faceSize, int levelCount, const probe::RoughnessMapping& mapping, probe::Lobe lobe, std::size_t probes,
                        bool allowLong) {
    const double seconds = static_cast<double>(probes) * probe::estimateReferenceSeconds(faceSize, levelCount, mapping, lobe);
    if (seconds < 60.0) return;
    const std::string estimate =
        seconds < 3600.0 ? fmt::format("{:.1f} minutes", seconds / 60.0) : fmt::format("{:.1f} hours", seconds / 3600.0);
    if (seconds > 3600.0 && !allowLong)
        throw probe::ProbeError(fmt::format("the CPU reference at {}^2 would take about {} here (quadratic in the face size); pass "
                                            "--allow-long to run it, or use a smaller --size",
                                            faceSize, estimate));
    probe::printToStderr(fmt::format("reference: about {} at {}^2 (estimated)\n", estimate, faceSize));
}

nlohmann::json medianTimes(const std::vector<probe::gpu::PassTime>& times) {
    nlohmann::json out = nlohmann::json::object();
    for (const probe::gpu::PassTime& t : times) out[t.name] = t.medianMs;
    return out;
}

nlohmann::json describeSh(const probe::ShCoefficients& coefficients) {
    nlohmann::json list = nlohmann::json::array();
    for (const glm::dvec3& rgb : coefficients) list.push_back({rgb.r, rgb.g, rgb.b});
    return list;
}

} // namespace probefilter
