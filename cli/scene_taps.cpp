#include "scene_taps.h"

#include <memory>

#include <fmt/format.h>

#include "probe/error.h"
#include "probe/fis.h"
#include "probe/runtime.h"
#include "probe/table_filter.h"
#include "probe/table_io.h"

namespace probefilter {

bool hasCharlieTable(const probe::SceneProbe& p) {
    return probe::gpu::findCompiledTable(p.faceSize, p.levelCount, p.mapping, {}, probe::Lobe::charlie) != nullptr;
}

probe::TapTable sceneProbeTable(const probe::Scene& scene, const probe::SceneProbe& p) {
    // A probe's "table" file is its GGX levels'.
    if (!p.table || p.method.lobe != probe::Lobe::ggx) {
        if (const probe::gpu::CompiledTable* compiled =
                probe::gpu::findCompiledTable(p.faceSize, p.levelCount, p.mapping, {}, p.method.lobe))
            return compiled->table;
        throw probe::ProbeError(fmt::format("{}: probe '{}': no built-in {} table for {}^2, {} levels, mapping {}; give a \"table\" "
                                            "(probefit fit --size {} --levels {} --taps 8 --form quad {} --out PREFIX makes one)",
                                            scene.path.string(), p.name, probe::lobeName(p.method.lobe), p.faceSize, p.levelCount,
                                            probe::describeRoughnessMapping(p.mapping), p.faceSize, p.levelCount,
                                            probe::mappingOptions(p.mapping)));
    }
    probe::TapTable table = probe::readTable(*p.table);
    if (table.faceSize != p.faceSize || table.levelCount != p.levelCount || table.mapping != p.mapping)
        throw probe::ProbeError(
            fmt::format("{}: table is for {}^2, {} levels, mapping {}, but probe '{}' of {} is {}^2, {} levels, mapping {}",
                        p.table->string(), table.faceSize, table.levelCount, probe::describeRoughnessMapping(table.mapping), p.name,
                        scene.path.string(), p.faceSize, p.levelCount, probe::describeRoughnessMapping(p.mapping)));
    return table;
}

probe::MethodTaps sceneProbeTaps(const probe::Scene& scene, const probe::SceneProbe& p) {
    switch (p.method.kind) {
    case probe::MethodKind::table: {
        // tableMethodTapGenerator refers to its table: the generator keeps it alive.
        auto table = std::make_shared<const probe::TapTable>(sceneProbeTable(scene, p));
        return {[table, generator = probe::tableMethodTapGenerator(*table)](
                    int level, const probe::Texel& texel, std::vector<probe::Tap>& taps) { return generator(level, texel, taps); },
                probe::levelMethods(p.method.kind, table.get(), p.levelCount)};
    }
    case probe::MethodKind::fis:
        return {probe::fisTapGenerator(p.faceSize, p.levelCount, p.mapping, p.method.fis, p.method.lobe),
                probe::levelMethods(p.method.kind, nullptr, p.levelCount)};
    case probe::MethodKind::reference: break;
    }
    return {{}, probe::levelMethods(p.method.kind, nullptr, p.levelCount)};
}

} // namespace probefilter
