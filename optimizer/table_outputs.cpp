#include "table_outputs.h"

#include <array>
#include <cctype>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/output_file.h"
#include "probe/staged_output.h"
#include "probe/table_io.h"

namespace probefit {

std::string tableIdentifier(const std::filesystem::path& prefix) {
    std::string name = prefix.filename().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) name = "t" + name;
    return name;
}

namespace {

constexpr std::array<const char*, 3> kExtensions{".json", ".h", ".glsl"};

} // namespace

void checkWritable(const std::filesystem::path& prefix, const char* flag) {
    try {
        for (const char* extension : kExtensions) {
            const probe::StagedFile file(prefix.string() + extension); // checks, creating nothing
        }
    } catch (const probe::ProbeError& e) {
        throw probe::ProbeError(fmt::format("{} {}: {}", flag, prefix.string(), e.what()));
    }
}

void writeTableOutputs(const std::filesystem::path& prefix, const probe::TapTable& table, const char* flag) {
    const std::string name = tableIdentifier(prefix);
    const std::array<std::string, 3> texts{probe::tableToJson(table), probe::tableCppHeader(table, name),
                                           probe::tableGlslInclude(table, name)};
    std::vector<std::unique_ptr<probe::StagedFile>> staged;
    try {
        for (std::size_t k = 0; k < texts.size(); ++k) {
            staged.push_back(std::make_unique<probe::StagedFile>(prefix.string() + kExtensions[k]));
            probe::writeFile(staged.back()->path(), texts[k]);
        }
        for (const auto& file : staged) file->commit();
    } catch (const probe::ProbeError& e) {
        throw probe::ProbeError(fmt::format("{} {}: {}", flag, prefix.string(), e.what()));
    }
}

} // namespace probefit
