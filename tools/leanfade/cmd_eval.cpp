// leanfade eval: every technique against the supersampled ground truth (docs/math.md §7) over a
// sweep of distances and shininesses: specular energy, error (relative RMSE, SSIM) and flicker,
// written as results.csv, results.json, gnuplot plots and an index.html report.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

#include "cli_ocean.hpp"
#include "cli_preset.hpp"
#include "cli_render_options.hpp"
#include "cli_render_scene.hpp"
#include "command.hpp"
#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/eval/runner.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "leanfade/core/technique.hpp"

namespace leanfade::cli {
namespace {

// The most bump maps one eval sweeps (--seeds).
constexpr int kMaxEvalSeeds = 64;
constexpr const char* kDefaultDistances = "2:64:6";

struct EvalArgs {
    std::vector<Technique> techniques = approximating_techniques();
    std::vector<float> distances = eval::parse_distance_sweep(kDefaultDistances);
    std::vector<float> shininess{128, 1024, 13777};
    int spp = 64;
    int frames = 16;
    float motion = 0.25f;
    bool fixed_spp = false;
    FramebufferSize size{256, 256};
    float fov = gl::kDefaultFovYDegrees;
    glm::vec3 view_dir = kDefaultViewDirection;  // from the object's centre toward the eye
    std::string out = "eval";
    std::string replot;
    int seeds = 1;  // independent bump maps of a built-in set: --seed, --seed + 1, ...
    ShadingFlags shading;
    RenderSourceFlags input;  // --scene, --bumps and the layer flags
    GlFlags gl;
};

std::string duration_text(double seconds) {
    char buffer[32];
    const int s = int(std::lround(seconds));
    if (s >= 60)
        std::snprintf(buffer, sizeof buffer, "%dm%02ds", s / 60, s % 60);
    else
        std::snprintf(buffer, sizeof buffer, "%ds", s);
    return buffer;
}

// --replot: the plots, results.csv and index.html again from a folder's results.json.
// The files of a report in `folder` (results.hpp: write_report), as outputs of `plan`.
void add_report_outputs(io::OutputPlan& plan, const std::string& folder, bool with_json) {
    if (with_json)
        plan.add_output((std::filesystem::path(folder) / "results.json").string(), "the report");
    for (const char* name : {"results.csv", "plot_data.tsv", "plots.gp",
                             "index.html", "energy.png", "energy_total.png", "rmse.png", "ssim.png",
                             "flicker.png"})
        plan.add_output((std::filesystem::path(folder) / name).string(), "the report");
}

// `text` with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t at = 0; !from.empty() && (at = text.find(from, at)) != std::string::npos;
         at += to.size())
        text.replace(at, from.size(), to);
    return text;
}

// The whole text of a file written by this run.
std::string read_whole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The report's notes name the temporary folder it was written in: they name `folder` instead,
// in index.html too.
void rename_folder_in_notes(std::vector<std::string>& notes, const std::string& staged,
                            const std::string& folder) {
    bool named = false;
    for (std::string& note : notes) {
        named = named || note.find(staged) != std::string::npos;
        note = replaced(note, staged, folder);
    }
    const std::string index = (std::filesystem::path(staged) / "index.html").string();
    if (named && std::filesystem::is_regular_file(index))
        eval::write_text_file(index, replaced(read_whole(index), staged, folder));
}

int run_replot(const std::string& folder) {
    // Its results.json is read, the other files of the report replaced.
    io::OutputPlan plan;
    plan.add_input(folder + "/results.json");
    plan.add_output_folder(folder, true);  // the files of add_report_outputs only
    add_report_outputs(plan, folder, false);
    plan.check();
    eval::SweepInfo info;
    std::vector<eval::CaseResult> cases;
    eval::read_results_json(folder + "/results.json", info, cases);
    // Written into a temporary folder and published into `folder` together. The report shows the
    // folder's images (seen through a link that is not published); results.json, the input, is
    // left as it is.
    namespace fs = std::filesystem;
    io::OutputTransaction outputs;
    const std::string staged = outputs.stage_folder(folder);
    const fs::path images = fs::path(folder) / "images";
    std::error_code error;
    if (fs::is_directory(images))
        fs::create_directory_symlink(fs::absolute(images), fs::path(staged) / "images", error);
    std::vector<std::string> notes = eval::write_report(staged, info, cases, {});
    rename_folder_in_notes(notes, staged, folder);
    if (!error && fs::is_symlink(fs::path(staged) / "images"))
        fs::remove(fs::path(staged) / "images");
    fs::remove(fs::path(staged) / "results.json");
    outputs.publish();
    for (const std::string& note : notes)
        std::fprintf(stderr, "leanfade eval: %s\n", note.c_str());
    std::printf("%s: redrew the plots and the report of %zu cases\n", folder.c_str(), cases.size());
    return 0;
}

int run_eval(const EvalArgs& args) {
    if (!args.replot.empty()) return run_replot(args.replot);
    const auto start = std::chrono::steady_clock::now();
    // Every flag is checked before anything is read or rendered.
    eval::SweepRequest request;
    request.settings = resolve_shading(args.shading);
    request.techniques = args.techniques;
    request.distances = args.distances;
    request.shininesses = args.shininess;
    request.width = args.size.width;
    request.height = args.size.height;
    const int k = int(std::lround(std::sqrt(double(std::max(args.spp, 0)))));
    if (args.spp < 1 || k * k != args.spp || k > kMaxReferenceSamples)
        throw Error("--spp",
                    "the reference takes k x k samples per pixel: 1, 4, 9, ..., 256, "
                    "got " +
                        std::to_string(args.spp));
    request.reference_samples = k;
    request.adaptive_reference = !args.fixed_spp;
    request.frames = args.frames;
    request.motion_pixels = args.motion;
    request.fov_y_degrees = args.fov;
    request.view_direction = args.view_dir;
    request.background = glm::vec3(0.012f, 0.013f, 0.016f);
    if (request.techniques.empty()) throw Error("--techniques", "no technique");
    for (gl::Technique t : request.techniques)
        if (info(t).supersampled)
            throw Error("--techniques", std::string("the ") + to_string(t) +
                                            " is what every technique is measured against; "
                                            "list only " +
                                            technique_names(approximating_techniques(), "and"));
    if (args.frames < 2 || args.frames > 1000)
        throw Error("--frames",
                    "flicker needs 2 to 1000 frames, got " + std::to_string(args.frames));
    if (!(args.motion > 0.0f && args.motion <= 4.0f))
        throw Error("--motion", "the pan per frame must be in (0, 4] pixels");
    if (args.seeds < 1 || args.seeds > kMaxEvalSeeds)
        throw Error("--seeds", "must be 1 to " + std::to_string(kMaxEvalSeeds) + ", got " +
                                   std::to_string(args.seeds));
    if (args.seeds > 1 && (!scene::is_builtin_bumps(args.input.bumps.source) ||
                           !args.input.layers.empty() || scene::is_ocean_scene(args.input.scene)))
        throw Error("--seeds", "independent maps come from a built-in bump set (--bumps one of " +
                                   join(builtin_bump_names()) + "), without --layers");

    // The report folder is checked before anything is read or rendered (docs/robustness.md).
    io::OutputPlan plan;
    for (const std::string& input : scene::scene_source_inputs(args.input))
        if (!input.empty() && std::filesystem::exists(input)) plan.add_input(input);
    plan.add_output_folder(args.out, false, "the report");
    add_report_outputs(plan, args.out, true);
    plan.check();

    const bool tty = stderr_is_terminal();
    auto status = [&](const std::string& text) {
        if (tty) std::fprintf(stderr, "\r%s\033[K", text.c_str());
    };
    status("loading " + args.input.scene + " and " + args.input.bumps.source + "...");
    const scene::Scene scene = load_render_scene(args.input, request.settings);

    gl::Context context(context_options(args.gl));
    gl::Renderer renderer(context, shader_sources(args.gl));
    renderer.set_scene(scene);

    const auto sweep_start = std::chrono::steady_clock::now();
    // One sweep per bump map (--seeds): seeds --seed, --seed + 1, ... of the built-in set, the
    // report's images from the first.
    eval::SweepOutput output;
    std::vector<std::vector<eval::CaseResult>> per_seed;
    for (int i = 0; i < args.seeds; ++i) {
        if (i > 0) {
            RenderSourceFlags input = args.input;
            input.bumps.seed = args.input.bumps.seed + std::uint32_t(i);
            renderer.set_scene(load_render_scene(input, request.settings));
            request.keep_images = false;
        }
        eval::SweepOutput one = eval::run_sweep(renderer, request, [&](int done, int total) {
            done += i * total;
            total *= args.seeds;
            const double elapsed =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - sweep_start)
                    .count();
            const int width = 30;
            const int filled = done * width / std::max(total, 1);
            const std::string bar = std::string(std::size_t(filled), '#') +
                                    std::string(std::size_t(width - filled), '.');
            status("[" + bar + "] " + std::to_string(done) + "/" + std::to_string(total) +
                   " frames, " + duration_text(elapsed * (total - done) / std::max(done, 1)) +
                   " left");
        });
        if (i == 0) output.images = std::move(one.images);
        per_seed.push_back(std::move(one.cases));
    }
    output.cases = args.seeds > 1 ? eval::combine_seeds(per_seed) : std::move(per_seed.front());
    if (tty) std::fprintf(stderr, "\r\033[K");

    eval::SweepInfo info;
    info.scene = args.input.scene;
    info.bumps = args.input.layers.empty() ? args.input.bumps.source
                                           : layers_text(args.input.layers);
    info.techniques = request.techniques;
    info.distances = request.distances;
    info.shininesses = request.shininesses;
    info.width = request.width;
    info.height = request.height;
    info.fov_y_degrees = request.fov_y_degrees;
    info.reference_samples = request.reference_samples;
    info.adaptive_reference = request.adaptive_reference;
    info.frames = request.frames;
    info.motion_pixels = request.motion_pixels;
    info.renderer = context.renderer();
    Preset preset;
    set_preset_source(args.input, preset);
    preset.shading = request.settings;
    preset.camera.direction = request.view_direction;
    preset.camera.fov_y_degrees = request.fov_y_degrees;
    preset.techniques = info.techniques;
    info.preset_json = preset_to_json(preset);
    info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    // The report is written into a temporary folder, then published into --out as a whole.
    io::OutputTransaction outputs;
    const std::string staged = outputs.stage_folder(args.out);
    std::vector<std::string> notes = eval::write_report(staged, info, output.cases, output.images);
    rename_folder_in_notes(notes, staged, args.out);
    outputs.publish();

    std::printf("%-9s %8s %9s %9s %9s %9s %7s %8s %6s\n", "technique", "distance", "shininess",
                "energy", "energy_all", "rmse", "ssim", "flicker", "refspp");
    bool any_flagged = false, any_still = false;
    for (const eval::CaseResult& c : output.cases) {
        const bool flagged = !(c.reference_energy_error <= eval::kUnconvergedEnergyError);
        any_flagged = any_flagged || flagged;
        // The flicker ratio is undefined where the truth's sRGB frames do not change at all
        // (most often: its highlight clips to white in every frame).
        const bool still = !(c.reference_change > 0.0);
        any_still = any_still || still;
        char flicker[16];
        if (still)
            std::snprintf(flicker, sizeof flicker, "still");
        else
            std::snprintf(flicker, sizeof flicker, "%.3g", c.flicker);
        std::printf("%-9s %8g %9g %9.4g %9.4g %9.4g %7.4f %8s %6d%s\n", to_string(c.technique),
                    c.distance, c.shininess, c.energy, c.energy_total, c.rmse, c.ssim, flicker,
                    c.reference_spp, flagged ? " *" : "");
    }
    std::printf(
        "energy: specular / reference's over the object's inner pixels; energy_all: over every "
        "covered pixel; rmse: relative to the reference's mean; ssim: sRGB; flicker: "
        "frame-to-frame change / reference's%s\n",
        args.seeds > 1 ? ("; energies are ratios of sums over " + std::to_string(args.seeds) +
                          " bump maps")
                             .c_str()
                       : "");
    if (any_still)
        std::printf(
            "still: the reference's sRGB frames do not change between frames (its highlight clips "
            "to white, or the motion moves nothing), so the flicker ratio is undefined (NaN in the "
            "CSV, null in the JSON); a dimmer light (--light-color, --ks) measures it\n");
    if (any_flagged)
        std::printf(
            "*: the reference's specular energy is uncertain by more than %.0f%% (not "
            "converged)\n",
            eval::kUnconvergedEnergyError * 100.0);
    for (const std::string& note : notes) std::fprintf(stderr, "leanfade eval: %s\n", note.c_str());
    std::printf("%s: %zu cases (%s, %s), %.1f s on %s; report %s/index.html\n",
                (args.out + "/results.csv").c_str(), output.cases.size(), args.input.scene.c_str(),
                args.input.bumps.source.c_str(), info.seconds, context.renderer().c_str(),
                args.out.c_str());
    return 0;
}

const CommandRegistration registration{
    "eval",
    "Measure each technique against the supersampled ground truth over distances and "
    "shininesses: specular energy, error (RMSE, SSIM) and flicker; CSV, JSON, plots, HTML report",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<EvalArgs>();
        app.add_option("--scene", args->input.scene,
                       "Object: " + scene::scene_choices_text())
            ->capture_default_str();
        add_techniques_option(app, "--techniques", args->techniques,
                              "Techniques to measure, comma-separated: " +
                                  technique_names(approximating_techniques(), "and"));
        add_distance_sweep_option(app, args->distances,
                                  "Camera distances in bounding radii: A:B:N (N log-spaced from A "
                                  "to B) or a comma list",
                                  kDefaultDistances);
        app.add_option("--spp", args->spp,
                       "Reference samples per pixel (a square: k x k at LOD 0, docs/math.md §7)")
            ->capture_default_str();
        app.add_flag("--fixed-spp", args->fixed_spp,
                     "Keep --spp at every distance (by default far, small objects get more "
                     "samples per pixel, at most the full frame's samples per frame)");
        app.add_option("--frames", args->frames, "Frames of the flicker measurement (>= 2)")
            ->capture_default_str();
        app.add_option("--motion", args->motion,
                       "Camera pan per frame of the flicker measurement, pixels")
            ->capture_default_str();
        add_size_option(app, "--size", args->size,
                        "Frame WIDTHxHEIGHT pixels (only the object's square is rendered)");
        add_camera_options(app, args->fov, args->view_dir, "the object's centre");
        app.add_option("--out", args->out,
                       "Output folder: results.csv, results.json, plots, images/, index.html")
            ->capture_default_str();
        app.add_option("--seeds", args->seeds,
                       "Independent bump maps of the built-in set (seeds --seed, --seed + 1, ...): "
                       "energies are reported as ratios of sums over the maps, with their "
                       "spread")
            ->capture_default_str();
        app.add_option("--replot", args->replot,
                       "Only redraw the plots, results.csv and index.html of this folder from its "
                       "results.json (no rendering)");
        add_shading_options(app, args->shading);
        // The sweep's list replaces the shading group's single --shininess.
        app.remove_option(app.get_option("--shininess"));
        add_typed_option(
            app, "--shininess", args->shininess,
            [](const std::string& text) {
                return eval::parse_shininess_list(text, "--shininess");
            },
            "Blinn-Phong exponents, comma-separated", "128,1024,13777");
        add_lean_source_options(app, args->input.bumps);
        add_layer_options(app, args->input.layers);
        add_gl_options(app, args->gl);
        return [args, &app] {
            apply_scene_light(args->shading, app, args->input.scene, args->view_dir);
            return run_eval(*args);
        };
    }};

}  // namespace
}  // namespace leanfade::cli
