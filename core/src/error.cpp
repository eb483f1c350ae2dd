#include "probe/error.h"

#include <cstdio>
#include <utility>

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

std::string_view parameterFlag(std::string_view parameter) {
    static constexpr std::pair<std::string_view, std::string_view> kFlags[] = {
        {"method.kind", "--method"},           {"method.table", "--table"},     {"method.fis.samples", "--samples"},
        {"method.fis.bias", "--fis-bias"},     {"method.fis.map", "--fis-map"}, {"method.lobe", "--lobe"},
        {"roughness", "--roughness"},          {"sampling", "--sampling"},      {"outputFormat", "--format"},
        {"pyramidFormat", "--pyramid-format"}, {"repeat", "--repeat"},          {"device", "--device"},
    };
    for (const auto& [name, flag] : kFlags)
        if (name == parameter) return flag;
    return {};
}

std::string messageWithFlag(const ParameterError& e) {
    const std::string_view flag = parameterFlag(e.parameter);
    const std::string message = e.what();
    if (flag.empty() || !message.starts_with(e.parameter)) return message;
    return std::string(flag) + message.substr(e.parameter.size());
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
