#include "sweep_summary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/input_file.h"
#include "probe/output_file.h"

namespace probefilter {

namespace {

bool isImpulse(const std::string& probe) { return probe.rfind("impulse", 0) == 0; }

std::string fisSetting(const SweepMethod& m) { return fmt::format("bias {}, {}", m.bias, m.pyramid); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

std::vector<MethodScore> score(const std::vector<SweepRow>& rows, bool impulses, int firstLevel) {
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
        if (r.level < firstLevel) continue; // a mirror level 0 is a copy for every method
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

// log(y) interpolated in log(x) between (x0, y0) and (x1, y1) at x.
double logLogInterpolate(double x0, double y0, double x1, double y1, double x) {
    const double t = x1 == x0 ? 1.0 : (std::log(x) - std::log(x0)) / (std::log(x1) - std::log(x0));
    return std::exp(std::log(y0) + t * (std::log(y1) - std::log(y0)));
}

// The most accurate table within `budget` ms; null where none is.
const MethodScore* mostAccurateTableWithin(const std::vector<MethodScore>& scores, double budget, bool impulse) {
    const MethodScore* best = nullptr;
    for (const MethodScore& s : scores)
        if (s.method.family == "table" && s.gpuMs <= budget && (!best || errorOf(s, impulse) < errorOf(*best, impulse))) best = &s;
    return best;
}

const MethodScore* fastestTable(const std::vector<MethodScore>& scores) {
    const MethodScore* fastest = nullptr;
    for (const MethodScore& s : scores)
        if (s.method.family == "table" && (!fastest || s.gpuMs < fastest->gpuMs)) fastest = &s;
    return fastest;
}

// The most accurate table within the time of uniform FIS-32 at `setting` (else the fastest table)
// against the front.
std::optional<Ratios> ratios(const std::vector<MethodScore>& scores, const std::vector<MethodScore>& front, const std::string& setting,
                             bool impulse) {
    const auto fis32 = std::find_if(scores.begin(), scores.end(), [&](const MethodScore& s) {
        return s.method.family == "fis" && s.method.count == 32 && fisSetting(s.method) == setting;
    });
    if (fis32 == scores.end() || front.empty()) return std::nullopt;
    const MethodScore* table = mostAccurateTableWithin(scores, fis32->gpuMs, impulse);
    Ratios r;
    r.tableWithinFis32Time = table != nullptr;
    if (!table) table = fastestTable(scores);
    if (!table) return std::nullopt;
    r.fis32 = fis32->method.name;
    r.tableName = table->method.name;
    r.tableMs = table->gpuMs;
    r.fis32Ms = fis32->gpuMs;
    r.tableError = errorOf(*table, impulse);
    r.fis32Error = errorOf(*fis32, impulse);
    r.frontErrorAtFis32Time = frontErrorAtTime(front, fis32->gpuMs, impulse);
    r.errorAtFis32Time = r.tableError / r.frontErrorAtFis32Time;
    r.errorAtTableTime = r.tableError / frontErrorAtTime(front, table->gpuMs, impulse);
    if (const std::optional<double> ms = frontTimeAtError(front, r.tableError, impulse)) r.timeAtTableError = *ms / table->gpuMs;
    r.frontMostAccurate = front.back().method.name;
    return r;
}

std::string formatRatios(const std::optional<Ratios>& r, const std::string& label) {
    if (!r) return fmt::format("{}: not measured (no table, no FIS-32 at the best setting or no FIS in the sweep)\n", label);
    const std::string time = r->timeAtTableError ? fmt::format("{:.2f}x", *r->timeAtTableError)
                                                 : fmt::format("never ({} is the front's end)", r->frontMostAccurate);
    const std::string table = r->tableWithinFis32Time
                                  ? fmt::format("table {} ({:.2f} ms, the most accurate within it)", r->tableName, r->tableMs)
                                  : fmt::format("no table is as fast; the fastest, {} ({:.2f} ms)", r->tableName, r->tableMs);
    return fmt::format(
        "{}: at FIS-32's time ({}, {:.2f} ms), {}: table error {:.4f} / FIS front's {:.4f} = {:.3f} (FIS-32 itself: {:.4f}); "
        "at the table's time, table error / front's = {:.3f}; at the table's error, front's time / table's = {}\n",
        label, r->fis32, r->fis32Ms, table, r->tableError, r->frontErrorAtFis32Time, r->errorAtFis32Time, r->fis32Error,
        r->errorAtTableTime, time);
}

nlohmann::json optionalJson(const std::optional<double>& x) { return x ? nlohmann::json(*x) : nlohmann::json(nullptr); }

nlohmann::json tablesJson(const std::vector<TableVersusFis>& tables) {
    nlohmann::json list = nlohmann::json::array();
    for (const TableVersusFis& t : tables)
        list.push_back({{"table", t.table},
                        {"error", t.error},
                        {"gpu_ms", t.gpuMs},
                        {"reads_per_texel", t.readsPerTexel},
                        {"error_at_table_time", t.errorAtTableTime},
                        {"fis_time_at_table_error", optionalJson(t.fisTimeAtTableError)}});
    return list;
}

nlohmann::json ratiosJson(const std::optional<Ratios>& r) {
    if (!r) return nullptr;
    return {{"fis32", r->fis32},
            {"fis32_ms", r->fis32Ms},
            {"fis32_error", r->fis32Error},
            {"table", r->tableName},
            {"table_within_fis32_time", r->tableWithinFis32Time},
            {"table_ms", r->tableMs},
            {"table_error", r->tableError},
            {"front_error_at_fis32_time", r->frontErrorAtFis32Time},
            {"error_at_fis32_time", r->errorAtFis32Time},
            {"error_at_table_time", r->errorAtTableTime},
            {"fis_time_at_table_error", optionalJson(r->timeAtTableError)},
            {"front_most_accurate", r->frontMostAccurate}};
}

nlohmann::json frontJson(const std::vector<MethodScore>& front, bool impulse) {
    nlohmann::json list = nlohmann::json::array();
    for (const MethodScore& s : front) list.push_back({{"method", s.method.name}, {"gpu_ms", s.gpuMs}, {"error", errorOf(s, impulse)}});
    return list;
}

std::vector<TableVersusFis> tablesVersusFront(const std::vector<MethodScore>& scores, const std::vector<MethodScore>& front, bool impulse) {
    std::vector<TableVersusFis> result;
    if (front.empty()) return result;
    for (const MethodScore& s : scores) {
        if (s.method.family != "table" && s.method.family != "ggx-levels") continue;
        TableVersusFis t{s.method.name, errorOf(s, impulse), s.gpuMs, s.method.readsPerTexel, 0.0, {}};
        t.errorAtTableTime = t.error / frontErrorAtTime(front, s.gpuMs, impulse);
        if (const std::optional<double> ms = frontTimeAtError(front, t.error, impulse)) t.fisTimeAtTableError = *ms / s.gpuMs;
        result.push_back(t);
    }
    std::sort(result.begin(), result.end(), [](const TableVersusFis& a, const TableVersusFis& b) { return a.gpuMs < b.gpuMs; });
    return result;
}

} // namespace

bool isFisFamily(const std::string& family) { return family == "fis" || family == "fis-mix" || family == "fis-paraboloid"; }

std::vector<MethodScore> fisFront(const std::vector<MethodScore>& scores, bool impulse) {
    std::vector<MethodScore> fis;
    for (const MethodScore& s : scores)
        if (isFisFamily(s.method.family)) fis.push_back(s);
    // By time, the more accurate first among equal times: a point joins the front when it beats
    // every faster one.
    std::sort(fis.begin(), fis.end(), [&](const MethodScore& a, const MethodScore& b) {
        return a.gpuMs != b.gpuMs ? a.gpuMs < b.gpuMs : errorOf(a, impulse) < errorOf(b, impulse);
    });
    std::vector<MethodScore> front;
    for (const MethodScore& s : fis)
        if (front.empty() || errorOf(s, impulse) < errorOf(front.back(), impulse)) front.push_back(s);
    return front;
}

double frontErrorAtTime(const std::vector<MethodScore>& front, double ms, bool impulse) {
    if (ms <= front.front().gpuMs) return errorOf(front.front(), impulse);
    for (std::size_t k = 1; k < front.size(); ++k)
        if (front[k].gpuMs >= ms)
            return logLogInterpolate(front[k - 1].gpuMs, errorOf(front[k - 1], impulse), front[k].gpuMs, errorOf(front[k], impulse), ms);
    return errorOf(front.back(), impulse);
}

std::optional<double> frontTimeAtError(const std::vector<MethodScore>& front, double error, bool impulse) {
    for (std::size_t k = 0; k < front.size(); ++k) {
        if (errorOf(front[k], impulse) > error) continue;
        if (k == 0) return front[0].gpuMs;
        return logLogInterpolate(errorOf(front[k - 1], impulse), front[k - 1].gpuMs, errorOf(front[k], impulse), front[k].gpuMs, error);
    }
    return std::nullopt;
}

SweepSummary summarizeSweep(const std::vector<SweepRow>& rows, int firstLevel) {
    SweepSummary summary;
    summary.images = score(rows, false, firstLevel);
    summary.impulses = score(rows, true, firstLevel);
    // The best single uniform FIS setting over the image probes (lowest geometric mean error over
    // N): its FIS-32 sets the time budget.
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
    summary.imageFront = fisFront(summary.images, false);
    summary.impulseFront = fisFront(summary.impulses, true);
    summary.imageRatios = ratios(summary.images, summary.imageFront, summary.bestFisSetting, false);
    summary.impulseRatios = ratios(summary.impulses, summary.impulseFront, summary.bestFisSetting, true);
    summary.tableImages = tablesVersusFront(summary.images, summary.imageFront, false);
    summary.tableImpulses = tablesVersusFront(summary.impulses, summary.impulseFront, true);
    return summary;
}

namespace {
constexpr const char* kCsvHeader = "method,family,count,bias,pyramid,form,reads_per_texel,shader_taps_per_texel,probe,level,image_l1,"
                                   "impulse_l1_mean,impulse_l1_max,gpu_ms,level_gpu_ms";
}

void writeSweepCsv(const std::filesystem::path& path, const std::vector<SweepRow>& rows) {
    std::ostringstream out;
    out << kCsvHeader << "\n";
    for (const SweepRow& r : rows)
        out << fmt::format("{},{},{},{},{},{},{:.6g},{:.6g},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", r.method.name, r.method.family,
                           r.method.count, r.method.bias, r.method.pyramid, r.method.form, r.method.readsPerTexel,
                           r.method.shaderTapsPerTexel, r.probe, r.level, r.imageL1, r.impulseL1Mean, r.impulseL1Max, r.gpuMs,
                           r.levelGpuMs);
    probe::writeFile(path, out.str());
}

std::vector<SweepRow> readSweepCsv(const std::filesystem::path& path) {
    std::istringstream in(probe::readTextFile(path)); // a regular file, bounded in size
    std::string line;
    if (!std::getline(in, line) || line != kCsvHeader)
        throw probe::ProbeError(fmt::format("{}: not a sweep.csv of this version (header differs)", path.string()));
    std::vector<SweepRow> rows;
    for (int number = 2; std::getline(in, line); ++number) {
        std::vector<std::string> f;
        std::stringstream fields(line);
        for (std::string field; std::getline(fields, field, ',');) f.push_back(field);
        const auto bad = [&](const std::string& problem) {
            return probe::ProbeError(fmt::format("{}: line {}: {}", path.string(), number, problem));
        };
        if (f.size() != 15) throw bad(fmt::format("{} fields, expected 15", f.size()));
        try {
            std::size_t used = 0;
            const auto toNumber = [&](const std::string& text) {
                const double x = std::stod(text, &used);
                if (used != text.size() || !std::isfinite(x)) throw std::invalid_argument(text);
                return x;
            };
            SweepRow r;
            r.method = {f[0], f[1], static_cast<int>(toNumber(f[2])), toNumber(f[3]), f[4], f[5], toNumber(f[6]), toNumber(f[7])};
            r.probe = f[8];
            r.level = static_cast<int>(toNumber(f[9]));
            r.imageL1 = toNumber(f[10]);
            r.impulseL1Mean = toNumber(f[11]);
            r.impulseL1Max = toNumber(f[12]);
            r.gpuMs = toNumber(f[13]);
            r.levelGpuMs = toNumber(f[14]);
            if (r.gpuMs <= 0.0 || r.level < 0) throw std::invalid_argument("range");
            rows.push_back(r);
        } catch (const std::logic_error&) {
            throw bad("a number field is not a finite number (or a time is not positive)");
        }
    }
    if (rows.empty()) throw probe::ProbeError(fmt::format("{}: no rows", path.string()));
    return rows;
}

std::string formatSummary(const SweepSummary& summary) {
    std::string s = fmt::format("FIS: the Pareto front of every FIS method in the sweep, per error measure; FIS-32 at the best "
                                "setting over the image probes ({}) sets the time budget\n",
                                summary.bestFisSetting);
    s += formatRatios(summary.imageRatios, "images");
    s += formatRatios(summary.impulseRatios, "impulses");
    return s;
}

void writeSweepMarkdown(const std::filesystem::path& path, const SweepSummary& summary, const std::vector<SweepRow>& rows,
                        const std::string& device, const SweepShape& shape, const nlohmann::json& header) {
    std::ostringstream out;
    out << fmt::format("# Sweep: {}^2, {} levels (glTF), {} lobe, on {}\n\n", shape.size, shape.levelCount, shape.lobe, device);
    out << fmt::format("Written by `{}` on {}.\n\n", header.at("command_line").get<std::string>(), header.at("date").get<std::string>());
    const std::string levels = shape.firstLevel > 0 ? "levels >= 1 (level 0 is a copy for every method)" : "every level";
    out << fmt::format("Errors are means over {}; image L1 over the non-impulse probes, impulse L1 over stratified output texels, "
                       "against the exact {} reference; GPU time covers all levels (both passes), the median of the repeats on one "
                       "probe (it does not depend on the content); reads are trilinear pyramid reads per output texel of those levels "
                       "(a table's taps in every frame the texel blends; FIS's samples).\n\n",
                       levels, shape.lobe);
    if (shape.lobe != "ggx")
        out << "The `ggx-levels` methods are what engines read in place of the lobe's own levels: the GGX table's levels at "
               "the same roughness (Filament's sheen), measured against this lobe.\n\n";
    out << "FIS is the Pareto front of every FIS method below, per error measure: at each time the lowest error any FIS "
           "variant reaches, interpolated between its points in log error against log time (outside them, the nearer end).\n\n";
    out << "```\n" << formatSummary(summary) << "```\n\n";
    out << "Each table (and stand-in) against the FIS front: its error over the front's at the table's time, and the front's "
           "time over the table's at the table's error.\n\n";
    out << "| table | GPU ms | reads/texel | image L1 | / front's at that time | front's time at that error | impulse L1 | / front's at "
           "that time | front's time at that error |\n"
           "|---|---|---|---|---|---|---|---|---|\n";
    const auto timeText = [](const std::optional<double>& x) { return x ? fmt::format("{:.2f}x", *x) : std::string("never"); };
    for (const TableVersusFis& image : summary.tableImages) {
        const auto impulse = std::find_if(summary.tableImpulses.begin(), summary.tableImpulses.end(),
                                          [&](const TableVersusFis& t) { return t.table == image.table; });
        out << fmt::format("| {} | {:.2f} | {:.1f} | {:.4f} | {:.3f} | {} |", image.table, image.gpuMs, image.readsPerTexel, image.error,
                           image.errorAtTableTime, timeText(image.fisTimeAtTableError));
        out << (impulse == summary.tableImpulses.end() ? std::string(" - | - | - |\n")
                                                       : fmt::format(" {:.4f} | {:.3f} | {} |\n", impulse->error, impulse->errorAtTableTime,
                                                                     timeText(impulse->fisTimeAtTableError)));
    }
    for (const bool impulse : {false, true}) {
        const std::vector<MethodScore>& front = impulse ? summary.impulseFront : summary.imageFront;
        out << fmt::format("\nThe FIS front, {}: ", impulse ? "impulse L1" : "image L1");
        for (std::size_t k = 0; k < front.size(); ++k)
            out << fmt::format("{}{} ({:.2f} ms, {:.4f})", k ? ", " : "", front[k].method.name, front[k].gpuMs, errorOf(front[k], impulse));
        out << ".\n";
    }
    out << "\n| method | family | taps/samples | bias | pyramid | reads/texel | image L1 | impulse L1 | GPU ms |\n"
           "|---|---|---|---|---|---|---|---|---|\n";
    for (const MethodScore& s : summary.images.empty() ? summary.impulses : summary.images)
        out << fmt::format("| {} | {} | {} | {} | {} | {:.1f} | {:.4f} | {:.4f} | {:.3f} |\n", s.method.name, s.method.family,
                           s.method.count, isFisFamily(s.method.family) ? fmt::format("{}", s.method.bias) : "-", s.method.pyramid,
                           s.method.readsPerTexel, s.imageL1, s.impulseL1, s.gpuMs);
    out << fmt::format("\n{} rows in sweep.csv.\n", rows.size());
    probe::writeFile(path, out.str());
}

nlohmann::json sweepSummaryJson(const SweepSummary& summary, const std::string& device, const std::string& driver,
                                const SweepShape& shape) {
    nlohmann::json methods = nlohmann::json::array();
    for (const MethodScore& s : summary.images.empty() ? summary.impulses : summary.images)
        methods.push_back({{"method", s.method.name},
                           {"family", s.method.family},
                           {"count", s.method.count},
                           {"bias", s.method.bias},
                           {"pyramid", s.method.pyramid},
                           {"form", s.method.form},
                           {"reads_per_texel", s.method.readsPerTexel},
                           {"shader_taps_per_texel", s.method.shaderTapsPerTexel},
                           {"image_l1", s.imageL1},
                           {"impulse_l1", s.impulseL1},
                           {"gpu_ms", s.gpuMs}});
    return {{"command", "sweep"},
            {"device", {{"name", device}, {"driver", driver}}},
            {"face_size", shape.size},
            {"level_count", shape.levelCount},
            {"lobe", shape.lobe},
            {"first_level", shape.firstLevel},
            {"best_fis_setting", summary.bestFisSetting},
            {"images", ratiosJson(summary.imageRatios)},
            {"impulses", ratiosJson(summary.impulseRatios)},
            {"fis_front_images", frontJson(summary.imageFront, false)},
            {"fis_front_impulses", frontJson(summary.impulseFront, true)},
            {"tables_images", tablesJson(summary.tableImages)},
            {"tables_impulses", tablesJson(summary.tableImpulses)},
            {"methods", methods}};
}

} // namespace probefilter
