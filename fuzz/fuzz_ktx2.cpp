// Fuzz target: the KTX 2.0 reader, both entry points of `leanfade info`: inspect_ktx2 (+ describe)
// on any KTX2 and read_ktx2 (+ unpack, summarize) on LEAN maps.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_common.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/ktx2.hpp"

using namespace leanfade;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::vector<std::uint8_t> bytes = fuzz::to_bytes(data, size);
    try {
        const io::Ktx2Info info = io::inspect_ktx2_from_memory(bytes, "fuzz.ktx2");
        if (io::describe(info).empty()) __builtin_trap();
    } catch (const Error&) {
    }
    try {
        io::ReadOptions options;
        options.max_dimension = fuzz::kMaxDimension;
        const PackedLeanMap map = io::read_ktx2_from_memory(bytes, "fuzz.ktx2", options);
        const LeanMapSummary summary = summarize(unpack_lean_map(map));
        if (summary.levels != int(map.levels.size())) __builtin_trap();
    } catch (const Error&) {
    }
    return 0;
}
