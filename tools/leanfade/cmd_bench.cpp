// leanfade bench: frame times of the techniques by the papers' protocol (one object filling the
// screen, then near / mid / far), with overhead ratios from interleaved frames; --bake: bake
// throughput against the memory bandwidth; --generate: per-frame LEAN map generation on the GPU.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_bench_bake.hpp"
#include "cli_bench_layers.hpp"
#include "cli_bench_report.hpp"
#include "cli_render_options.hpp"
#include "cli_render_scene.hpp"
#include "command.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/detail/frame_bench.hpp"
#include "leanfade/gl/detail/generate.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

struct BenchArgs {
    FramebufferSize size{1600, 1200};
    std::vector<std::string> scenes{"sphere", "torus", "teapot", "terrain"};
    // Every real-time technique (the reference is offline), in the table's order.
    std::vector<Technique> techniques = approximating_techniques();
    std::vector<float> distances{3.0f, 8.0f, 24.0f};  // empty: none
    bool no_fill = false;
    bool no_floor = false;
    int frames = 20;
    int warmup = 3;
    gl::TimingMethod timing = gl::TimingMethod::Auto;
    std::string json;
    bool bake = false;
    std::vector<int> bake_sizes{1024, 2048, 4096, 8192};
    std::vector<std::string> bake_input{"normal", "height"};
    int bake_runs = 0;
    int threads = 0;
    bool generate = false;
    bool layer_columns = false;  // --layer-columns: the LEAN paper's Fig. 12 columns
    std::vector<int> generate_sizes{512, 1024, 2048, 4096};
    ShadingFlags shading;
    RenderSourceFlags input;  // --scene, --bumps and the layer flags
    GlFlags gl;
};

std::unique_ptr<gl::Context> make_context(const GlFlags& flags) {
    gl::ContextOptions options = context_options(flags);
    options.debug = false;  // no debug context: it slows some drivers down
    return std::make_unique<gl::Context>(options);
}

std::vector<GenerateBenchRow> run_generate_bench(gl::Context& context, const BenchArgs& args,
                                                 const std::vector<int>& sizes, Storage storage,
                                                 float strength,
                                                 const std::function<void(const std::string&)>& say,
                                                 gl::TimingChoice& timing) {
    timing = gl::choose_timing(args.timing, context);
    gl::LeanGenerator generator(context, shader_sources(args.gl));
    gl::IntervalTimer timer(timing.method);
    std::vector<GenerateBenchRow> rows;
    for (int size : sizes) {
        say("generating " + std::to_string(size) + "^2 on the GPU");
        const Image height = tiled_bumps_height(size);
        BakeOptions bake_options;
        bake_options.strength = strength;
        const SlopeResult slopes = slopes_from_height(height, bake_options, "bench");
        float max_b = 0.0f;
        for (float v : slopes.slopes.pixels) max_b = std::max(max_b, std::abs(v));
        gl::GenerateOptions options;
        options.strength = strength;
        options.scale = std::max(max_b, 1e-6f);
        options.storage = storage;
        generator.set_source(height, gl::GenerateInput::Height);
        const gl::GenerationTimes times =
            gl::time_generation(generator, options, args.frames, args.warmup, timer);
        GenerateBenchRow row;
        row.size = size;
        row.storage = to_string(storage);
        row.pass = gl::sample_stats(times.pass_ms);
        row.mipmap = gl::sample_stats(times.mipmap_ms);
        std::vector<double> total;
        for (std::size_t i = 0; i < times.pass_ms.size(); ++i)
            total.push_back(times.pass_ms[i] + times.mipmap_ms[i]);
        row.total = gl::sample_stats(total);
        row.texels_per_second =
            row.total.median > 0.0 ? double(size) * double(size) / (row.total.median * 1e-3) : 0.0;
        rows.push_back(row);
    }
    context.check("per-frame generation");
    return rows;
}

int run_bench(const BenchArgs& args) {
    // Every flag is checked before anything is measured.
    const ShadingSettings settings = resolve_shading(args.shading);
    const bool frames_mode = !args.bake && !args.generate && !args.layer_columns;
    gl::FrameBenchRequest request;
    request.width = args.size.width;
    request.height = args.size.height;
    request.techniques = args.techniques;
    request.distances = args.distances;
    request.fill = !args.no_fill;
    request.floor = !args.no_floor;
    request.frames = args.frames;
    request.warmup = args.warmup;
    request.timing = args.timing;
    request.settings = settings;
    gl::validate_frame_bench(request);
    const std::vector<std::string>& scene_names = args.scenes;
    for (std::size_t i = 0; i < scene_names.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (scene_names[i] == scene_names[j])
                throw Error("--scenes", "scene '" + scene_names[i] + "' given twice");
    const std::vector<int>& bake_sizes = args.bake_sizes;
    const std::vector<int>& generate_sizes = args.generate_sizes;
    const std::vector<std::string>& bake_inputs = args.bake_input;
    const Storage storage = args.input.bumps.bits.storage;
    if (args.threads < 0) throw Error("--threads", "must be >= 0 (0 = all hardware threads)");
    if (args.bake_runs < 0 || args.bake_runs > 1000)
        throw Error("--bake-runs", "must be in [0, 1000] (0 = by size)");
    if (!args.json.empty()) {
        // Checked before anything is measured (docs/robustness.md).
        io::OutputPlan plan;
        for (const std::string& input : scene::scene_source_inputs(args.input)) plan.add_input(input);
        plan.add_output(args.json, "--json");
        plan.check();
    }

    const bool tty = stderr_is_terminal();
    auto say = [&](const std::string& text) {
        if (tty) std::fprintf(stderr, "\r%s\033[K", text.c_str());
    };
    BenchSystem system = describe_system();
    nlohmann::json root = {{"tool", "leanfade bench"}, {"version", LEANFADE_VERSION}};
    std::string report;

    std::unique_ptr<gl::Context> context;
    if (frames_mode || args.generate || args.layer_columns) {
        context = make_context(args.gl);
        system.gl_renderer = context->renderer();
        system.gl_version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    }

    if (frames_mode) {
        say("loading the scenes and the LEAN map...");
        std::vector<scene::Scene> loaded;
        for (const std::string& name : scene_names) {
            RenderSourceFlags flags = args.input;
            flags.scene = name;
            loaded.push_back(load_render_scene(flags, settings));
        }
        std::vector<gl::FrameBenchScene> scenes;
        for (std::size_t i = 0; i < loaded.size(); ++i)
            scenes.push_back({scene_names[i], nullptr, &loaded[i]});
        const PackedLeanMap& map = loaded.front().lean_maps.front();
        gl::Renderer renderer(*context, shader_sources(args.gl));
        const gl::FrameBenchResult result =
            gl::run_frame_bench(renderer, scenes, request, [&](int done, int total) {
                say("measuring view " + std::to_string(done) + "/" + std::to_string(total) +
                    " on " + context->renderer());
            });
        system.timing = gl::to_string(result.timing.method);
        system.timing_description = result.timing.description;
        report += frame_tables(result, request);
        root["frames"] = frame_json(result, request);
        root["frames"]["lean_map"] = {{"bumps", args.input.bumps.source},
                                      {"texture_size", map.levels.front().width},
                                      {"storage", to_string(map.storage)}};
    }
    if (args.bake) {
        const BakeBenchResult bake =
            run_bake_bench(bake_inputs, bake_sizes, args.threads, args.bake_runs, say);
        report += bake_table(bake);
        root["bake"] = bake_json(bake);
    }
    if (args.generate) {
        gl::TimingChoice timing;
        const std::vector<GenerateBenchRow> rows = run_generate_bench(
            *context, args, generate_sizes, storage, settings.bump_strength, say, timing);
        system.timing = gl::to_string(timing.method);
        system.timing_description = timing.description;
        report += generate_table(rows);
        root["generate"] = generate_json(rows);
        root["generate_settings"] = {{"frames", args.frames}, {"warmup", args.warmup}};
    }
    if (args.layer_columns) {
        const std::vector<LayerBenchResult> columns =
            run_layer_bench(*context, args.gl, args.input, scene_names, request, say);
        const gl::TimingChoice timing = gl::choose_timing(request.timing, *context);
        system.timing = gl::to_string(timing.method);
        system.timing_description = timing.description;
        report += layer_bench_table(columns);
        root["fig12"] = layer_bench_json(columns);
        const LayerSettings layers = fig12_layer_settings(args.input.layers);
        root["fig12_settings"] = {{"layers", join(layers.sources)},
                                  {"layer_velocity", velocities_text(layers.velocity)},
                                  {"seconds_per_frame", request.seconds_per_round},
                                  {"size", size_text(args.size)},
                                  {"frames", args.frames},
                                  {"warmup", args.warmup}};
    }
    if (tty) std::fprintf(stderr, "\r\033[K");

    std::fputs((system_header(system) + report).c_str(), stdout);
    root["system"] = system_json(system);
    if (!args.json.empty()) {
        const std::string text = root.dump(2) + "\n";
        io::AtomicFile file(args.json);
        file.write(text.data(), text.size());
        file.commit();
        std::printf("\nJSON written to %s\n", args.json.c_str());
    }
    return 0;
}

const CommandRegistration registration{
    "bench",
    "Measure frame times of the techniques by the papers' protocol (object filling the screen, "
    "near / mid / far) with overhead ratios; --bake: bake throughput; --generate: per-frame "
    "LEAN map generation on the GPU",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<BenchArgs>();
        args->input.bumps.texture_size = 1024;
        add_size_option(app, "--size", args->size, "Framebuffer size, WIDTHxHEIGHT pixels");
        add_typed_option(
            app, "--scenes", args->scenes,
            [](const std::string& text) {
                const std::vector<std::string> names = parse_names(text);
                for (std::size_t i = 0; i < names.size(); ++i)
                    for (std::size_t j = 0; j < i; ++j)
                        if (names[i] == names[j])
                            throw Error("--scenes", "scene '" + names[i] + "' given twice");
                return names;
            },
            "Objects, comma-separated: " + scene::scene_choices_text(), join(args->scenes));
        add_typed_option(
            app, "--techniques", args->techniques,
            [](const std::string& text) { return parse_techniques(text, "--techniques"); },
            "Techniques, comma-separated (default: every real-time technique: " +
                join_technique_names(args->techniques) + ")");
        add_typed_option(
            app, "--distances", args->distances,
            [](const std::string& text) {
                return text.empty() || text == "none" ? std::vector<float>{}
                                                      : parse_distances(text, "--distances");
            },
            "Camera distances of the near / mid / far views in bounding radii, in (1, 1e4], or "
            "'none'",
            "3,8,24");
        app.add_flag("--no-fill", args->no_fill, "Skip the object-filling-the-screen view");
        app.add_flag("--no-floor", args->no_floor, "Skip the constant-colour fill-rate floor");
        app.add_option("--frames", args->frames,
                       "Timed frames per technique and view (generation: per size)")
            ->capture_default_str();
        app.add_option("--warmup", args->warmup, "Untimed frames first")->capture_default_str();
        add_typed_option(
            app, "--timing", args->timing,
            [](const std::string& text) { return gl::parse_timing_method(text, "--timing"); },
            "auto (GPU timer queries unless the renderer is a software one), gpu "
            "(GL_TIME_ELAPSED), cpu (glFinish + steady clock) or cputime (glFinish + the "
            "process's CPU time: software renderers on a busy machine)",
            "auto");
        app.add_option("--json", args->json, "Also write the results as JSON");
        app.add_flag("--bake", args->bake,
                     "Measure bake throughput (MB/s, texels/s) against the memory bandwidth");
        add_typed_option(
            app, "--bake-sizes", args->bake_sizes,
            [](const std::string& text) {
                return parse_sizes(text, "--bake-sizes", kMinTextureSize,
                                   kDefaultMaxImageDimension);
            },
            "Sizes of --bake, texels per side", "1024,2048,4096,8192");
        add_typed_option(
            app, "--bake-input", args->bake_input,
            [](const std::string& text) {
                const std::vector<std::string> inputs = parse_names(text);
                for (const std::string& input : inputs)
                    if (input != "normal" && input != "height")
                        throw Error("--bake-input",
                                    "expected normal or height, got '" + input + "'");
                return inputs;
            },
            "Inputs of --bake, comma-separated: normal (3 floats per texel), height",
            join(args->bake_input));
        app.add_option("--bake-runs", args->bake_runs,
                       "Timed bakes per size (0: 5 up to 2048, 3 at 4096, 2 above)")
            ->capture_default_str();
        app.add_option("--threads", args->threads, "Bake threads (0 = all hardware threads)")
            ->capture_default_str();
        app.add_flag("--layer-columns", args->layer_columns,
                     "The LEAN paper's Fig. 12 columns, each object filling the screen: "
                     "Blinn-Phong, single LEAN, per-frame generation, mixture textures and "
                     "mixture approximation of two layers (--layers, default bumps,noise)");
        app.add_flag("--generate", args->generate,
                     "Measure per-frame LEAN map generation on the GPU");
        add_typed_option(
            app, "--generate-sizes", args->generate_sizes,
            [](const std::string& text) {
                return parse_sizes(text, "--generate-sizes", kMinTextureSize,
                                   kDefaultMaxImageDimension);
            },
            "Sizes of --generate, texels per side", "512,1024,2048,4096");
        add_shading_options(app, args->shading);
        add_lean_source_options(app, args->input.bumps);
        add_layer_options(app, args->input.layers);
        add_gl_options(app, args->gl);
        return [args] { return run_bench(*args); };
    }};

}  // namespace
}  // namespace leanfade::cli
