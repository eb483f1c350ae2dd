#include "table_outputs.h"

#include <cctype>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/output_file.h"
#include "probe/table_io.h"

namespace probefit {

std::string tableIdentifier(const std::filesystem::path& prefix) {
    std::string name = prefix.filename().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) name = "t" + name;
    return name;
}

void checkWritable(const std::filesystem::path& prefix) {
    const std::filesystem::path test = prefix.string() + ".json.partial";
    std::ofstream out(test);
    if (!out) throw probe::ProbeError(fmt::format("--out {}: folder does not exist or is not writable", prefix.string()));
    out.close();
    std::filesystem::remove(test);
}

void writeTableOutputs(const std::filesystem::path& prefix, const probe::TapTable& table) {
    const std::string name = tableIdentifier(prefix);
    const std::vector<std::pair<std::string, std::string>> files{
        {".json", probe::tableToJson(table)}, {".h", probe::tableCppHeader(table, name)}, {".glsl", probe::tableGlslInclude(table, name)}};
    std::vector<std::filesystem::path> written;
    for (const auto& [extension, text] : files) {
        const std::filesystem::path temporary = prefix.string() + extension + ".partial";
        written.push_back(temporary);
        try {
            probe::writeFile(temporary, text);
        } catch (const probe::ProbeError& e) {
            for (const auto& p : written) std::filesystem::remove(p);
            throw probe::ProbeError(fmt::format("--out {}: {}", prefix.string(), e.what()));
        }
    }
    for (std::size_t k = 0; k < files.size(); ++k) std::filesystem::rename(written[k], prefix.string() + files[k].first);
}

} // namespace probefit
