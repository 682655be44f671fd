// leanfade bake: height or normal maps -> LEAN maps (KTX2 with every MIP level, or PNG previews).
// The run: the plan (cli_bake_plan.hpp), then each input read, baked into its staged outputs and
// reported (cli_bake_report.hpp); the outputs are published as they are done.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_bake_cross_terms.hpp"
#include "cli_bake_gltf.hpp"
#include "cli_bake_gltf_out.hpp"
#include "cli_bake_plan.hpp"
#include "cli_bake_plateau.hpp"
#include "cli_bake_report.hpp"
#include "cli_bake_roughness.hpp"
#include "cli_text.hpp"
#include "command.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/io/detail/png_io.hpp"
#include "leanfade/scene/gltf.hpp"

namespace leanfade::cli {
namespace {

// The cross-term texture of two bump layers (cli_bake_cross_terms.cpp). Every option that the
// kind of bake does not honour is refused by name, rather than ignored (an output asked for and
// never written).
int run_cross_terms_bake(const BakeArgs& given) {
    const std::string refused = first_inapplicable(given, kCrossTermsBake);
    if (!refused.empty())
        throw Error(refused, "does not apply to --cross-terms (it takes " +
                                 applicable_flags_text(kCrossTermsBake) + ")");
    return run_bake_cross_terms({given.cross_terms, given.output, given.from, given.directx,
                                 given.strength, given.size, given.seed, given.max_size});
}

bool is_gltf_bake(const BakeArgs& given) {
    return given.inputs.size() == 1 && given.builtin.empty() &&
           scene::is_gltf_path(given.inputs[0]);
}

// A glTF scene: every normal texture of it (cli_bake_gltf.cpp).
int run_gltf_bake(const BakeArgs& given) {
    GltfBakeArgs gltf{given.inputs[0],      given.out_dir,          given.bits,
                      given.threads,        given.max_size,         given.json,
                      given.fsync,          given.strict_normals,   given.supercompression,
                      given.zstd_level,
                      // KHR_texture_basisu's images are Basis Universal unless --compress none.
                      given.roughness.compression_given ? given.roughness.compression
                                                        : io::BlockCompression::Basis,
                      {}};
    std::string refused = first_inapplicable(given, kGltfBake);
    // --compress: the engine textures of the filtered copy (-o) only.
    if (refused.empty() && given.output.empty() && given.roughness.compression_given)
        refused = "--compress";
    if (!refused.empty()) gltf.refused_flags.push_back(refused);
    // The folder of -o, or a missing --out-dir, is created as for any bake, and removed again if
    // the run writes nothing into it.
    const io::CreatedFolders out_folder(given.out_dir);
    const io::CreatedFolders output_folder(
        given.output.empty() ? std::string() : std::filesystem::path(given.output).parent_path().string());
    // -o OUT.gltf|OUT.glb: a filtered copy of the scene (cli_bake_gltf_out.hpp).
    if (!given.output.empty()) return run_bake_gltf_out(gltf, given.output);
    return run_bake_gltf(gltf);
}

// One job's input: 8- and 16-bit files stay integer samples (half the memory of floats).
std::variant<Image, UnormImage> read_job_input(const BakeJob& job, const BakeArgs& args,
                                               const BakeRunSettings& settings) {
    if (job.from_file) return io::read_image_compact(job.name, settings.read_options);
    return make_builtin_height(args.builtin, args.size, args.seed);
}

// One job's LEAN map, baked into its staged outputs.
struct StagedBake {
    PackedBakeResult baked;
    std::string output;  // as reported: the .ktx2, or NAME.lean{1,2}.png
    std::string staged;  // a KTX2 bake: the staged file, complete, not yet published
};

// The fused fast path: the same bytes as pack_lean_map(bake_lean_map(...)), plus the summary,
// without the float MIP chain (docs/perf.md). A PNG pair in the storage asked for; a KTX2 file
// baked straight into the mapped output file, which appears only when complete, by the storage
// policy.
// `moments`: the engine textures' sink, or empty.
StagedBake bake_to_staged_outputs(const BakeJob& job, const std::variant<Image, UnormImage>& input,
                                  BakeSource kind, const BakeArgs& args,
                                  const BakeRunSettings& settings, io::OutputTransaction& outputs,
                                  const MomentRunSink& moments) {
    StagedBake result;
    const BakeInput samples(input, kind, job.name);
    if (args.format == LeanFileFormat::Png) {
        // The pair's files were planned with the plateau layer: it stays, empty or not.
        PackedMapSink memory;
        memory.moments = moments;
        result.baked = bake(samples,
                            BakeSettings{.options = settings.options,
                                         .storage = StoragePolicy::fixed(settings.storage.storage),
                                         .generator = generator_string(),
                                         .keep_empty_plateau = true},
                            memory);
        io::write_lean_png_pair(
            outputs.stage(job.outputs[0]), outputs.stage(job.outputs[1]), result.baked.packed,
            settings.write_options, job.outputs.size() > 2 ? outputs.stage(job.outputs[2]) : "");
        result.output = job.outputs[0].substr(0, job.outputs[0].size() - 10) +
                        (job.outputs.size() > 2 ? ".{lean1,lean2,plateau}.png" : ".lean{1,2}.png");
        return result;
    }
    result.output = job.outputs[0];
    result.staged = outputs.stage(result.output);
    io::Ktx2FileSink file(result.staged, settings.write_options, settings.read_options);
    file.moments = moments;
    result.baked =
        bake(samples, BakeSettings{settings.options, settings.storage, generator_string()}, file);
    return result;
}

// The files and folders a bake writes besides the LEAN map (one input only).
std::vector<std::string> engine_outputs(const BakeArgs& args) {
    std::vector<std::string> files;
    if (!args.roughness.roughness_out.empty()) {
        files.push_back(args.roughness.roughness_out);
        files.push_back(normal_output_path(args.roughness.roughness_out));
    }
    if (!args.roughness.anisotropy_out.empty()) files.push_back(args.roughness.anisotropy_out);
    if (args.roughness.png_levels) files.push_back(levels_folder_path(args.roughness) + "/");
    if (!args.plateau_out.empty()) files.push_back(args.plateau_out);
    return files;
}

// The jobs of one run, in order. One input: its outputs and --json are published together. A
// batch publishes each input's outputs when they are done, and --json at the end; a failed
// input is reported and the others go on.
class BakeRun {
  public:
    BakeRun(const BakeArgs& args, const BakeRunSettings& settings, const std::vector<BakeJob>& jobs)
        : args_(args),
          settings_(settings),
          jobs_(jobs),
          one_group_(jobs.size() == 1),
          progress_(stderr_is_terminal()),
          run_outputs_(settings.write_options.durability) {}

    // The exit code: 0, or 1 when an input of a batch failed.
    int run() {
        for (const BakeJob& job : jobs_) bake_guarded(job);
        if (!args_.json.empty()) write_json();
        run_outputs_.publish();
        for (const BakeReport& report : reports_) print_bake_report(report);
        std::fputs(roughness_only_report_.c_str(), stdout);
        if (failures_ > 0) {
            std::fprintf(stderr, "leanfade bake: %d of %zu inputs failed\n", failures_,
                         jobs_.size());
            return 1;
        }
        return 0;
    }

  private:
    void bake_guarded(const BakeJob& job) {
        io::OutputTransaction job_outputs(settings_.write_options.durability);
        io::OutputTransaction& outputs = one_group_ ? run_outputs_ : job_outputs;
        try {
            bake_one(job, outputs);
        } catch (const Error& raw) {
            const Error e = outputs.named(raw);  // the output's name, not its temporary's
            if (progress_) std::fprintf(stderr, "\r\033[K");
            if (jobs_.size() == 1) throw e;
            std::fprintf(stderr, "leanfade bake: %s\n", terminal_text(e.what()).c_str());
            summaries_.push_back({{"input", job.name}, {"error", e.what()}});
            ++failures_;
        }
    }

    void bake_one(const BakeJob& job, io::OutputTransaction& outputs) {
        const std::string& name = job.name;
        ++done_;
        if (progress_)
            std::fprintf(stderr, "\r[%zu/%zu] baking %s...\033[K", done_, jobs_.size(),
                         terminal_text(name).c_str());
        const auto start = std::chrono::steady_clock::now();
        const std::variant<Image, UnormImage> input = read_job_input(job, args_, settings_);
        const BakeSource kind = job.from_file ? settings_.source : BakeSource::Height;
        if (!job.output_is_input.empty())
            throw Error(name, "is the same file as its output " + job.output_is_input +
                                  "; an output may not replace an input");
        // The engine textures, made inside the bake from its moments (cli_bake_roughness.hpp).
        std::optional<RoughnessExport> engine;
        if (args_.roughness.requested()) {
            const auto [width, height] = std::visit(
                [](const auto& image) { return std::pair{image.width, image.height}; }, input);
            engine.emplace(args_.roughness, width, height, settings_.options,
                           settings_.read_options, settings_.write_options, outputs);
        }
        if (!args_.writes_lean_map) {
            // Only the engine outputs.
            engine->bake_alone(input, kind, settings_.options, name);
            const int levels = engine->write();
            roughness_only_report_ = terminal_text(name) + ": " + std::to_string(levels) +
                                     " levels, no LEAN map (none asked: -o, --out-dir)\n";
            for (const std::string& file : engine_outputs(args_))
                roughness_only_report_ += "  wrote " + terminal_text(file) + "\n";
            return;
        }
        const StagedBake staged = bake_to_staged_outputs(job, input, kind, args_, settings_, outputs,
                                                         engine ? engine->sink() : MomentRunSink{});
        const PackedBakeResult& baked = staged.baked;
        // Checked before anything is published: the staged outputs are dropped.
        if (args_.strength_given && baked.source == BakeSource::Normal)
            throw Error(name, "is a normal map: --strength applies to height maps only");
        if (engine) engine->write();
        if (!args_.plateau_out.empty() || args_.ktx2_2d) {
            // From the map as stored: a KTX2 bake keeps no copy of it in memory.
            const PackedLeanMap stored =
                args_.format == LeanFileFormat::Png ? baked.packed
                                      : io::read_ktx2(staged.staged, settings_.read_options);
            if (!args_.plateau_out.empty())
                write_plateau_output(args_.plateau_out, stored, settings_.options.plateau_epsilon,
                                     settings_.options.threads,
                                     settings_.write_options, outputs);
            if (args_.ktx2_2d) {
                const auto [lean1, lean2] = layer_texture_paths(staged.output);
                io::write_ktx2_layer_textures(outputs.stage(lean1), outputs.stage(lean2), stored,
                                              settings_.write_options);
            }
        }
        if (!one_group_) outputs.publish();
        const bool other_convention =
            baked.source == BakeSource::Normal &&
            warn_if_other_convention(name, input, settings_.options.convention);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (progress_) std::fprintf(stderr, "\r\033[K");
        // What stdout reports of an output is printed once it is published (a single input's
        // reports after the whole group, --json included).
        BakeReport report = bake_report(name, staged.output, baked, seconds, other_convention);
        report.also_written = engine_outputs(args_);
        if (args_.ktx2_2d) {
            const auto [lean1, lean2] = layer_texture_paths(staged.output);
            report.also_written.push_back(lean1);
            report.also_written.push_back(lean2);
        }
        if (one_group_)
            reports_.push_back(report);
        else
            print_bake_report(report);
        summaries_.push_back(bake_report_json(report));
    }

    void write_json() {
        const std::string text =
            summaries_.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
        try {
            io::AtomicFile file(run_outputs_.stage(args_.json), settings_.write_options.durability);
            file.write(text.data(), text.size());
            file.commit();
        } catch (const Error& e) {
            throw run_outputs_.named(e);
        }
    }

    const BakeArgs& args_;
    const BakeRunSettings& settings_;
    const std::vector<BakeJob>& jobs_;
    const bool one_group_;
    const bool progress_;
    io::OutputTransaction run_outputs_;
    nlohmann::json summaries_ = nlohmann::json::array();
    std::vector<BakeReport> reports_;
    std::string roughness_only_report_;  // the engine outputs of a bake without a LEAN map
    std::size_t done_ = 0;
    int failures_ = 0;
};

int run_bake(const BakeArgs& given) {
    if (!given.cross_terms.empty()) return run_cross_terms_bake(given);
    if (is_gltf_bake(given)) return run_gltf_bake(given);
    // Flags checked before touching any file.
    const BakeArgs args = checked_bake_args(given);
    // A missing --out-dir, or the folder of -o, is created, and removed again if the run writes
    // nothing into it.
    const io::CreatedFolders out_folder(args.out_dir);
    const io::CreatedFolders output_folder(
        args.output.empty() ? std::string() : std::filesystem::path(args.output).parent_path().string());
    const BakeRunSettings settings = bake_settings(args);
    const std::vector<BakeJob> jobs = plan_bake_jobs(args);
    return BakeRun(args, settings, jobs).run();
}

const CommandRegistration registration{
    "bake", "Bake height or normal maps into LEAN maps (two RGBA layers with full MIP chains)",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<BakeArgs>();
        app.add_option("inputs", args->inputs, "Height or normal maps (PNG 8/16-bit, EXR, PFM)");
        app.add_option("-o,--output", args->output,
                       "Output file (one input only; a missing folder is created); with --format "
                       "png, the name before .lean1.png/.lean2.png");
        app.add_option("--out-dir", args->out_dir, "Folder for the outputs of a batch");
        add_typed_option(
            app, "--from", args->from,
            [](const std::string& text) { return parse_bake_source(text, "--from"); },
            "Input kind: " + name_list(bake_source_names()) +
                " (auto: 1-2 channels = height, 3-4 = normal)")
            ->check(CLI::IsMember(bake_source_names()));
        CLI::Option* strength =
            app.add_option("--strength", args->strength,
                           "Height maps: the height of one unit of value, in --strength-unit "
                           "(not 0; negative inverts the heights; an error for normal maps)")
                ->capture_default_str();
        add_named_option(app, "--strength-unit", args->strength_unit, strength_unit_names(),
                         "Unit of --strength: texel (height per texel spacing, the default: "
                         "slopes halve at twice the resolution) or uv (height per UV unit, the "
                         "map's width along u and height along v: the same slopes at any "
                         "resolution)",
                         to_string(args->strength_unit));
        app.add_flag("--directx", args->directx,
                     "Normal maps use the DirectX convention (green = -v, \"-Y\"; how to tell: "
                     "README, quick start)");
        app.add_flag("--strict-normals", args->strict_normals,
                     "Normal maps: refuse texels with z <= 0 instead of taking (0, 0, 0) padding "
                     "as flat and raising the others (counted and reported)");
        add_typed_option(
            app, "--bits", args->bits,
            [](const std::string& text) { return parse_storage_policy(text, "--bits"); },
            "Storage: " + name_list(bake_storage_names()) +
                " (8, 16: UNORM; 16f, 32f: float; auto: 16, or 16f for a map with "
                "outliers beyond sc, which 16 would clamp, or 16f/32f where 16's "
                "rounding of the moments would hide the base roughness, docs/ktx2.md; "
                "a PNG pair: 16)",
            to_string(args->bits))
            ->check(CLI::IsMember(bake_storage_names()));
        app.add_option("--bake-roughness", args->bake_roughness,
                       "Bake the base roughness 1/S of Blinn-Phong exponent S (LEAN eq. 6)")
            ->check(CLI::PositiveNumber);
        app.add_option("--plateau-epsilon", args->plateau_epsilon,
                       "Two-lobe LEAN's plateau layer (docs/math.md §10): a texel whose slope "
                       "differs from each neighbour's by less than this per component is on a "
                       "plateau; 0 bakes no layer (two-lobe then shades as LEAN)")
            ->capture_default_str();
        add_spike_option(app, args->spike_fit,
                         "Which texels form two-lobe LEAN's spike (docs/math.md §10)");
        add_named_option(app, "--sc", args->sc_excludes_outliers, scale_rule_names(),
                         "Scale sc of the slopes: auto (the steepest slope except outliers, "
                         "texels at least twice as steep as the 99.9th percentile: counted, and "
                         "clamped in 8/16-bit maps) or max (the steepest slope)",
                         "auto");
        add_named_option(app, "--wrap", args->wrap, wrap_names(),
                         "Border handling of the slope filter", to_string(args->wrap));
        add_named_option(app, "--supercompression", args->supercompression,
                         io::supercompression_names(),
                         "KTX2 LEAN maps: zstd (each MIP level a Zstandard frame, KTX2 scheme 2: "
                         "smaller files, the same GPU memory; read by leanfade, libktx and "
                         "three.js's KTX2Loader) or none (the level data as the GPU takes it)",
                         io::to_string(args->supercompression));
        app.add_option("--zstd-level", args->zstd_level,
                       "Zstandard level: 1 (fastest) to 19 (smallest; several times slower)")
            ->check(CLI::Range(1, 19))
            ->capture_default_str();
        add_named_option(app, "--format", args->format, lean_file_format_names(),
                         "ktx2 (GPU-ready, every MIP level) or png (the top level as two RGBA "
                         "PNGs of --bits 8 or 16 with sc, and NAME.plateau.png with the plateau "
                         "layer; loads back with --bumps NAME.lean1.png); default: from -o's "
                         "extension, else ktx2");
        app.get_option("--output")
            ->description("Output (one input only; a missing folder is created, and removed if "
                          "the bake fails): NAME.ktx2, or NAME.png for the PNG pair "
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
        add_plateau_bake_option(app, args->plateau_out);
        app.add_flag("--ktx2-2d", args->ktx2_2d,
                     "Also write the LEAN map's two layers as plain 2D KTX2 textures, "
                     "OUT.lean1.ktx2 and OUT.lean2.ktx2, every level, for loaders that read no "
                     "array layers (docs/ktx2.md)");
        return [args, strength, &app] {
            args->strength_given = strength->count() > 0;
            for (const CLI::Option* option : app.get_options())
                if (option->count() > 0) args->given.push_back(option->get_name());
            return run_bake(*args);
        };
    }};

}  // namespace
}  // namespace leanfade::cli
