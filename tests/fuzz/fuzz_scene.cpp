// probe::readScene on arbitrary text. The folder holds an (empty) probe.exr, so that seeds naming
// it get past the image check to the rest of the scene.
#include "fuzz_input.h"

#include "probe/error.h"
#include "probe/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > probe_fuzz::kMaxInputBytes) return -1;
    static const std::filesystem::path image = probe_fuzz::tempFolder().write("probe.exr", data, 0);
    const std::filesystem::path path = probe_fuzz::tempFolder().write("scene.json", data, size);
    try {
        probe::readScene(path);
    } catch (const probe::ProbeError&) {
        // A refusal naming the file and the problem: the expected outcome for most inputs.
    }
    return 0;
}
