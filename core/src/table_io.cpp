#include "probe/table_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "probe/error.h"
#include "probe/input_file.h"
#include "probe/json_input.h"
#include "probe/output_file.h"

namespace probe {

namespace {

using nlohmann::json;

constexpr std::string_view kFormatName = "probefilter-tap-table";
// Version 2 names the face size "faceSize"; version 1 called it "baseSize" and is still read.
constexpr int kFormatVersion = 2;

json errorToJson(const ImpulseError& e) { return {{"mean", e.mean}, {"max", e.max}, {"worst", {e.worst.face, e.worst.i, e.worst.j}}}; }

// Field access that names the file and the field in every error.
struct Reader {
    const std::filesystem::path& path;

    [[noreturn]] void fail(std::string_view key, const std::string& problem) const {
        throw ProbeError(fmt::format("{}: field '{}' {}", path.string(), key, problem));
    }
    const json& field(const json& object, std::string_view key) const {
        if (!object.is_object()) throw ProbeError(fmt::format("{}: expected an object where '{}' should be", path.string(), key));
        const auto it = object.find(key);
        if (it == object.end()) throw ProbeError(fmt::format("{}: missing field '{}'", path.string(), key));
        return *it;
    }
    // Every key of `object` must be one of `known`.
    void refuseUnknown(const json& object, std::initializer_list<std::string_view> known, std::string_view where) const {
        for (const auto& [key, value] : object.items())
            if (std::find(known.begin(), known.end(), key) == known.end())
                throw ProbeError(fmt::format("{}: unknown field '{}{}'", path.string(), where, key.substr(0, 64)));
    }
    // Numbers are checked, not converted blindly: ints must be integers within int's range.
    template <typename T>
    T get(const json& object, std::string_view key) const {
        const json& value = field(object, key);
        if constexpr (std::is_same_v<T, int>) {
            const std::optional<int> v = jsonInt(value);
            if (!v) fail(key, fmt::format("is {}, not an integer within int's range", describeJson(value)));
            return *v;
        } else if constexpr (std::is_same_v<T, double>) {
            if (!value.is_number()) fail(key, fmt::format("is {}, not a number", describeJson(value)));
            return value.get<double>();
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
            if (!value.is_array()) fail(key, fmt::format("is {}, not an array of numbers", describeJson(value)));
            std::vector<double> out;
            out.reserve(value.size());
            for (const json& v : value) {
                if (!v.is_number()) fail(key, fmt::format("holds {}, not a number", describeJson(v)));
                out.push_back(v.get<double>());
            }
            return out;
        } else {
            try {
                return value.get<T>();
            } catch (const json::exception&) {
                fail(key, fmt::format("is {}, the wrong type", describeJson(value)));
            }
        }
    }
    // Parsers of names throw ProbeError without the file; add it.
    template <typename Parse>
    auto name(const json& object, std::string_view key, Parse parse) const {
        const std::string value = get<std::string>(object, key);
        try {
            return parse(value);
        } catch (const ProbeError& e) {
            throw ProbeError(fmt::format("{}: field '{}': {}", path.string(), key, e.what()));
        }
    }
    ImpulseError error(const json& object, std::string_view key) const {
        const json& e = field(object, key);
        ImpulseError out;
        out.mean = get<double>(e, "mean");
        out.max = get<double>(e, "max");
        const json& worst = field(e, "worst");
        std::optional<int> face, i, j;
        if (worst.is_array() && worst.size() == 3) face = jsonInt(worst[0]), i = jsonInt(worst[1]), j = jsonInt(worst[2]);
        if (!face || !i || !j) throw ProbeError(fmt::format("{}: field '{}.worst' is not [face, i, j]", path.string(), key));
        out.worst = {*face, *i, *j};
        refuseUnknown(e, {"mean", "max", "worst"}, fmt::format("{}.", key));
        return out;
    }
};

// A float literal that round-trips float32 and is a float in both C++ and GLSL ("1.0f", "2.5e-05f").
std::string floatLiteral(float value) {
    std::string text = fmt::format("{:.9g}", value);
    if (text.find_first_of(".e") == std::string::npos) text += ".0";
    return text + "f";
}

std::string floatList(const std::vector<float>& values, int perLine, std::string_view open, std::string_view close) {
    std::string out;
    for (std::size_t k = 0; k < values.size(); k += 4) {
        if (k % (4 * static_cast<std::size_t>(perLine)) == 0) out += "\n   ";
        out += fmt::format(" {}{}, {}, {}, {}{},", open, floatLiteral(values[k]), floatLiteral(values[k + 1]), floatLiteral(values[k + 2]),
                           floatLiteral(values[k + 3]), close);
    }
    if (!out.empty()) out.pop_back();
    return out;
}

std::vector<float> publishedLayout(const TapTable& table) {
    std::vector<float> all;
    for (int m = 0; m < table.levelCount; ++m) {
        const std::vector<float> level = publishedLevelLayout(table, m);
        all.insert(all.end(), level.begin(), level.end());
    }
    return all;
}

std::vector<int> tapGroups(const TapTable& table) {
    std::vector<int> groups;
    for (int m = 0; m < table.levelCount; ++m) groups.push_back((tapsInUse(table, m) + 3) / 4);
    return groups;
}

std::vector<int> fisSamples(const TapTable& table) {
    std::vector<int> samples;
    for (const TableLevel& level : table.levels) samples.push_back(level.fisSamples);
    return samples;
}

std::string commentBlock(const TapTable& table) {
    std::string out;
    for (const std::string& line : tableSummary(table)) out += "// " + line + "\n";
    return out;
}

} // namespace

std::string tableToJson(const TapTable& table) {
    validateTable(table, "tap table");
    json levels = json::array();
    for (int m = 0; m < table.levelCount; ++m) {
        const TableLevel& level = table.levels[m];
        json entry = {{"level", m},
                      {"alpha", tableLevelAlpha(table, m)},
                      {"stratified", errorToJson(level.stratified)},
                      {"all", errorToJson(level.all)},
                      {"minWeightSum", level.minWeightSum}};
        if (level.fisSamples > 0) entry["fisSamples"] = level.fisSamples; // levels the table filters name none
        entry["coefficients"] = level.coefficients;
        levels.push_back(std::move(entry));
    }
    json j = {{"format", kFormatName},
              {"version", kFormatVersion},
              {"layout", "coefficients[frame][tap][parameter: dir x, dir y, dir z, level, weight][coefficient]"},
              {"faceSize", table.faceSize},
              {"levelCount", table.levelCount},
              {"taps", table.taps},
              {"form", tableFormName(table.form)},
              {"mapping", roughnessMappingName(table.mapping)},
              {"pyramid", {{"kind", pyramidKindName(table.pyramid.kind)}, {"weighting", pyramidWeightingName(table.pyramid.weighting)}}},
              {"solver", table.solver},
              {"stratifiedBudget", table.stratifiedBudget},
              {"fitSeconds", table.fitSeconds},
              {"levels", levels}};
    if (table.seamWeight > 0.0) j["seamWeight"] = table.seamWeight; // tables from before the seam term have none
    if (table.lobe != Lobe::ggx) j["lobe"] = lobeName(table.lobe);  // GGX tables name none
    if (table.mapping.curve() == RoughnessMapping::Curve::custom) j["roughness"] = table.mapping.list();
    return j.dump(1) + "\n";
}

// "mapping": a named curve, or "custom" with the list in "roughness".
RoughnessMapping tableMapping(const Reader& r, const json& j) {
    if (r.get<std::string>(j, "mapping") != "custom") {
        if (j.contains("roughness")) r.fail("roughness", "is given with a named mapping (expected \"mapping\": \"custom\")");
        return r.name(j, "mapping", parseRoughnessMapping);
    }
    return RoughnessMapping::custom(r.get<std::vector<double>>(j, "roughness"));
}

TapTable tableFromJson(std::string_view text, const std::filesystem::path& path) {
    const json j = parseJsonFile(text, path, "table file");
    const Reader r{path};
    if (r.get<std::string>(j, "format") != kFormatName) throw ProbeError(fmt::format("{}: not a {} file", path.string(), kFormatName));
    const int version = r.get<int>(j, "version");
    if (version != 1 && version != kFormatVersion)
        throw ProbeError(fmt::format("{}: table format version {} (this build reads 1 and {})", path.string(), version, kFormatVersion));
    const char* faceSizeKey = version == 1 ? "baseSize" : "faceSize";
    r.refuseUnknown(j,
                    {"format", "version", "layout", faceSizeKey, "levelCount", "taps", "form", "mapping", "pyramid", "solver",
                     "stratifiedBudget", "fitSeconds", "seamWeight", "roughness", "lobe", "levels"},
                    "");
    if (version == 1)
        printToStderr(fmt::format(
            "note: {}: table format version 1; version 2 names \"baseSize\" \"faceSize\" (probefit export rewrites it)\n", path.string()));
    const json& pyramid = r.field(j, "pyramid");
    r.refuseUnknown(pyramid, {"kind", "weighting"}, "pyramid.");
    TapTable table;
    try {
        table = emptyTable(r.get<int>(j, faceSizeKey), r.get<int>(j, "levelCount"), r.get<int>(j, "taps"),
                           r.name(j, "form", parseTableForm), tableMapping(r, j),
                           {r.name(pyramid, "kind", parsePyramidKind), r.name(pyramid, "weighting", parsePyramidWeighting)});
    } catch (const ProbeError& e) {
        const std::string message = e.what();
        if (message.starts_with(path.string())) throw;
        throw ProbeError(fmt::format("{}: {}", path.string(), message));
    }
    table.solver = r.get<std::string>(j, "solver");
    table.stratifiedBudget = r.get<int>(j, "stratifiedBudget");
    if (table.stratifiedBudget < 24)
        r.fail("stratifiedBudget", fmt::format("is {}, fewer than the 24 corner texels", table.stratifiedBudget));
    table.fitSeconds = r.get<double>(j, "fitSeconds");
    if (j.contains("seamWeight")) table.seamWeight = r.get<double>(j, "seamWeight");
    if (j.contains("lobe")) table.lobe = r.name(j, "lobe", parseLobe);
    const json& levels = r.field(j, "levels");
    if (!levels.is_array() || levels.size() != static_cast<std::size_t>(table.levelCount))
        throw ProbeError(fmt::format("{}: 'levels' must list {} levels", path.string(), table.levelCount));
    for (int m = 0; m < table.levelCount; ++m) {
        const json& level = levels[static_cast<std::size_t>(m)];
        if (r.get<int>(level, "level") != m) throw ProbeError(fmt::format("{}: levels out of order at entry {}", path.string(), m));
        r.refuseUnknown(level, {"level", "alpha", "stratified", "all", "minWeightSum", "fisSamples", "coefficients"},
                        fmt::format("levels[{}].", m));
        TableLevel& out = table.levels[m];
        out.coefficients = r.get<std::vector<double>>(level, "coefficients");
        out.stratified = r.error(level, "stratified");
        out.all = r.error(level, "all");
        out.minWeightSum = r.get<double>(level, "minWeightSum");
        if (level.contains("fisSamples")) out.fisSamples = r.get<int>(level, "fisSamples");
    }
    validateTableValues(table, path.string());
    return table;
}

TapTable readTable(const std::filesystem::path& path) { return tableFromJson(readTextFile(path), path); }

TapTable importPublishedTable(const std::filesystem::path& path, int faceSize, int levelCount, int taps, TableForm form,
                              const RoughnessMapping& mapping, PyramidSettings pyramid) {
    TapTable table = emptyTable(faceSize, levelCount, taps, form, mapping, pyramid);
    const std::string text = readTextFile(path);
    std::vector<double> numbers;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const unsigned char ch = static_cast<unsigned char>(text[pos]);
        if (std::isspace(ch) || ch == ',') {
            ++pos;
            continue;
        }
        double value = 0.0;
        const auto [end, ec] = std::from_chars(text.data() + pos, text.data() + text.size(), value);
        if (ec != std::errc() || end == text.data() + pos)
            throw ProbeError(fmt::format("{}: not a number at byte {} ('{}')", path.string(), pos, text.substr(pos, 12)));
        numbers.push_back(value);
        pos = static_cast<std::size_t>(end - text.data());
    }
    const std::size_t perLevel = static_cast<std::size_t>(table.coefficientsPerLevel());
    if (numbers.size() != perLevel * levelCount)
        throw ProbeError(fmt::format("{}: {} numbers, expected {} ({} levels x {} taps x 3 frames x 5 x {})", path.string(), numbers.size(),
                                     perLevel * levelCount, levelCount, taps, coefficientCount(form)));
    setPublishedLayout(table, numbers);
    validateTableValues(table, path.string());
    table.solver = fmt::format("imported from {}", path.filename().string());
    return table;
}

void writePublishedTable(const std::filesystem::path& path, const TapTable& table) {
    validateTable(table, "tap table");
    std::string text;
    const std::vector<float> values = publishedLayout(table);
    for (std::size_t k = 0; k < values.size(); k += 4)
        text += fmt::format("{:.9g} {:.9g} {:.9g} {:.9g}\n", values[k], values[k + 1], values[k + 2], values[k + 3]);
    writeFile(path, text);
}

std::vector<std::string> tableSummary(const TapTable& table) {
    std::vector<std::string> lines;
    lines.push_back(fmt::format("face size {}, {} levels, {} taps x {} frames, form {}, mapping {}", table.faceSize, table.levelCount,
                                table.taps, kFrameCount, tableFormName(table.form), describeRoughnessMapping(table.mapping)));
    lines.push_back(
        fmt::format("pyramid {} weighted by {}", pyramidKindName(table.pyramid.kind), pyramidWeightingName(table.pyramid.weighting)));
    lines.push_back(fmt::format("solver: {}; stratified texels: budget {} per level", table.solver, table.stratifiedBudget));
    lines.push_back(fmt::format("fit time {:.1f} s", table.fitSeconds));
    lines.push_back("impulse-response L1 per level: stratified mean / max, all texels mean / max (worst texel "
                    "face,i,j), min weight sum");
    for (int m = 0; m < table.levelCount; ++m) {
        const TableLevel& l = table.levels[m];
        const double alpha = tableLevelAlpha(table, m);
        if (alpha <= 0.0) {
            lines.push_back(fmt::format("  level {} alpha 0: copy of the source", m));
            continue;
        }
        const std::string all = l.all.mean < 0.0 ? std::string("not measured")
                                                 : fmt::format("{:.5f} / {:.5f} ({},{},{})", l.all.mean, l.all.max, l.all.worst.face,
                                                               l.all.worst.i, l.all.worst.j);
        const std::string stratified =
            l.stratified.mean < 0.0 ? std::string("not measured") : fmt::format("{:.5f} / {:.5f}", l.stratified.mean, l.stratified.max);
        const std::string handOff = l.fisSamples > 0 ? fmt::format("; filtered by FIS with {} samples", l.fisSamples) : std::string();
        lines.push_back(fmt::format("  level {} alpha {:.5f}: {}, {}, {:.4f}{}", m, alpha, stratified, all, l.minWeightSum, handOff));
    }
    return lines;
}

std::string tableCppHeader(const TapTable& table, std::string_view name) {
    validateTable(table, "tap table");
    const std::vector<float> values = publishedLayout(table);
    std::string out = "// Generated by probefit; do not edit.\n" + commentBlock(table);
    out += "#pragma once\n\nnamespace probe_tables::" + std::string(name) + " {\n\n";
    out += fmt::format("inline constexpr int kFaceSize = {};\n", table.faceSize);
    out += fmt::format("inline constexpr int kLevelCount = {};\n", table.levelCount);
    out += fmt::format("inline constexpr int kTaps = {}; // per frame\n", table.taps);
    out += fmt::format("inline constexpr int kCoefficientCount = {}; // {}\n", coefficientCount(table.form), tableFormName(table.form));
    out += fmt::format("inline constexpr const char* kForm = \"{}\";\n", tableFormName(table.form));
    out += fmt::format("inline constexpr const char* kMapping = \"{}\";\n", roughnessMappingName(table.mapping));
    out += fmt::format("inline constexpr const char* kLobe = \"{}\"; // the lobe the levels are fitted to\n", lobeName(table.lobe));
    std::vector<double> roughness;
    for (int m = 0; m < table.levelCount; ++m) roughness.push_back(levelRoughness(table.mapping, m, table.levelCount));
    out += "// Per level, the perceptual roughness it holds (the mapping's; a custom mapping's list).\n";
    out += fmt::format("inline constexpr double kLevelRoughness[{}] = {{{}}};\n", table.levelCount, fmt::join(roughness, ", "));
    out += fmt::format("inline constexpr const char* kPyramidKind = \"{}\";\n", pyramidKindName(table.pyramid.kind));
    out += fmt::format("inline constexpr const char* kPyramidWeighting = \"{}\";\n", pyramidWeightingName(table.pyramid.weighting));
    out += fmt::format("inline constexpr const char* kSolver = R\"probetable({})probetable\";\n", table.solver);
    out += fmt::format("inline constexpr int kStratifiedBudget = {};\n", table.stratifiedBudget);
    out += fmt::format("inline constexpr double kFitSeconds = {};\n", table.fitSeconds);
    out += fmt::format("inline constexpr double kSeamWeight = {};\n", table.seamWeight);
    out += "// Per level, the groups of four taps per frame in use (the rest weigh 0 and can be skipped).\n";
    out += fmt::format("inline constexpr int kTapGroups[{}] = {{{}}};\n", table.levelCount, fmt::join(tapGroups(table), ", "));
    out += "// Per level, what the fit achieved: the impulse-response L1 over the stratified texels (mean, max, worst\n"
           "// texel face, i, j), the same over all texels (mean < 0: not measured), and the smallest weight sum.\n";
    out += fmt::format("inline constexpr double kLevelFits[{}][{}] = {{\n", table.levelCount, kLevelFitColumns);
    for (const TableLevel& level : table.levels) {
        const auto error = [](const ImpulseError& e) {
            return fmt::format("{}, {}, {}, {}, {}", e.mean, e.max, e.worst.face, e.worst.i, e.worst.j);
        };
        out += fmt::format("    {{{}, {}, {}}},\n", error(level.stratified), error(level.all), level.minWeightSum);
    }
    out += "};\n";
    out += "// Per level, the FIS samples per texel that filter it in the table's place (bias 0, on the table's\n"
           "// pyramid), where FIS measured better at no more time; 0: the table's taps filter it.\n";
    out += fmt::format("inline constexpr int kFisSamples[{}] = {{{}}};\n", table.levelCount, fmt::join(fisSamples(table), ", "));
    out += "// Per level, the published layout: [parameter][coefficient][frame * kTaps / 4 + tap / 4][tap % 4].\n";
    out += fmt::format("inline constexpr float kCoefficients[{}] = {{{}\n}};\n", values.size(), floatList(values, 2, "", ""));
    out += "\n} // namespace probe_tables::" + std::string(name) + "\n";
    return out;
}

std::string tableGlslInclude(const TapTable& table, std::string_view name) {
    validateTable(table, "tap table");
    const std::vector<float> values = publishedLayout(table);
    std::string guard = "PROBE_TABLE_" + std::string(name) + "_GLSL";
    for (char& c : guard) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    std::string out = "// Generated by probefit; do not edit.\n" + commentBlock(table);
    out += "#ifndef " + guard + "\n#define " + guard + "\n\n";
    out += fmt::format("#define PROBE_TABLE_FACE_SIZE {}\n", table.faceSize);
    out += fmt::format("#define PROBE_TABLE_LEVEL_COUNT {}\n", table.levelCount);
    out += fmt::format("#define PROBE_TABLE_TAPS {}\n", table.taps);
    out += fmt::format("#define PROBE_TABLE_COEFFICIENT_COUNT {}\n", coefficientCount(table.form));
    out += "// The pyramid pass the table was fitted for (engine/probe_pyramid.glsl builds the B-spline one).\n";
    out += fmt::format("#define PROBE_TABLE_PYRAMID_BSPLINE {}\n", table.pyramid.kind == PyramidKind::bspline ? 1 : 0);
    out += fmt::format("#define PROBE_TABLE_PYRAMID_INVERSE_SOLID_ANGLE {}\n",
                       table.pyramid.weighting == PyramidWeighting::inverseSolidAngle ? 1 : 0);
    out += "// The coefficients. A shader that needs only the pyramid pass (engine/probe_pyramid.glsl) defines\n"
           "// PROBE_TABLE_PYRAMID_ONLY before this include, so that its module carries none of them.\n"
           "#ifndef PROBE_TABLE_PYRAMID_ONLY\n";
    out += "// vec4 index of (level, parameter, coefficient, frame, tap / 4):\n"
           "// ((level * 5 + parameter) * PROBE_TABLE_COEFFICIENT_COUNT + coefficient) * (3 * PROBE_TABLE_TAPS / 4)\n"
           "//   + frame * PROBE_TABLE_TAPS / 4 + tap / 4; component tap % 4.\n";
    out += "// Globals with initializers rather than `const` arrays: glslang copies a `const` array into a\n"
           "// function variable at each dynamic index, which Mesa's lavapipe compiles for many minutes; drivers\n"
           "// that fold read-only arrays into constant data (RADV) compile both to the same code.\n";
    out += fmt::format("vec4 probeTableCoeffs[{}] = vec4[]({}\n);\n", values.size() / 4, floatList(values, 2, "vec4(", ")"));
    out += "// Per level, the groups of four taps per frame in use (the rest weigh 0 and can be skipped).\n";
    out += fmt::format("int probeTableTapGroups[{}] = int[]({});\n", table.levelCount, fmt::join(tapGroups(table), ", "));
    out += "// Per level, the FIS samples per texel that filter it better than the taps (bias 0, on the same\n"
           "// pyramid); 0: the taps. A shader without FIS may still use the taps there.\n";
    out += fmt::format("int probeTableFisSamples[{}] = int[]({});\n", table.levelCount, fmt::join(fisSamples(table), ", "));
    out += "#endif\n\n#endif\n";
    return out;
}

} // namespace probe
