// Every committed table under tables/: the table file parses, its name says what it records
// (mapping, size, form, taps; a mix: the taps of level 1, and "lean" for the cheaper of two mixes
// with those taps; "_charlie" for the sheen lobe), and the generated header and GLSL
// include are exactly what the table file generates (so they carry the same sizes, levels, mapping,
// pyramid and coefficients). The headers also compile: committed_table_headers.cpp includes them all.
// The tables compiled into the runtime from those headers equal their table files.
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "probe/runtime.h"
#include "probe/table_io.h"
#include "table_outputs.h"

namespace {

using namespace probe;

std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(CommittedTables, MatchTheirNamesAndGeneratedSources) {
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(PROBE_TABLES_DIR)) {
        if (entry.path().extension() != ".json") continue;
        ++count;
        const std::filesystem::path prefix = entry.path().parent_path() / entry.path().stem();
        SCOPED_TRACE(prefix.string());
        const TapTable table = readTable(entry.path());
        std::smatch m;
        const std::string stem = entry.path().stem().string();
        ASSERT_TRUE(
            std::regex_match(stem, m, std::regex("(gltf|authors|filament|unity)([0-9]+)_(const|quad)(mix)?([0-9]+)(lean)?(_charlie)?")));
        EXPECT_EQ(table.lobe, m[7].matched ? Lobe::charlie : Lobe::ggx);
        EXPECT_EQ(roughnessMappingName(table.mapping), m[1].str());
        EXPECT_EQ(table.faceSize, std::stoi(m[2].str()));
        EXPECT_EQ(tableFormName(table.form), m[3].str());
        // A mix (probefit mix) is named by the taps of level 1, which sets its time.
        EXPECT_TRUE(m[4].matched || !m[6].matched) << "only a mix is lean";
        EXPECT_EQ(m[4].matched ? tapsInUse(table, 1) : table.taps, std::stoi(m[5].str()));
        EXPECT_EQ(table.levelCount, table.mapping == RoughnessMapping::authors ? 7 : defaultLevelCount(table.faceSize));
        EXPECT_EQ(table.pyramid, (PyramidSettings{PyramidKind::bspline, PyramidWeighting::solidAngle}));
        for (int level = 0; level < table.levelCount; ++level)
            if (tableLevelAlpha(table, level) > 0.0) {
                EXPECT_GE(table.levels[level].stratified.mean, 0.0) << "level " << level << " has no recorded L1";
                EXPECT_GT(table.levels[level].minWeightSum, 0.0) << "level " << level;
            }
        const std::string name = probefit::tableIdentifier(prefix);
        EXPECT_EQ(readFile(prefix.string() + ".h"), tableCppHeader(table, name));
        EXPECT_EQ(readFile(prefix.string() + ".glsl"), tableGlslInclude(table, name));
    }
    EXPECT_GT(count, 0);
}

TEST(CompiledTables, EqualTheirTableFiles) {
    const std::vector<gpu::CompiledTable>& compiled = gpu::compiledTables();
    ASSERT_FALSE(compiled.empty());
    for (const gpu::CompiledTable& c : compiled) {
        SCOPED_TRACE(c.name);
        const TapTable file = readTable(std::filesystem::path(PROBE_TABLES_DIR) / (c.name + ".json"));
        const TapTable& t = c.table;
        EXPECT_EQ(
            std::tie(t.faceSize, t.levelCount, t.taps, t.form, t.mapping, t.pyramid, t.solver, t.stratifiedBudget),
            std::tie(file.faceSize, file.levelCount, file.taps, file.form, file.mapping, file.pyramid, file.solver, file.stratifiedBudget));
        EXPECT_EQ(t.fitSeconds, file.fitSeconds);
        EXPECT_EQ(t.seamWeight, file.seamWeight);
        for (int m = 0; m < file.levelCount; ++m) {
            const TableLevel &a = t.levels[m], &b = file.levels[m];
            EXPECT_EQ(std::tie(a.stratified.mean, a.stratified.max, a.stratified.worst, a.all.mean, a.all.max, a.all.worst, a.minWeightSum,
                               a.fisSamples),
                      std::tie(b.stratified.mean, b.stratified.max, b.stratified.worst, b.all.mean, b.all.max, b.all.worst, b.minWeightSum,
                               b.fisSamples));
            ASSERT_EQ(a.coefficients.size(), b.coefficients.size());
            // The headers hold floats, what the GPU reads.
            for (std::size_t k = 0; k < b.coefficients.size(); ++k)
                ASSERT_EQ(a.coefficients[k], static_cast<double>(static_cast<float>(b.coefficients[k])))
                    << "level " << m << " [" << k << "]";
        }
    }
    // --method table finds a compiled-in table at the common sizes of the glTF mapping.
    for (int size : {16, 32, 64, 128, 256, 512, 1024})
        EXPECT_NE(gpu::findCompiledTable(size, defaultLevelCount(size), RoughnessMapping::gltf, {}, Lobe::ggx), nullptr) << size;
}

} // namespace
