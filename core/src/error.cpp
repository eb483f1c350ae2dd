#include "probe/error.h"

#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace probe {

std::string oneLine(std::string_view message) {
    std::string line;
    line.reserve(message.size());
    for (const char c : message) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '\n') line += "\\n";
        else if (c == '\r') line += "\\r";
        else if (c == '\t') line += "\\t";
        else if (u < 0x20 || u == 0x7f) line += fmt::format("\\x{:02x}", u);
        else line += c;
    }
    return line;
}

void printToStderr(std::string_view text) { std::fwrite(text.data(), 1, text.size(), stderr); }

std::string commandLineValueProblem(std::string_view value) {
    if (value.empty()) return "empty value";
    try {
        (void)nlohmann::json(value).dump();
    } catch (const nlohmann::json::type_error&) {
        return "not valid UTF-8 (reports and tables are JSON, which holds UTF-8 text only)";
    }
    return {};
}

} // namespace probe
