#include "sweep_summary.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include "probe/error.h"

namespace probefilter {

namespace {

bool isImpulse(const std::string& probe) { return probe.rfind("impulse", 0) == 0; }

std::string fisSetting(const SweepMethod& m) { return fmt::format("bias {}, {}", m.bias, m.pyramid); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

std::vector<MethodScore> score(const std::vector<SweepRow>& rows, bool impulses) {
    struct Sums {
        SweepMethod method;
        double image = 0.0, impulse = 0.0;
        int count = 0;
        std::map<std::string, double> times;
    };
    std::map<std::string, Sums> byMethod;
    std::vector<std::string> order;
    for (const SweepRow& r : rows) {
        if (isImpulse(r.probe) != impulses) continue;
        if (!byMethod.count(r.method.name)) order.push_back(r.method.name);
        Sums& s = byMethod[r.method.name];
        s.method = r.method;
        s.times[r.probe] = r.gpuMs;
        if (r.level == 0) continue; // the mirror level is a copy for every method
        s.image += r.imageL1;
        s.impulse += r.impulseL1Mean;
        ++s.count;
    }
    std::vector<MethodScore> scores;
    for (const std::string& name : order) {
        const Sums& s = byMethod[name];
        std::vector<double> times;
        for (const auto& [probe, ms] : s.times) times.push_back(ms);
        scores.push_back({s.method, s.count ? s.image / s.count : 0.0, s.count ? s.impulse / s.count : 0.0, median(times)});
    }
    return scores;
}

double errorOf(const MethodScore& s, bool impulse) { return impulse ? s.impulseL1 : s.imageL1; }

// FIS of one family ("fis" or "fis-mix") at one setting, ascending in samples (at level 1).
std::vector<MethodScore> fisCurve(const std::vector<MethodScore>& scores, const std::string& family, const std::string& setting) {
    std::vector<MethodScore> curve;
    for (const MethodScore& s : scores)
        if (s.method.family == family && fisSetting(s.method) == setting) curve.push_back(s);
    std::sort(curve.begin(), curve.end(), [](const MethodScore& a, const MethodScore& b) { return a.method.count < b.method.count; });
    return curve;
}

// The most accurate of `family` within `budget` ms; null where none is.
const MethodScore* mostAccurateWithin(const std::vector<MethodScore>& scores, const std::string& family, double budget, bool impulse) {
    const MethodScore* best = nullptr;
    for (const MethodScore& s : scores)
        if (s.method.family == family && s.gpuMs <= budget && (!best || errorOf(s, impulse) < errorOf(*best, impulse))) best = &s;
    return best;
}

double fastestTime(const std::vector<MethodScore>& scores, const std::string& family) {
    double fastest = 0.0;
    for (const MethodScore& s : scores)
        if (s.method.family == family && (fastest == 0.0 || s.gpuMs < fastest)) fastest = s.gpuMs;
    return fastest;
}

// The error of a FIS curve (ascending in samples) at `ms`, interpolated in log error against log
// time between the two counts around it; the error at the nearer end outside the curve's times.
double fisErrorAtTime(const std::vector<MethodScore>& curve, double ms, bool impulse) {
    if (ms <= curve.front().gpuMs) return errorOf(curve.front(), impulse);
    for (std::size_t k = 1; k < curve.size(); ++k) {
        if (curve[k].gpuMs < ms) continue;
        const double t0 = std::log(curve[k - 1].gpuMs), t1 = std::log(curve[k].gpuMs);
        const double t = t1 == t0 ? 1.0 : (std::log(ms) - t0) / (t1 - t0);
        return std::exp(std::log(errorOf(curve[k - 1], impulse)) +
                        t * (std::log(errorOf(curve[k], impulse)) - std::log(errorOf(curve[k - 1], impulse))));
    }
    return errorOf(curve.back(), impulse);
}

// The time at which a FIS curve (ascending in samples) reaches `error`, interpolated in log error
// against log time between the two counts around it; empty where even the last count does not.
std::optional<double> fisTimeAtError(const std::vector<MethodScore>& curve, double error, bool impulse) {
    for (std::size_t k = 0; k < curve.size(); ++k) {
        if (errorOf(curve[k], impulse) > error) continue;
        if (k == 0) return curve[0].gpuMs;
        const double e0 = std::log(errorOf(curve[k - 1], impulse)), e1 = std::log(errorOf(curve[k], impulse));
        const double t = e0 == e1 ? 1.0 : (e0 - std::log(error)) / (e0 - e1);
        return std::exp(std::log(curve[k - 1].gpuMs) + t * (std::log(curve[k].gpuMs) - std::log(curve[k - 1].gpuMs)));
    }
    return std::nullopt;
}

// The two ratios against one FIS family at one setting. The time budget is uniform FIS-32's at
// that setting; the table compared is the most accurate one within it (else the fastest), and so is
// the FIS point: FIS-32 itself for "fis", the most accurate per-level mix for "fis-mix".
std::optional<Ratios> ratios(const std::vector<MethodScore>& scores, const std::string& family, const std::string& setting, bool impulse) {
    const std::vector<MethodScore> uniform = fisCurve(scores, "fis", setting);
    const auto fis32 = std::find_if(uniform.begin(), uniform.end(), [](const MethodScore& s) { return s.method.count == 32; });
    const std::vector<MethodScore> curve = fisCurve(scores, family, setting);
    if (fis32 == uniform.end() || curve.empty()) return std::nullopt;
    const MethodScore* fis = family == "fis" ? &*fis32 : mostAccurateWithin(curve, family, fis32->gpuMs, impulse);
    if (!fis) fis = &curve.front();
    const MethodScore* table = mostAccurateWithin(scores, "table", fis32->gpuMs, impulse);
    Ratios r;
    r.tableWithinFis32Time = table != nullptr;
    if (!table) table = mostAccurateWithin(scores, "table", fastestTime(scores, "table"), impulse);
    if (!table) return std::nullopt;
    r.fisSetting = setting;
    r.fisFamily = family;
    r.fisCompared = fis->method.name;
    r.tableName = table->method.name;
    r.tableMs = table->gpuMs;
    r.fis32Ms = fis32->gpuMs;
    r.errorAtFis32Time = errorOf(*table, impulse) / errorOf(*fis, impulse);
    r.errorAtTableTime = errorOf(*table, impulse) / fisErrorAtTime(curve, table->gpuMs, impulse);
    r.fisMaxSamples = curve.back().method.count;
    if (const std::optional<double> ms = fisTimeAtError(curve, errorOf(*table, impulse), impulse)) r.timeAtTableError = *ms / table->gpuMs;
    return r;
}

std::string formatRatios(const std::optional<Ratios>& r, const std::string& label) {
    if (!r) return fmt::format("{}: not measured (no table, no FIS-32 or no FIS of that family in the sweep)\n", label);
    const std::string last = fmt::format("{}-{}", r->fisFamily == "fis" ? "FIS" : "FIS-mix", r->fisMaxSamples);
    const std::string time =
        r->timeAtTableError ? fmt::format("{:.2f}x", *r->timeAtTableError) : fmt::format("> {} (never reaches it)", last);
    const std::string fis = r->fisFamily == "fis" ? "FIS-32" : "the best FIS mix within it";
    const std::string compared = r->fisFamily == "fis" ? "" : fmt::format("; FIS {}", r->fisCompared);
    const std::string atBudget =
        r->tableWithinFis32Time
            ? fmt::format("at FIS-32's time, table error / {} error = {:.3f}", fis, r->errorAtFis32Time)
            : fmt::format("no table is as fast as FIS-32 ({:.2f} ms), the fastest takes {:.2f} ms: its error / {} error = {:.3f}",
                          r->fis32Ms, r->tableMs, fis, r->errorAtFis32Time);
    return fmt::format("{} (FIS {}; table {}{}): {}; at the table's time, table error / {} error = {:.3f}; "
                       "at the table's error, {} time / table time = {}\n",
                       label, r->fisSetting, r->tableName, compared, atBudget, r->fisFamily == "fis" ? "FIS" : "FIS-mix",
                       r->errorAtTableTime, r->fisFamily == "fis" ? "FIS" : "FIS-mix", time);
}

nlohmann::json tablesJson(const std::vector<TableVersusFis>& tables) {
    nlohmann::json list = nlohmann::json::array();
    for (const TableVersusFis& t : tables)
        list.push_back(
            {{"table", t.table},
             {"error", t.error},
             {"gpu_ms", t.gpuMs},
             {"error_at_table_time", t.errorAtTableTime},
             {"fis_time_at_table_error", t.fisTimeAtTableError ? nlohmann::json(*t.fisTimeAtTableError) : nlohmann::json(nullptr)}});
    return list;
}

nlohmann::json ratiosJson(const std::optional<Ratios>& r) {
    if (!r) return nullptr;
    return {{"fis_setting", r->fisSetting},
            {"fis_family", r->fisFamily},
            {"fis_compared", r->fisCompared},
            {"table", r->tableName},
            {"table_within_fis32_time", r->tableWithinFis32Time},
            {"table_ms", r->tableMs},
            {"fis32_ms", r->fis32Ms},
            {"error_at_fis32_time", r->errorAtFis32Time},
            {"error_at_table_time", r->errorAtTableTime},
            {"fis_time_at_table_error", r->timeAtTableError ? nlohmann::json(*r->timeAtTableError) : nlohmann::json(nullptr)},
            {"fis_max_samples", r->fisMaxSamples}};
}

std::vector<TableVersusFis> tablesVersusFis(const std::vector<MethodScore>& scores, const std::string& setting, bool impulse) {
    std::vector<TableVersusFis> result;
    const std::vector<MethodScore> curve = fisCurve(scores, "fis", setting);
    if (curve.empty()) return result;
    for (const MethodScore& s : scores) {
        if (s.method.family != "table") continue;
        TableVersusFis t{s.method.name, errorOf(s, impulse), s.gpuMs, errorOf(s, impulse) / fisErrorAtTime(curve, s.gpuMs, impulse), {}};
        if (const std::optional<double> ms = fisTimeAtError(curve, t.error, impulse)) t.fisTimeAtTableError = *ms / s.gpuMs;
        result.push_back(t);
    }
    std::sort(result.begin(), result.end(), [](const TableVersusFis& a, const TableVersusFis& b) { return a.gpuMs < b.gpuMs; });
    return result;
}

} // namespace

SweepSummary summarizeSweep(const std::vector<SweepRow>& rows) {
    SweepSummary summary;
    summary.images = score(rows, false);
    summary.impulses = score(rows, true);
    // The best single FIS setting over the image probes: lowest geometric mean error over N.
    std::map<std::string, std::pair<double, int>> logSums;
    for (const MethodScore& s : summary.images.empty() ? summary.impulses : summary.images)
        if (s.method.family == "fis") {
            auto& [sum, n] = logSums[fisSetting(s.method)];
            sum += std::log(std::max(errorOf(s, summary.images.empty()), 1e-12));
            ++n;
        }
    double best = 1e300;
    for (const auto& [setting, sum] : logSums)
        if (sum.first / sum.second < best) {
            best = sum.first / sum.second;
            summary.bestFisSetting = setting;
        }
    if (!summary.images.empty()) {
        summary.best = ratios(summary.images, "fis", summary.bestFisSetting, false);
        summary.paper = ratios(summary.images, "fis", "bias 1, box", false);
        summary.bestMix = ratios(summary.images, "fis-mix", summary.bestFisSetting, false);
    }
    summary.tableImages = tablesVersusFis(summary.images, summary.bestFisSetting, false);
    summary.tableImpulses = tablesVersusFis(summary.impulses, summary.bestFisSetting, true);
    if (!summary.impulses.empty()) {
        summary.impulseBest = ratios(summary.impulses, "fis", summary.bestFisSetting, true);
        summary.impulseBestMix = ratios(summary.impulses, "fis-mix", summary.bestFisSetting, true);
    }
    return summary;
}

void writeSweepCsv(const std::filesystem::path& path, const std::vector<SweepRow>& rows) {
    std::ofstream out(path);
    out << "method,family,count,bias,pyramid,form,probe,level,image_l1,impulse_l1_mean,impulse_l1_max,gpu_ms,level_gpu_ms\n";
    for (const SweepRow& r : rows)
        out << fmt::format("{},{},{},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", r.method.name, r.method.family, r.method.count,
                           r.method.bias, r.method.pyramid, r.method.form, r.probe, r.level, r.imageL1, r.impulseL1Mean, r.impulseL1Max,
                           r.gpuMs, r.levelGpuMs);
    if (!out) throw probe::ProbeError(fmt::format("{}: cannot write", path.string()));
}

std::string formatSummary(const SweepSummary& summary) {
    std::string s = fmt::format("best FIS setting over the image probes: {}\n", summary.bestFisSetting);
    s += formatRatios(summary.best, "images, best FIS");
    s += formatRatios(summary.paper, "images, paper's FIS");
    s += formatRatios(summary.impulseBest, "impulses, best FIS");
    s += formatRatios(summary.bestMix, "images, best FIS per-level mix");
    s += formatRatios(summary.impulseBestMix, "impulses, best FIS per-level mix");
    return s;
}

void writeSweepMarkdown(const std::filesystem::path& path, const SweepSummary& summary, const std::vector<SweepRow>& rows,
                        const std::string& device, int size, int levelCount) {
    std::ofstream out(path);
    out << fmt::format("# Sweep: {}^2, {} levels (glTF), on {}\n\n", size, levelCount, device);
    out << "Errors are means over levels >= 1 (level 0 is a copy for every method); image L1 over the non-impulse probes, "
           "impulse L1 over stratified output texels; GPU time covers all levels (both passes), the median of the repeats "
           "on one probe (it does not depend on the content).\n\n";
    out << "```\n" << formatSummary(summary) << "```\n\n";
    out << fmt::format("Each table against uniform FIS at the best setting ({}), interpolated in log error against log time: "
                       "its error over FIS's at the table's time, and FIS's time over the table's at the table's error.\n\n",
                       summary.bestFisSetting);
    out << "| table | GPU ms | image L1 | / FIS's at that time | FIS time at that error | impulse L1 | / FIS's at that time | FIS time at "
           "that error |\n"
           "|---|---|---|---|---|---|---|---|\n";
    const auto timeText = [](const std::optional<double>& x) { return x ? fmt::format("{:.2f}x", *x) : std::string("never"); };
    for (std::size_t k = 0; k < summary.tableImages.size(); ++k) {
        const TableVersusFis& image = summary.tableImages[k];
        const auto impulse = std::find_if(summary.tableImpulses.begin(), summary.tableImpulses.end(),
                                          [&](const TableVersusFis& t) { return t.table == image.table; });
        out << fmt::format("| {} | {:.2f} | {:.4f} | {:.3f} | {} |", image.table, image.gpuMs, image.error, image.errorAtTableTime,
                           timeText(image.fisTimeAtTableError));
        out << (impulse == summary.tableImpulses.end() ? std::string(" - | - | - |\n")
                                                       : fmt::format(" {:.4f} | {:.3f} | {} |\n", impulse->error, impulse->errorAtTableTime,
                                                                     timeText(impulse->fisTimeAtTableError)));
    }
    out << "\n| method | family | taps/samples | bias | pyramid | image L1 | impulse L1 | GPU ms |\n|---|---|---|---|---|---|---|---|\n";
    for (const MethodScore& s : summary.images.empty() ? summary.impulses : summary.images)
        out << fmt::format("| {} | {} | {} | {} | {} | {:.4f} | {:.4f} | {:.3f} |\n", s.method.name, s.method.family, s.method.count,
                           s.method.family != "table" ? fmt::format("{}", s.method.bias) : "-", s.method.pyramid, s.imageL1, s.impulseL1,
                           s.gpuMs);
    out << fmt::format("\n{} rows in sweep.csv.\n", rows.size());
    if (!out) throw probe::ProbeError(fmt::format("{}: cannot write", path.string()));
}

nlohmann::json sweepSummaryJson(const SweepSummary& summary, const std::string& device, const std::string& driver, int size,
                                int levelCount) {
    nlohmann::json methods = nlohmann::json::array();
    for (const MethodScore& s : summary.images.empty() ? summary.impulses : summary.images)
        methods.push_back({{"method", s.method.name}, {"image_l1", s.imageL1}, {"impulse_l1", s.impulseL1}, {"gpu_ms", s.gpuMs}});
    return {{"command", "sweep"},
            {"device", {{"name", device}, {"driver", driver}}},
            {"face_size", size},
            {"level_count", levelCount},
            {"best_fis_setting", summary.bestFisSetting},
            {"images_best_fis", ratiosJson(summary.best)},
            {"images_paper_fis", ratiosJson(summary.paper)},
            {"impulses_best_fis", ratiosJson(summary.impulseBest)},
            {"images_best_fis_mix", ratiosJson(summary.bestMix)},
            {"impulses_best_fis_mix", ratiosJson(summary.impulseBestMix)},
            {"tables_images", tablesJson(summary.tableImages)},
            {"tables_impulses", tablesJson(summary.tableImpulses)},
            {"methods", methods}};
}

} // namespace probefilter
