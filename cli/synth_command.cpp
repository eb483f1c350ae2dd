// probefilter synth NAME --size S --out FILE.exr: writes a synthetic probe as a 6S x S face strip.
#include <optional>

#include <fmt/format.h>

#include "commands.h"
#include "probe/error.h"
#include "probe/limits.h"
#include "probe/probe_io.h"
#include "probe/roughness.h"
#include "probe/staged_output.h"
#include "probe/synthetic.h"

namespace probefilter {

// The widest W x W/2 image within the input limit, so that what synth writes, filter reads.
constexpr int kMaxEquirectWidth = 16384;
static_assert(std::int64_t{kMaxEquirectWidth} * kMaxEquirectWidth / 2 <= probe::kMaxImagePixels);

void addSynthCommand(CLI::App& app) {
    struct Options {
        std::string name;
        int size = 128;
        std::optional<int> equirectWidth;
        std::string out;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("synth", "Write a synthetic probe (constant, sky, sunsky, room, checker) as a face strip EXR");
    cmd->add_option("name", o->name, "Which probe")->required();
    cmd->add_option("--size", o->size, "Face size of the 6S x S strip");
    cmd->add_option("--equirect", o->equirectWidth,
                    fmt::format("Write a W x W/2 equirectangular image instead of a strip (W even, 4 to {})", kMaxEquirectWidth));
    cmd->add_option("--out", o->out, "Output EXR file")->required();
    cmd->callback([o] {
        probe::StagedFile out(o->out);
        if (o->equirectWidth) {
            const int width = *o->equirectWidth;
            if (width < 4 || width % 2 != 0 || width > kMaxEquirectWidth)
                throw probe::ProbeError(fmt::format("--equirect {}: the width must be even, 4 to {}", width, kMaxEquirectWidth));
            probe::writeExr(out.path(), probe::syntheticEquirect(o->name, width));
        } else {
            probe::validateSizeAndLevels(o->size, 1);
            probe::writeExr(out.path(), probe::cubeToStrip(probe::syntheticProbe(o->name, o->size)));
        }
        out.commit();
        fmt::print("synth: {} -> {}\n", o->name, o->out);
    });
}

} // namespace probefilter
