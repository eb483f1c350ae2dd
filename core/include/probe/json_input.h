// JSON input files (tables, scenes): parsed with bounded nesting and without duplicate keys, and read
// with checked conversions, so that every refusal names the file and the problem in one line.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace probe {

// Parses `text`, the contents of `path` (a `what`: "table file", "scene file"). Throws ProbeError
// ("<path>: <what>: <problem>") on a syntax error, a number out of double's range, nesting deeper
// than kMaxJsonDepth or more than kMaxJsonValues values (limits.h), or a key that an object holds
// twice; the document's tree is built only after these checks.
nlohmann::json parseJsonFile(std::string_view text, const std::filesystem::path& path, std::string_view what);

// The value as an int, or std::nullopt unless it is an integer (no fraction) within int's range.
std::optional<int> jsonInt(const nlohmann::json& value);

// A short description of a value for messages: its type, and a scalar's text up to a few dozen
// characters (never a dump of a whole tree).
std::string describeJson(const nlohmann::json& value);

} // namespace probe
