// probe::importPublishedTable, the reader of the published plain-text layout, on arbitrary text.
// The shape is the caller's: the one of tests/fixtures/table_16_quad4_gltf.txt (face size 16,
// 4 levels, 4 taps, quad), so that the seeds from that file reach the layout code.
#include "fuzz_input.h"

#include "probe/error.h"
#include "probe/table_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > probe_fuzz::kMaxInputBytes) return -1;
    const std::filesystem::path path = probe_fuzz::tempFolder().write("input.txt", data, size);
    try {
        probe::importPublishedTable(path, 16, 4, 4, probe::TableForm::quadratic, probe::RoughnessMapping::gltf, {});
    } catch (const probe::ProbeError&) {
        // A refusal naming the file and the problem: the expected outcome for most inputs.
    }
    return 0;
}
