#pragma once
// `leanfade bake` of images and built-in sets (cmd_bake.cpp): the flags, and the plan of a run,
// made before any input is read: the flags checked, the bake's settings with its storage policy,
// and one job per input with its outputs, all checked together (docs/robustness.md).
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <string_view>
#include <vector>

#include "cli_bake_roughness.hpp"
#include "leanfade/core/detail/bump_source.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::cli {

// Where `bake` writes a LEAN map: a KTX2 file, or the top level as a PNG pair (NAME.lean1.png,
// NAME.lean2.png).
enum class LeanFileFormat { Ktx2, Png };
const std::vector<std::pair<std::string, LeanFileFormat>>& lean_file_format_names();
// --sc: auto (the steepest slope except outliers) or max (the steepest slope), as
// BakeOptions::scale_excludes_outliers.
const std::vector<std::pair<std::string, bool>>& scale_rule_names();

struct BakeArgs {
    std::vector<std::string> inputs;
    std::string output;
    std::string out_dir;
    BakeSource from = BakeSource::Auto;
    float strength = 1.0f;
    bool strength_given = false;  // --strength on the command line (an error for normal maps)
    StrengthUnit strength_unit = StrengthUnit::Texel;
    bool sc_excludes_outliers = true;  // --sc auto (true) or max
    bool directx = false;
    bool strict_normals = false;
    StoragePolicy bits = StoragePolicy::measured();  // auto: 16, or 16f by the probe
    float bake_roughness = 0.0f;
    // The plateau layer's epsilon (slope units; 0 = no layer): BakeOptions::plateau_epsilon.
    float plateau_epsilon = kDefaultPlateauEpsilon;
    SpikeFit spike_fit = SpikeFit::Auto;  // BakeOptions::spike_fit
    Wrap wrap = Wrap::Repeat;
    // KTX2 LEAN maps' supercompression (--supercompression, --zstd-level; docs/ktx2.md).
    io::Supercompression supercompression = io::Supercompression::Zstandard;
    int zstd_level = 3;
    // --format; none: from -o's extension, else ktx2 (checked_bake_args resolves it).
    std::optional<LeanFileFormat> format;
    int threads = 0;
    bool fsync = false;
    std::string builtin;
    std::string cross_terms;  // --cross-terms A,B (cli_bake_cross_terms.hpp)
    int size = 1024;
    std::uint32_t seed = 1;
    int max_size = kDefaultMaxImageDimension;
    std::string json;
    RoughnessBakeArgs roughness;     // --roughness-out and its flags (cli_bake_roughness.hpp)
    std::string plateau_out;         // --plateau-out FILE.ktx2 (cli_bake_plateau.hpp)
    bool ktx2_2d = false;            // --ktx2-2d: the layers also as 2D KTX2 files
    // Whether the LEAN map itself is written: not when only engine outputs are asked
    // (--roughness-out / --anisotropy-out without -o, --out-dir or --plateau-out).
    bool writes_lean_map = true;
    std::vector<std::string> given;  // the options given on the command line, by long name
};

// The 2D KTX2 files of a LEAN map's layers beside OUT.ktx2 (--ktx2-2d): OUT.lean1.ktx2 and
// OUT.lean2.ktx2.
std::pair<std::string, std::string> layer_texture_paths(const std::string& ktx2_output);

// The kinds of run `leanfade bake` makes, as bits: images and built-in sets into LEAN maps, a
// glTF scene's normal textures (or its filtered copy), the cross-term texture of two layers.
enum BakeKind : unsigned { kImageBake = 1u, kGltfBake = 2u, kCrossTermsBake = 4u };
inline constexpr unsigned kEveryBake = kImageBake | kGltfBake | kCrossTermsBake;

// Which kinds of run honour a flag of `bake`, by its long name as CLI11 stores it ("inputs" for
// the files): the flags that other kinds than images honour. Every flag not listed honours image
// bakes only; each kind refuses, by name, a flag given that it does not honour (rather than
// ignore an output asked for and never written).
struct BakeFlagScope {
    std::string_view flag;
    unsigned kinds;
};
inline constexpr BakeFlagScope kBakeFlagScopes[] = {
    {"inputs", kImageBake | kGltfBake},
    {"--output", kEveryBake},
    {"--out-dir", kImageBake | kGltfBake},
    {"--max-size", kEveryBake},
    {"--from", kImageBake | kCrossTermsBake},
    {"--directx", kImageBake | kCrossTermsBake},
    {"--strength", kImageBake | kCrossTermsBake},
    {"--size", kImageBake | kCrossTermsBake},
    {"--seed", kImageBake | kCrossTermsBake},
    {"--cross-terms", kCrossTermsBake},
    {"--bits", kImageBake | kGltfBake},
    {"--threads", kImageBake | kGltfBake},
    {"--json", kImageBake | kGltfBake},
    {"--fsync", kImageBake | kGltfBake},
    {"--strict-normals", kImageBake | kGltfBake},
    {"--supercompression", kImageBake | kGltfBake},
    {"--zstd-level", kImageBake | kGltfBake},
    {"--compress", kImageBake | kGltfBake},
};
// Whether a run of `kind` honours `flag`.
bool flag_applies(std::string_view flag, BakeKind kind);
// The first option given that a run of `kind` does not honour ("" when it honours all).
std::string first_inapplicable(const BakeArgs& args, BakeKind kind);
// The flags a run of `kind` honours, as a message lists them ("-o, --from and --max-size"; the
// files are not named).
std::string applicable_flags_text(BakeKind kind);

// The flags checked before any file is touched, with the output format resolved: --format, else
// png for an -o named .png, else ktx2. Throws leanfade::Error(flag, cause).
BakeArgs checked_bake_args(const BakeArgs& given);

// What every bake of the run uses.
struct BakeRunSettings {
    BakeOptions options;
    BakeSource source = BakeSource::Auto;  // of the input files (built-in sets are height maps)
    StoragePolicy storage;  // leanfade::StoragePolicy of --bits
    io::ReadOptions read_options;
    io::WriteOptions write_options;
};

// The settings of checked_bake_args' flags. Throws leanfade::Error("--bits", ...) for a PNG pair
// of other than 8 or 16 bits.
BakeRunSettings bake_settings(const BakeArgs& args);

// One input of the run and where its outputs go.
struct BakeJob {
    std::string name;  // the file, or builtin:NAME
    bool from_file = false;
    std::vector<std::string> outputs;  // the .ktx2, or the .lean1.png, .lean2.png (and
                                       // .plateau.png with the plateau layer)
    std::string output_is_input;       // an output that is this job's own input
};

// The jobs (the built-in set first, then the files in order) with their outputs. Every output of
// the run is checked before anything is read: a regular file (or a new one) in a writable
// folder, not an input, not the output of another input; --json and the roughness outputs too.
// Throws leanfade::Error naming the output.
std::vector<BakeJob> plan_bake_jobs(const BakeArgs& args);

std::string generator_string();  // "leanfade VERSION"

}  // namespace leanfade::cli
