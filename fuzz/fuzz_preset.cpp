// Fuzz target: the JSON preset reader (core preset_from_json: nlohmann::json parsing, strict
// keys, types and ranges of every setting, ShadingSettings included). A preset it accepts must
// round-trip: preset_to_json of it parses again to the same JSON (preset.hpp promises
// preset_from_json(preset_to_json(p)) == p).
#include <cstddef>
#include <cstdint>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/preset.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    leanfade::Preset preset;
    try {
        preset = leanfade::preset_from_json(std::string(reinterpret_cast<const char*>(data), size),
                                            "fuzz.json");
    } catch (const leanfade::Error&) {
        return 0;
    }
    const std::string json = leanfade::preset_to_json(preset);
    try {
        if (leanfade::preset_to_json(leanfade::preset_from_json(json, "round-trip.json")) != json) {
            __builtin_trap();
        }
    } catch (const leanfade::Error&) {
        __builtin_trap();  // its own output refused
    }
    return 0;
}
