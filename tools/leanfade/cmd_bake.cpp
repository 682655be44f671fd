// leanfade bake: height or normal maps -> LEAN maps (KTX2 with every MIP level, or PNG previews).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "cli_bake_cross_terms.hpp"
#include "cli_bake_roughness.hpp"
#include "cli_bake_gltf.hpp"
#include "cli_flags.hpp"
#include "command.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/procedural.hpp"
#include "leanfade/core/text.hpp"
#include "leanfade/io/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/output_plan.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/io/png_io.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

struct BakeArgs {
    std::vector<std::string> inputs;
    std::string output;
    std::string out_dir;
    std::string from = "auto";
    float strength = 1.0f;
    bool strength_given = false;  // --strength on the command line (an error for normal maps)
    std::string strength_unit = "texel";
    std::string sc = "auto";
    bool directx = false;
    bool strict_normals = false;
    std::string bits = "auto";  // auto: 16, or 16f for a map with outliers beyond sc
    float bake_roughness = 0.0f;
    std::string wrap = "repeat";
    std::string format;  // ktx2 or png; "" = from -o's extension, else ktx2
    int threads = 0;
    bool fsync = false;
    std::string builtin;
    std::string cross_terms;  // --cross-terms A,B (cli_bake_cross_terms.hpp)
    int size = 1024;
    std::uint32_t seed = 1;
    int max_size = kDefaultMaxImageDimension;
    std::string json;
    RoughnessBakeArgs roughness;  // --roughness-out and its flags (cli_bake_roughness.hpp)
    std::vector<std::string> given;  // the options given on the command line, by long name
};

// The first option given that is not one of `applicable` ("" when all are).
std::string first_inapplicable(const BakeArgs& args,
                               std::initializer_list<std::string_view> applicable) {
    for (const std::string& option : args.given)
        if (std::find(applicable.begin(), applicable.end(), option) == applicable.end())
            return option;
    return {};
}

std::string generator_string() {
    return std::string("leanfade ") + LEANFADE_VERSION;
}

bool has_extension(const std::string& path, const char* extension) {
    std::string e = fs::path(path).extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e == extension;
}

// The output format: --format, else png for an -o named .png, else ktx2. An -o whose extension
// (.png or .ktx2) contradicts --format is refused.
std::string resolve_format(const BakeArgs& args) {
    const bool png_name = !args.output.empty() && has_extension(args.output, ".png");
    const bool ktx2_name = !args.output.empty() && has_extension(args.output, ".ktx2");
    if (args.format.empty()) return png_name ? "png" : "ktx2";
    if ((args.format == "png" && ktx2_name) || (args.format == "ktx2" && png_name))
        throw Error("-o", "'" + args.output + "' does not name a " + args.format +
                              " output (--format " + args.format + ")");
    return args.format;
}

// Where one input's output goes: -o, else --out-dir or the input's folder, named after the input.
std::string output_base(const BakeArgs& args, const std::string& input_name, bool from_file) {
    if (!args.output.empty()) {
        fs::path out(args.output);
        if (args.format == "png" && has_extension(args.output, ".png")) out.replace_extension();
        return out.string();
    }
    fs::path stem = fs::path(input_name).stem();
    fs::path folder = !args.out_dir.empty() ? fs::path(args.out_dir)
                      : from_file           ? fs::path(input_name).parent_path()
                                            : fs::path();
    return (folder / stem).string();
}

// Every step-th texel of the first 3 channels, at most 512 per side: enough for the convention
// check, in bounded memory for any input.
Image convention_sample(const std::variant<Image, UnormImage>& input) {
    const Image* floats = std::get_if<Image>(&input);
    const UnormImage* unorm = std::get_if<UnormImage>(&input);
    const int w = floats != nullptr ? floats->width : unorm->width;
    const int h = floats != nullptr ? floats->height : unorm->height;
    const int channels = floats != nullptr ? floats->channels : unorm->channels;
    const int step = std::max(1, (std::max(w, h) + 511) / 512);
    Image sample((w + step - 1) / step, (h + step - 1) / step, 3);
    if (channels < 3) return Image();
    for (int y = 0; y < sample.height; ++y)
        for (int x = 0; x < sample.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const std::size_t i =
                    (std::size_t(y * step) * std::size_t(w) + std::size_t(x * step)) *
                        std::size_t(channels) +
                    std::size_t(c);
                sample.at(x, y, c) = floats != nullptr
                                         ? floats->pixels[i]
                                         : float(unorm->samples[i]) / float(unorm->max_value);
            }
    return sample;
}

// A warning when a normal map's slopes fit a height field clearly better in the other convention
// (check_normal_convention).
// Returns whether it warned (the summary's looks_like_other_convention).
bool warn_if_other_convention(const std::string& name,
                              const std::variant<Image, UnormImage>& input,
                              NormalConvention convention) {
    const NormalConventionCheck check =
        check_normal_convention(convention_sample(input), convention);
    if (!check.looks_flipped()) return false;
    std::fprintf(stderr, "leanfade bake: warning: %s\n",
                 convention_warning(name, convention == NormalConvention::DirectX,
                                    check.curl_as_read / std::max(check.curl_flipped, 1e-30))
                     .c_str());
    return true;
}

nlohmann::json summary_json(const std::string& input, const std::string& output,
                            const LeanMapSummary& s, const BakeResult& result,
                            const std::string& storage, double seconds) {
    return {{"input", input},
            {"output", output},
            {"source", to_string(result.source)},
            {"width", s.width},
            {"height", s.height},
            {"levels", s.levels},
            {"scale", s.scale},
            {"mean_slope", s.mean_slope},
            {"max_slope", s.max_slope},
            {"coarsest_covariance",
             {s.coarsest_covariance.x, s.coarsest_covariance.y, s.coarsest_covariance.z}},
            {"coarsest_anisotropy", std::isfinite(s.coarsest_anisotropy)
                                        ? nlohmann::json(s.coarsest_anisotropy)
                                        : nlohmann::json("inf")},
            {"clamped_normals", result.clamped_texels},
            {"padding_texels", result.map.normal_repairs.padding_texels},
            {"raised_normals", result.map.normal_repairs.raised_texels},
            {"texels_beyond_sc", result.map.texels_beyond_scale},
            {"storage", storage},
            {"roughness_baked", result.map.roughness_baked},
            {"seconds", seconds}};
}

void print_summary(const std::string& input, const std::string& output, const LeanMapSummary& s,
                   const BakeResult& result, Storage storage, double seconds) {
    std::printf("%s -> %s\n", terminal_text(input).c_str(), terminal_text(output).c_str());
    std::printf("  %dx%d, %d levels, %s map, sc = %.6g, storage %s\n", s.width, s.height,
                s.levels, to_string(result.source), s.scale, to_string(storage));
    std::printf("  slope |B|: mean %.4f, max %.4f\n", s.mean_slope, s.max_slope);
    std::printf("  coarsest level: covariance (xx %.5f, yy %.5f, xy %.5f), anisotropy %.3g\n",
                s.coarsest_covariance.x, s.coarsest_covariance.y, s.coarsest_covariance.z,
                s.coarsest_anisotropy);
    if (result.clamped_texels > 0)
        std::printf("  %zu normals had z < %.4f and were raised to it\n", result.clamped_texels,
                    kMinNormalZ);
    if (result.map.normal_repairs.any())
        std::printf("  %s\n", normal_repairs_note(input, result.map.normal_repairs).c_str());
    const std::uint64_t beyond = result.map.texels_beyond_scale;
    if (beyond > 0) {
        const double percent = 100.0 * double(beyond) / (double(s.width) * double(s.height));
        const bool unorm = storage == Storage::Unorm8 || storage == Storage::Unorm16;
        std::printf("  %llu texels (%.3g %%) have a slope component above sc (up to %.4g): %s\n",
                    static_cast<unsigned long long>(beyond), percent, s.max_slope,
                    unorm ? "clamped to sc in this UNORM map (docs/ktx2.md, \"Choosing storage "
                            "and sc\")"
                          : "kept, beyond [0, 1], by the float storage");
    }
    std::printf("  %.3f s\n", seconds);
}

int run_bake(const BakeArgs& given) {
    // The cross-term texture of two bump layers (cli_bake_cross_terms.cpp).
    // Every option that the kind of bake does not honour is refused by name, rather than
    // ignored (an output asked for and never written).
    if (!given.cross_terms.empty()) {
        const std::string refused =
            first_inapplicable(given, {"--cross-terms", "--output", "--from", "--directx",
                                       "--strength", "--size", "--seed", "--max-size"});
        if (!refused.empty())
            throw Error(refused,
                        "does not apply to --cross-terms (it writes the one texture of "
                        "-o, from --from, --directx, --strength, --size, --seed and "
                        "--max-size)");
        return run_bake_cross_terms({given.cross_terms, given.output, given.from, given.directx,
                                     given.strength, given.size, given.seed, given.max_size});
    }
    // A glTF scene: every normal texture of it (cli_bake_gltf.cpp).
    if (given.inputs.size() == 1 && given.builtin.empty() &&
        scene::is_gltf_path(given.inputs[0])) {
        GltfBakeArgs gltf{given.inputs[0], given.out_dir, given.bits,  given.threads,
                          given.max_size,  given.json,    given.fsync, given.strict_normals,
                          {}};
        const std::string refused =
            first_inapplicable(given, {"inputs", "--out-dir", "--bits", "--threads",
                                       "--max-size", "--json", "--fsync", "--strict-normals"});
        if (!refused.empty()) gltf.refused_flags.push_back(refused);
        return run_bake_gltf(gltf);
    }
    // Validate flags before touching any file.
    BakeArgs args = given;
    args.format = resolve_format(given);
    if (!std::isfinite(args.strength)) throw Error("--strength", "must be a finite number");
    if (args.strength == 0.0f)
        throw Error("--strength", "must not be 0 (a negative strength inverts the heights)");
    if (args.strength_given && args.from == "normal")
        throw Error("--strength", "applies to height maps; --from normal bakes normal maps");
    if (!(args.bake_roughness >= 0.0f) || !std::isfinite(args.bake_roughness))
        throw Error("--bake-roughness", "must be a positive shininess");
    if (args.inputs.empty() && args.builtin.empty())
        throw Error("bake", "no input: give image files or --builtin NAME");
    const std::size_t job_count = args.inputs.size() + (args.builtin.empty() ? 0 : 1);
    if (!args.output.empty() && job_count > 1)
        throw Error("-o", "one output for " + std::to_string(job_count) +
                              " inputs; use --out-dir for a batch");
    // A missing --out-dir is created, and removed again if the run writes nothing into it.
    const io::CreatedFolders out_folder(args.out_dir);

    if (args.format == "png" && args.bits != "8" && args.bits != "16" && args.bits != "auto")
        throw Error("--bits", "a PNG pair holds 8 or 16 bits; " + args.bits +
                                  " needs --format ktx2");

    BakeOptions options;
    options.strength = args.strength;
    options.strength_unit = args.strength_unit == "uv" ? StrengthUnit::Uv : StrengthUnit::Texel;
    options.scale_excludes_outliers = args.sc == "auto";
    options.wrap = args.wrap == "clamp" ? Wrap::Clamp : Wrap::Repeat;
    options.convention = args.directx ? NormalConvention::DirectX : NormalConvention::OpenGL;
    options.bake_roughness_shininess = args.bake_roughness;
    options.threads = args.threads;
    options.strict_normals = args.strict_normals;
    const BakeSource source = parse_bake_source(args.from);
    // auto: 16-bit UNORM; a map with outliers beyond sc (choose_lean_scale), or whose UNORM
    // second moments would round away the base roughness, is baked again as half float
    // (leanfade::auto_storage; docs/ktx2.md, "Choosing storage and sc"). PNG pairs: 16.
    const bool auto_storage = args.bits == "auto";
    const Storage storage = parse_bake_storage(args.bits);
    io::ReadOptions read_options;
    read_options.max_dimension = args.max_size;
    read_options.drop_alpha = true;  // normal maps use RGB only
    io::WriteOptions write_options;
    write_options.durability = args.fsync ? io::Durability::Flush : io::Durability::Rename;
    write_options.threads = args.threads;

    // Every output of the run, checked before anything is read: a regular file (or a new one) in
    // a writable folder, not an input, not the output of another input (docs/robustness.md).
    struct Job {
        std::string name;
        bool from_file = false;
        std::vector<std::string> outputs;  // the .ktx2, or the .lean1.png and .lean2.png
        std::string output_is_input;       // an output that is this job's own input
    };
    std::vector<Job> jobs;
    if (!args.builtin.empty()) jobs.push_back({"builtin:" + args.builtin, false, {}, {}});
    for (const std::string& input : args.inputs) jobs.push_back({input, true, {}, {}});
    io::OutputPlan plan;
    for (const std::string& input : args.inputs) plan.add_input(input);
    for (Job& j : jobs) {
        const std::string base =
            output_base(args, j.from_file ? j.name : args.builtin, j.from_file);
        if (args.format == "png")
            j.outputs = {base + ".lean1.png", base + ".lean2.png"};
        else
            j.outputs = {!args.output.empty() ? args.output : base + ".ktx2"};
        for (const std::string& output : j.outputs) {
            // An output that is its own input (`bake map.ktx2`) fails that input alone, once it is
            // read, so that a file that is not an image is named as such; nothing is written.
            std::error_code error;
            if (j.from_file && fs::equivalent(output, j.name, error) && !error) {
                j.output_is_input = output;
                continue;
            }
            plan.add_output(output, "the output of " + j.name);
        }
    }
    if (!args.json.empty()) plan.add_output(args.json, "--json");
    plan_roughness_outputs(args.roughness, job_count, args.bake_roughness, plan);
    plan.check();

    // One input: its outputs and --json are published together. A batch publishes each input's
    // outputs when they are done, and --json at the end.
    const bool one_group = job_count == 1;
    io::OutputTransaction run_outputs(write_options.durability);

    nlohmann::json summaries = nlohmann::json::array();
    int failures = 0;
    const bool progress = stderr_is_terminal();
    std::size_t job = 0;
    // What stdout reports of an output is printed once it is published (a single input's
    // reports after the whole group, --json included).
    std::vector<std::function<void()>> reports;
    auto bake_one = [&](const Job& j, io::OutputTransaction& outputs) {
        const std::string& name = j.name;
        const bool from_file = j.from_file;
        ++job;
        if (progress)
            std::fprintf(stderr, "\r[%zu/%zu] baking %s...\033[K", job, job_count,
                         terminal_text(name).c_str());
        const auto start = std::chrono::steady_clock::now();
        // 8- and 16-bit files stay integer samples (half the memory of floats).
        const std::variant<Image, UnormImage> input =
            from_file ? io::read_image_compact(name, read_options)
                      : std::variant<Image, UnormImage>(
                            make_builtin_height(args.builtin, args.size, args.seed));
        // The fused fast path: the same bytes as pack_lean_map(bake_lean_map(...)), plus the
        // summary, without the float MIP chain (docs/perf.md).
        const BakeSource kind = from_file ? source : BakeSource::Height;
        if (!j.output_is_input.empty())
            throw Error(name, "is the same file as its output " + j.output_is_input +
                                  "; an output may not replace an input");
        std::string output;
        PackedBakeResult baked;
        if (args.format == "png") {
            Image converted;
            const Image* floats = std::get_if<Image>(&input);
            if (floats == nullptr) floats = &(converted = std::get<UnormImage>(input).to_float());
            baked = bake_packed(*floats, kind, options, storage, generator_string(), name);
            io::write_lean_png_pair(outputs.stage(j.outputs[0]), outputs.stage(j.outputs[1]),
                                    baked.packed, write_options);
            output = j.outputs[0].substr(0, j.outputs[0].size() - 10) + ".lean{1,2}.png";
        } else {
            output = j.outputs[0];
            // Baked straight into the mapped output file, which appears only when complete.
            const std::string staged = outputs.stage(output);
            baked = bake_with_auto_storage(storage, auto_storage, [&](Storage s) {
                return io::bake_to_ktx2(staged, input, kind, options, s, generator_string(), name,
                                        write_options);
            });
        }
        // Checked before anything is published: the staged outputs are dropped.
        if (args.strength_given && baked.source == BakeSource::Normal)
            throw Error(name, "is a normal map: --strength applies to height maps only");
        if (args.roughness.requested())
            write_roughness_outputs(args.roughness, input, kind, options, read_options,
                                    write_options, outputs);
        if (!one_group) outputs.publish();
        const bool other_convention =
            baked.source == BakeSource::Normal &&
            warn_if_other_convention(name, input, options.convention);
        const PackedLeanMap& packed = baked.packed;
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (progress) std::fprintf(stderr, "\r\033[K");
        // What print_summary and summary_json read of a BakeResult: the source, the clamped
        // count and the roughness flag.
        BakeResult result;
        result.source = baked.source;
        result.clamped_texels = baked.clamped_texels;
        result.map.roughness_baked = packed.roughness_baked;
        result.map.texels_beyond_scale = baked.texels_beyond_scale;
        result.map.normal_repairs = packed.normal_repairs;
        const LeanMapSummary& s = baked.summary;
        const Storage stored = packed.storage;
        auto report = [name, output, s, result, stored, seconds] {
            print_summary(name, output, s, result, stored, seconds);
        };
        if (one_group)
            reports.push_back(report);
        else
            report();
        summaries.push_back(
            summary_json(name, output, s, result, to_string(packed.storage), seconds));
        summaries.back()["looks_like_other_convention"] = other_convention;
    };

    auto guarded = [&](const Job& j) {
        io::OutputTransaction job_outputs(write_options.durability);
        io::OutputTransaction& outputs = one_group ? run_outputs : job_outputs;
        try {
            bake_one(j, outputs);
        } catch (const Error& raw) {
            const Error e = outputs.named(raw);  // the output's name, not its temporary's
            if (progress) std::fprintf(stderr, "\r\033[K");
            if (job_count == 1) throw e;
            std::fprintf(stderr, "leanfade bake: %s\n", terminal_text(e.what()).c_str());
            summaries.push_back({{"input", j.name}, {"error", e.what()}});
            ++failures;
        }
    };
    for (const Job& j : jobs) guarded(j);

    if (!args.json.empty()) {
        const std::string text =
            summaries.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
        try {
            io::AtomicFile file(run_outputs.stage(args.json), write_options.durability);
            file.write(text.data(), text.size());
            file.commit();
        } catch (const Error& e) {
            throw run_outputs.named(e);
        }
    }
    run_outputs.publish();
    for (const auto& report : reports) report();
    if (failures > 0) {
        std::fprintf(stderr, "leanfade bake: %d of %zu inputs failed\n", failures, job_count);
        return 1;
    }
    return 0;
}

const CommandRegistration registration{
    "bake", "Bake height or normal maps into LEAN maps (two RGBA layers with full MIP chains)",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<BakeArgs>();
        app.add_option("inputs", args->inputs, "Height or normal maps (PNG 8/16-bit, EXR, PFM)");
        app.add_option("-o,--output", args->output,
                       "Output file (one input only); with --format png, the name before "
                       ".lean1.png/.lean2.png");
        app.add_option("--out-dir", args->out_dir, "Folder for the outputs of a batch");
        app.add_option("--from", args->from,
                       "Input kind: " + name_list(bake_source_names()) +
                           " (auto: 1-2 channels = height, 3-4 = normal)")
            ->check(CLI::IsMember(bake_source_names()));
        CLI::Option* strength =
            app.add_option("--strength", args->strength,
                           "Height maps: the height of one unit of value, in --strength-unit "
                           "(not 0; negative inverts the heights; an error for normal maps)")
                ->capture_default_str();
        app.add_option("--strength-unit", args->strength_unit,
                       "Unit of --strength: texel (height per texel spacing, the default: "
                       "slopes halve at twice the resolution) or uv (height per UV unit, the "
                       "map's width along u and height along v: the same slopes at any "
                       "resolution)")
            ->check(CLI::IsMember({"texel", "uv"}))
            ->capture_default_str();
        app.add_flag("--directx", args->directx,
                     "Normal maps use the DirectX convention (green = -v, \"-Y\"; how to tell: "
                     "README, quick start)");
        app.add_flag("--strict-normals", args->strict_normals,
                     "Normal maps: refuse texels with z <= 0 instead of taking (0, 0, 0) padding "
                     "as flat and raising the others (counted and reported)");
        app.add_option("--bits", args->bits,
                       "Storage: " + name_list(bake_storage_names()) +
                           " (8, 16: UNORM; 16f, 32f: float; auto: 16, or 16f for a map with "
                           "outliers beyond sc, which 16 would clamp, or 16f/32f where 16's "
                           "rounding of the moments would hide the base roughness, docs/ktx2.md; "
                           "a PNG pair: 16)")
            ->check(CLI::IsMember(bake_storage_names()))
            ->capture_default_str();
        app.add_option("--bake-roughness", args->bake_roughness,
                       "Bake the base roughness 1/S of Blinn-Phong exponent S (LEAN eq. 6)")
            ->check(CLI::PositiveNumber);
        app.add_option("--sc", args->sc,
                       "Scale sc of the slopes: auto (the steepest slope except outliers, "
                       "texels at least twice as steep as the 99.9th percentile: counted, and "
                       "clamped in 8/16-bit maps) or max (the steepest slope)")
            ->check(CLI::IsMember({"auto", "max"}))
            ->capture_default_str();
        app.add_option("--wrap", args->wrap, "Border handling of the slope filter")
            ->check(CLI::IsMember({"repeat", "clamp"}))
            ->capture_default_str();
        app.add_option("--format", args->format,
                       "ktx2 (GPU-ready, every MIP level) or png (the top level as two RGBA PNGs "
                       "of --bits 8 or 16 with sc; loads back with --bumps NAME.lean1.png); "
                       "default: from -o's extension, else ktx2")
            ->check(CLI::IsMember({"ktx2", "png"}));
        app.get_option("--output")
            ->description("Output (one input only): NAME.ktx2, or NAME.png for the PNG pair "
                          "NAME.lean1.png + NAME.lean2.png");
        app.add_flag("--fsync", args->fsync,
                     "Flush each output to disk before it replaces the old one (survives a "
                     "power cut; slower)");
        app.add_option("--threads", args->threads, "Worker threads (0 = all cores)")
            ->check(CLI::Range(0, 256));
        app.add_option("--builtin", args->builtin, "Bake a built-in bump set instead of a file")
            ->check(CLI::IsMember(builtin_bump_names()));
        app.add_option("--size", args->size, "Built-in set size in texels")
            ->check(CLI::Range(4, kDefaultMaxImageDimension))
            ->capture_default_str();
        app.add_option("--seed", args->seed, "Built-in set seed")->capture_default_str();
        app.add_option("--cross-terms", args->cross_terms,
                       "Write the cross-term texture of two aligned bump layers A,B (built-in "
                       "sets, images or .ktx2) to -o FILE.ktx2 (docs/ktx2.md)");
        app.add_option("--max-size", args->max_size,
                       "Largest accepted input width or height (refused before decoding)")
            ->check(CLI::Range(1, 1 << 20))
            ->capture_default_str();
        app.add_option("--json", args->json, "Also write the summaries as JSON");
        add_roughness_bake_options(app, args->roughness);
        return [args, strength, &app] {
            args->strength_given = strength->count() > 0;
            for (const CLI::Option* option : app.get_options())
                if (option->count() > 0) args->given.push_back(option->get_name());
            return run_bake(*args);
        };
    }};

}  // namespace
}  // namespace leanfade::cli
