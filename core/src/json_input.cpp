#include "json_input.h"

#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/limits.h"

namespace probe {

using nlohmann::json;

json parseJsonFile(std::string_view text, const std::filesystem::path& path, std::string_view what) {
    const auto fail = [&](const std::string& problem) { return ProbeError(fmt::format("{}: {}: {}", path.string(), what, problem)); };
    // The keys of each object being parsed, innermost last.
    std::vector<std::set<std::string>> keys;
    const json::parser_callback_t check = [&](int depth, json::parse_event_t event, json& parsed) {
        if (depth > kMaxJsonDepth) throw fail(fmt::format("nested deeper than {} levels", kMaxJsonDepth));
        switch (event) {
        case json::parse_event_t::object_start: keys.emplace_back(); break;
        case json::parse_event_t::object_end: keys.pop_back(); break;
        case json::parse_event_t::key: {
            const std::string& key = parsed.get_ref<const std::string&>();
            if (!keys.back().insert(key).second) throw fail(fmt::format("key '{}' appears twice in one object", key.substr(0, 64)));
            break;
        }
        default: break;
        }
        return true;
    };
    try {
        return json::parse(text, check);
    } catch (const json::exception& e) {
        // The library's message names the byte; a number too large for double is reported as such.
        std::string message = e.what();
        if (const std::size_t colon = message.find("] "); colon != std::string::npos) message.erase(0, colon + 2);
        throw fail(fmt::format("not valid JSON, or incomplete ({})", message.substr(0, 200)));
    }
}

std::optional<int> jsonInt(const json& value) {
    if (value.is_number_unsigned()) {
        const auto v = value.get<json::number_unsigned_t>();
        if (v <= static_cast<json::number_unsigned_t>(std::numeric_limits<int>::max())) return static_cast<int>(v);
    } else if (value.is_number_integer()) {
        const auto v = value.get<json::number_integer_t>();
        if (v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max()) return static_cast<int>(v);
    }
    return std::nullopt;
}

std::string describeJson(const json& value) {
    if (value.is_structured()) return value.is_object() ? "an object" : "an array";
    std::string text = value.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return fmt::format("{} {}", value.type_name(), text);
}

} // namespace probe
