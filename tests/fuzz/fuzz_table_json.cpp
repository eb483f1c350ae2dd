// probe::tableFromJson, the reader of the project's table files, on arbitrary text.
#include "fuzz_input.h"

#include <string_view>

#include "probe/error.h"
#include "probe/table_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > probe_fuzz::kMaxInputBytes) return -1;
    try {
        probe::tableFromJson(std::string_view(reinterpret_cast<const char*>(data), size), "input.json");
    } catch (const probe::ProbeError&) {
        // A refusal naming the file and the problem: the expected outcome for most inputs.
    }
    return 0;
}
