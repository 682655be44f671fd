// The plan of a `leanfade bake` run (cli_bake_plan.hpp).
#include "cli_bake_plan.hpp"

#include "cli_bake_plateau.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <system_error>

#include "leanfade/core/error.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/io/detail/png_io.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

const char* format_name(LeanFileFormat format) {
    return format == LeanFileFormat::Png ? "png" : "ktx2";
}

// The output format: --format, else png for an -o named .png, else ktx2. An -o whose extension
// (.png or .ktx2) contradicts --format is refused.
LeanFileFormat resolve_format(const BakeArgs& args) {
    const bool png_name = !args.output.empty() && io::has_extension(args.output, ".png");
    const bool ktx2_name = !args.output.empty() && io::has_extension(args.output, ".ktx2");
    if (!args.format) return png_name ? LeanFileFormat::Png : LeanFileFormat::Ktx2;
    if ((args.format == LeanFileFormat::Png && ktx2_name) ||
        (args.format == LeanFileFormat::Ktx2 && png_name)) {
        const std::string name = format_name(*args.format);
        throw Error("-o", "'" + args.output + "' does not name a " + name + " output (--format " +
                              name + ")");
    }
    return *args.format;
}

// Where one input's output goes: -o, else --out-dir or the input's folder, named after the input.
std::string output_base(const BakeArgs& args, const std::string& input_name, bool from_file) {
    if (!args.output.empty()) {
        fs::path out(args.output);
        if (args.format == LeanFileFormat::Png && io::has_extension(args.output, ".png"))
            out.replace_extension();
        return out.string();
    }
    fs::path stem = fs::path(input_name).stem();
    fs::path folder = !args.out_dir.empty() ? fs::path(args.out_dir)
                      : from_file           ? fs::path(input_name).parent_path()
                                            : fs::path();
    return (folder / stem).string();
}

std::size_t job_count(const BakeArgs& args) {
    return args.inputs.size() + (args.builtin.empty() ? 0 : 1);
}

}  // namespace

bool flag_applies(std::string_view flag, BakeKind kind) {
    for (const BakeFlagScope& row : kBakeFlagScopes)
        if (row.flag == flag) return (row.kinds & kind) != 0;
    return kind == kImageBake;
}

std::string first_inapplicable(const BakeArgs& args, BakeKind kind) {
    for (const std::string& option : args.given)
        if (!flag_applies(option, kind)) return option;
    return {};
}

std::string applicable_flags_text(BakeKind kind) {
    std::vector<std::string> flags;
    for (const BakeFlagScope& row : kBakeFlagScopes)
        if ((row.kinds & kind) != 0 && row.flag != "inputs")
            flags.emplace_back(row.flag == "--output" ? "-o" : row.flag);
    std::string text;
    for (std::size_t i = 0; i < flags.size(); ++i)
        text += (i == 0 ? "" : i + 1 == flags.size() ? " and " : ", ") + flags[i];
    return text;
}

BakeArgs checked_bake_args(const BakeArgs& given) {
    BakeArgs args = given;
    args.format = resolve_format(given);
    if (!std::isfinite(args.strength)) throw Error("--strength", "must be a finite number");
    if (args.strength == 0.0f)
        throw Error("--strength", "must not be 0 (a negative strength inverts the heights)");
    if (args.strength_given && args.from == BakeSource::Normal)
        throw Error("--strength", "applies to height maps; --from normal bakes normal maps");
    if (!(args.bake_roughness >= 0.0f) || !std::isfinite(args.bake_roughness))
        throw Error("--bake-roughness", "must be a positive shininess");
    if (!(args.plateau_epsilon >= 0.0f) || !std::isfinite(args.plateau_epsilon))
        throw Error("--plateau-epsilon", "must be a finite number >= 0 (0: no plateau layer)");
    if (args.plateau_epsilon == 0.0f && !args.plateau_out.empty())
        throw Error("--plateau-out", "needs the plateau layer; --plateau-epsilon 0 bakes none");
    const auto given_flag = [&](std::string_view flag) {
        return std::find(args.given.begin(), args.given.end(), flag) != args.given.end();
    };
    // A PNG pair is deflated by PNG itself: KTX2's supercompression does not apply to it.
    for (const char* flag : {"--supercompression", "--zstd-level"})
        if (args.format == LeanFileFormat::Png && given_flag(flag))
            throw Error::setting(flag,
                                 "applies to KTX2 LEAN maps, not to a PNG pair (--format png)");
    if (given_flag("--zstd-level") && args.supercompression != io::Supercompression::Zstandard)
        throw Error("--zstd-level", "needs --supercompression zstd");
    if (args.inputs.empty() && args.builtin.empty())
        throw Error("bake", "no input: give image files or --builtin NAME");
    const std::size_t jobs = job_count(args);
    if (!args.output.empty() && jobs > 1)
        throw Error(
            "-o", "one output for " + std::to_string(jobs) + " inputs; use --out-dir for a batch");
    args.writes_lean_map = !(args.roughness.requested() && args.output.empty() &&
                             args.out_dir.empty() && args.plateau_out.empty() &&
                             args.format != LeanFileFormat::Png);
    return args;
}

BakeRunSettings bake_settings(const BakeArgs& args) {
    const bool png_bits = args.bits.automatic || args.bits.storage == Storage::Unorm8 ||
                          args.bits.storage == Storage::Unorm16;
    if (args.format == LeanFileFormat::Png && !png_bits)
        throw Error("--bits", "a PNG pair holds 8 or 16 bits; " + std::string(to_string(args.bits)) +
                                  " needs --format ktx2");
    BakeRunSettings settings;
    BakeOptions& options = settings.options;
    options.strength = args.strength;
    options.strength_unit = args.strength_unit;
    options.scale_excludes_outliers = args.sc_excludes_outliers;
    options.wrap = args.wrap;
    options.convention = args.directx ? NormalConvention::DirectX : NormalConvention::OpenGL;
    options.bake_roughness_shininess = args.bake_roughness;
    options.threads = args.threads;
    options.strict_normals = args.strict_normals;
    options.plateau_epsilon = args.plateau_epsilon;
    options.spike_fit = args.spike_fit;
    settings.source = args.from;
    // auto: 16-bit UNORM; a map with outliers beyond sc (choose_lean_scale), or whose UNORM
    // second moments would round away the base roughness, is baked again as half float
    // (leanfade::StorageProbe; docs/ktx2.md, "Choosing storage and sc"). PNG pairs: 16.
    settings.storage = args.bits;
    settings.read_options.max_dimension = args.max_size;
    settings.read_options.drop_alpha = true;  // normal maps use RGB only
    settings.write_options.durability = args.fsync ? io::Durability::Flush : io::Durability::Rename;
    settings.write_options.threads = args.threads;
    settings.write_options.supercompression = args.supercompression;
    settings.write_options.zstd_level = args.zstd_level;
    return settings;
}

std::pair<std::string, std::string> layer_texture_paths(const std::string& ktx2_output) {
    fs::path stem(ktx2_output);
    stem.replace_extension();
    return {stem.string() + ".lean1.ktx2", stem.string() + ".lean2.ktx2"};
}

std::vector<BakeJob> plan_bake_jobs(const BakeArgs& args) {
    std::vector<BakeJob> jobs;
    if (!args.builtin.empty()) jobs.push_back({"builtin:" + args.builtin, false, {}, {}});
    for (const std::string& input : args.inputs) jobs.push_back({input, true, {}, {}});
    io::OutputPlan plan;
    for (const std::string& input : args.inputs) plan.add_input(input);
    for (BakeJob& j : jobs) {
        const std::string base =
            output_base(args, j.from_file ? j.name : args.builtin, j.from_file);
        // A PNG pair (and the plateau layer's PNG when there is one), else one .ktx2.
        if (args.format == LeanFileFormat::Png) {
            j.outputs = {base + ".lean1.png", base + ".lean2.png"};
            if (args.plateau_epsilon > 0.0f) j.outputs.push_back(base + io::kPlateauPngSuffix);
        } else {
            j.outputs = {!args.output.empty() ? args.output : base + ".ktx2"};
        }
        if (!args.writes_lean_map) j.outputs.clear();
        for (const std::string& output : j.outputs) {
            // An output that is its own input (`bake map.ktx2`) fails that input alone, once it is
            // read, so that a file that is not an image is named as such; nothing is written.
            std::error_code error;
            if (j.from_file && fs::equivalent(output, j.name, error) && !error) {
                j.output_is_input = output;
                continue;
            }
            plan.add_output(output, "the output of " + j.name,
                            args.format == LeanFileFormat::Png ? ".png" : ".ktx2");
        }
    }
    if (!args.json.empty()) plan.add_output(args.json, "--json");
    plan_roughness_outputs(args.roughness, job_count(args), args.bake_roughness, plan);
    plan_plateau_output(args.plateau_out, job_count(args), plan);
    if (args.ktx2_2d) {
        if (job_count(args) != 1 || args.format != LeanFileFormat::Ktx2 || !args.writes_lean_map)
            throw Error("--ktx2-2d", "needs one input baked to a .ktx2 LEAN map");
        const auto [lean1, lean2] = layer_texture_paths(jobs.front().outputs.front());
        plan.add_output(lean1, "--ktx2-2d");
        plan.add_output(lean2, "--ktx2-2d");
    }
    plan.check();
    return jobs;
}

const std::vector<std::pair<std::string, LeanFileFormat>>& lean_file_format_names() {
    static const std::vector<std::pair<std::string, LeanFileFormat>> names{
        {format_name(LeanFileFormat::Ktx2), LeanFileFormat::Ktx2},
        {format_name(LeanFileFormat::Png), LeanFileFormat::Png}};
    return names;
}

const std::vector<std::pair<std::string, bool>>& scale_rule_names() {
    static const std::vector<std::pair<std::string, bool>> names{{"auto", true}, {"max", false}};
    return names;
}

std::string generator_string() {
    return std::string(LEANFADE_GENERATOR);
}

}  // namespace leanfade::cli
