#pragma once
// What `leanfade bake` (cmd_bake.cpp) reports of each baked input: the summary on stdout, its
// entry in --json, and the warning on stderr about a normal map that reads better in the other
// convention.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade::cli {

// One baked input.
struct BakeReport {
    std::string input;
    std::string output;  // the .ktx2, or NAME.lean{1,2}.png
    LeanMapSummary summary;
    BakeSource source = BakeSource::Height;  // what the input was taken as
    std::size_t clamped_texels = 0;          // normal maps: z raised to kMinNormalZ
    NormalRepairs normal_repairs;
    std::uint64_t texels_beyond_scale = 0;
    bool roughness_baked = false;
    Storage storage = Storage::Unorm16;  // as written (--bits auto: the storage chosen)
    // --bits auto: the highlight's PSNR (dB) as 16-bit UNORM and as half floats store the map
    // (StorageProbe); NaN otherwise.
    double probe_unorm16_psnr = std::numeric_limits<double>::quiet_NaN();
    double probe_float16_psnr = std::numeric_limits<double>::quiet_NaN();
    double seconds = 0.0;
    bool looks_like_other_convention = false;
    // The other files (and folders) the bake wrote for this input: roughness, normal and
    // anisotropy MIPs, their PNG levels, the plateau layer.
    std::vector<std::string> also_written;
};

BakeReport bake_report(const std::string& input, const std::string& output,
                       const PackedBakeResult& baked, double seconds,
                       bool looks_like_other_convention);

// The summary on stdout: sizes, sc and storage, slopes, the coarsest level, and the notes on
// clamped, repaired and beyond-sc texels.
void print_bake_report(const BakeReport& report);
// The entry of --json.
nlohmann::json bake_report_json(const BakeReport& report);

// A warning on stderr when a normal map's slopes fit a height field clearly better in the other
// convention (check_normal_convention). Returns whether it warned.
bool warn_if_other_convention(const std::string& name, const std::variant<Image, UnormImage>& input,
                              NormalConvention convention);

}  // namespace leanfade::cli
