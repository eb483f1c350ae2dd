// probe::readImage on arbitrary bytes: the Radiance HDR and KTX2 readers and OpenEXR's, then the pixel check
// every probe goes through.
#include "fuzz_input.h"

#include "probe/error.h"
#include "probe/probe_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > probe_fuzz::kMaxInputBytes) return -1;
    const std::filesystem::path path = probe_fuzz::tempFolder().write("input.img", data, size);
    try {
        probe::Image image = probe::readImage(path);
        probe::checkPixels(image, path, probe::BadPixelPolicy::repair);
    } catch (const probe::ProbeError&) {
        // A refusal naming the file and the problem: the expected outcome for most inputs.
    }
    return 0;
}
