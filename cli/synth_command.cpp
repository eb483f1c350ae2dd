// probefilter synth NAME --size S --out FILE.exr: writes a synthetic probe as a 6S x S face strip.
#include <fmt/format.h>

#include "commands.h"
#include "probe/probe_io.h"
#include "probe/roughness.h"
#include "probe/synthetic.h"

namespace probefilter {

void addSynthCommand(CLI::App& app) {
    struct Options {
        std::string name;
        int size = 128;
        std::string out;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("synth", "Write a synthetic probe (constant, sky, sunsky, room, checker) as a face strip EXR");
    cmd->add_option("name", o->name, "Which probe")->required();
    cmd->add_option("--size", o->size, "Face size")->required();
    cmd->add_option("--out", o->out, "Output EXR file")->required();
    cmd->callback([o] {
        probe::validateSizeAndLevels(o->size, 1);
        const probe::CubeImage cube = probe::syntheticProbe(o->name, o->size);
        const std::filesystem::path out(o->out);
        const std::filesystem::path partial = out.parent_path() / ("." + out.filename().string() + ".partial");
        probe::writeExr(partial, probe::cubeToStrip(cube));
        std::filesystem::rename(partial, out);
        fmt::print("synth: {} {}^2 -> {}\n", o->name, o->size, o->out);
    });
}

} // namespace probefilter
