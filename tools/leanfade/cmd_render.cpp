// leanfade render: the papers' comparison figure (a column per technique, a row per distance)
// rendered offscreen with OpenGL 4.5 through EGL, written as one labelled sRGB PNG.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_ocean.hpp"
#include "cli_preset.hpp"
#include "cli_render_options.hpp"
#include "cli_render_mixings.hpp"
#include "cli_render_scene.hpp"
#include "command.hpp"
#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/detail/figure.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

// The float files of --cells.
enum class CellFormat { Pfm, Exr };
const char* to_string(CellFormat format) { return format == CellFormat::Exr ? "exr" : "pfm"; }

struct RenderArgs {
    // The papers' comparison: the baseline, LEAN and LEAN with fading.
    std::vector<Technique> techniques{Technique::Bump, Technique::Lean, Technique::Fade};
    std::vector<float> distances{3.0f, 24.0f};
    FramebufferSize size{400, 400};
    std::string output = "teaser.png";
    bool zoom = false;
    std::string cells;
    CellFormat cell_format = CellFormat::Pfm;
    int ref_samples = 8;
    float time = 0.0f;  // seconds, for moving bump layers
    MixingFigureArgs mixings;  // --mixings: the layer figures (cli_render_mixings.hpp)
    int frames = 1;     // a sequence of frames, `output` a %03d pattern (cli_ocean.hpp)
    float fps = 12.0f;  // frames per second of the sequence
    float fov = gl::kDefaultFovYDegrees;
    glm::vec3 view_dir = kDefaultViewDirection;  // from the target toward the eye
    glm::vec3 target{0.0f};                      // the point the camera looks at
    std::string preset;                // JSON preset of `leanfade view`: the defaults of the flags
    ShadingFlags shading;
    RenderSourceFlags input;  // --scene, --bumps and the layer flags
    GlFlags gl;
};

// Largest number of cell pixels in one picture of `render` (2^25: 8192 x 4096).
constexpr std::uint64_t kMaxFigurePixels = std::uint64_t(1) << 25;

// The reference's own error, as eval measures it (reference_energy_error, a case flagged "not
// converged" above eval::kUnconvergedEnergyError): the specular energy of the object's pixels
// from the reference and from a second one with a quarter of the samples (k/2 x k/2; 2 x 2 for
// k = 1); for n times fewer samples their difference has sqrt(1 + n) times the error of the
// better one. A note for each distance above the bound; not for a reference of fewer than 4x4
// samples, asked for as a quick preview.
void note_reference_noise(gl::Renderer& renderer, const gl::FigureRequest& request) {
    if (!request.views.empty() || request.reference_samples < 4 ||
        std::find(request.techniques.begin(), request.techniques.end(),
                  gl::Technique::Reference) == request.techniques.end())
        return;
    gl::FigureRequest specular = request;
    specular.techniques = {gl::Technique::Reference};
    specular.zoom = false;
    specular.output = gl::OutputMode::Specular;
    specular.background = glm::vec3(0.0f);
    specular.settings.fog = FogMode::None;
    gl::FigureRequest fewer = specular;
    const int k = request.reference_samples;
    fewer.reference_samples = k >= 2 ? k / 2 : 2;
    const double n = double(k * k) / double(fewer.reference_samples * fewer.reference_samples);
    const double spread = std::sqrt(1.0 + n);
    const gl::Figure full = gl::render_figure(renderer, specular);
    const gl::Figure check = gl::render_figure(renderer, fewer);
    for (std::size_t i = 0; i < full.cells.size() && i < check.cells.size(); ++i) {
        double energy = 0.0, other = 0.0;
        for (const float v : full.cells[i].radiance.pixels) energy += double(v);
        for (const float v : check.cells[i].radiance.pixels) other += double(v);
        if (!(energy > 0.0)) continue;
        const double error = std::abs(other - energy) / (energy * spread);
        if (error > eval::kUnconvergedEnergyError)
            std::fprintf(stderr,
                         "leanfade render: note: the reference at distance %s has not converged "
                         "(its specular energy is uncertain by %.0f%% with %dx%d samples; raise "
                         "--ref-samples)\n",
                         gl::distance_text(full.cells[i].distance).c_str(), 100.0 * error, k, k);
    }
}

int run_render(const RenderArgs& args) {
    const auto start = std::chrono::steady_clock::now();
    // Every flag is checked before anything is read or rendered.
    const ShadingSettings settings = resolve_shading(args.shading);
    gl::FigureRequest request;
    request.techniques = args.techniques;
    request.distances = args.distances;
    request.cell_width = args.size.width;
    request.cell_height = args.size.height;
    request.settings = settings;
    request.zoom = args.zoom;
    request.fov_y_degrees = args.fov;
    request.view_direction = args.view_dir;
    request.target = args.target;
    request.reference_samples = checked_reference_samples(args.ref_samples);
    if (!std::isfinite(args.time) || std::abs(args.time) > 1e6f)
        throw Error("--time", "must be a finite number of seconds up to 1e6 in magnitude");
    request.time = args.time;
    if (args.frames < 1 || args.frames > 100000)
        throw Error("--frames", "must be in [1, 100000], got " + std::to_string(args.frames));
    if (!(args.fps > 0.0f) || !std::isfinite(args.fps) || args.fps > 1000.0f)
        throw Error("--fps", "must be in (0, 1000] frames per second");
    if (args.frames > 1 && !args.cells.empty())
        throw Error("--cells", "is for one frame; not with --frames");
    const bool ocean = scene::is_ocean_scene(args.input.scene);
    // The ocean's rows are its cameras (--views), checked here before anything is read.
    if (ocean) ocean_views(args.input.ocean_views, scene::OceanSettings{}, glm::mat4(1.0f));
    // The picture holds every cell (and a zoom row for each): bounded before any is rendered.
    {
        const std::uint64_t rows =
            ocean ? args.input.ocean_views.size() : request.distances.size();
        const std::uint64_t cells = rows * request.techniques.size() * (args.zoom ? 2 : 1);
        const std::uint64_t pixels =
            cells * std::uint64_t(request.cell_width) * std::uint64_t(request.cell_height);
        if (pixels > kMaxFigurePixels)
            throw Error(ocean ? "--views" : "--distances",
                        std::to_string(cells) + " cells of " + size_text(args.size) + " make " +
                            std::to_string(pixels) + " pixels, more than the limit of " +
                            std::to_string(kMaxFigurePixels) + " for one picture");
    }
    // One picture, or one per frame of a sequence (-o a pattern such as out/ocean_%03d.png).
    std::vector<std::string> pictures{args.output};
    if (args.frames > 1) {
        pictures.clear();
        for (int k = 0; k < args.frames; ++k) pictures.push_back(frame_path(args.output, k));
    }
    if (!args.mixings.mixings.empty()) {
        MixingFigureArgs mixing_args = args.mixings;
        mixing_args.output = args.output;
        return run_mixing_figure(mixing_args, args.input, request, args.gl,
                                 scene::scene_source_inputs(args.input, args.preset));
    }
    // Every output is checked before anything is read or rendered: a regular file (or a new one)
    // in a writable folder, not an input, not another output (docs/robustness.md).
    auto cell_name = [](gl::Technique technique, float distance, const std::string& view) {
        return std::string(gl::to_string(technique)) +
               (view.empty() ? "_d" + gl::distance_text(distance) : "_" + view);
    };
    io::OutputPlan plan;
    for (const std::string& input : scene::scene_source_inputs(args.input, args.preset))
        if (!input.empty() && fs::exists(input)) plan.add_input(input);
    for (const std::string& picture : pictures) plan.add_output(picture, "-o", ".png");
    if (!args.cells.empty()) {
        plan.add_output_folder(args.cells, true);
        std::vector<std::pair<float, std::string>> rows;
        if (ocean)
            for (const std::string& view : args.input.ocean_views)
                rows.emplace_back(0.0f, view);
        else
            for (float distance : request.distances) rows.emplace_back(distance, "");
        for (gl::Technique technique : request.techniques)
            for (const auto& [distance, view] : rows) {
                const fs::path base = fs::path(args.cells) / cell_name(technique, distance, view);
                plan.add_output(base.string() + ".png", "--cells");
                plan.add_output(base.string() + "." + to_string(args.cell_format), "--cells");
            }
    }
    plan.check();

    const bool tty = stderr_is_terminal();
    auto status = [&](const std::string& text) {
        if (tty) std::fprintf(stderr, "\r%s\033[K", text.c_str());
    };
    status("loading " + args.input.scene + " and " + args.input.bumps.source + "...");
    const scene::Scene scene = load_render_scene(args.input, settings);

    gl::Context context(context_options(args.gl));
    gl::Renderer renderer(context, shader_sources(args.gl));
    renderer.set_scene(scene);
    if (ocean)
        request.views = ocean_views(args.input.ocean_views, scene::OceanSettings{},
                                    renderer.model_matrix());

    // The pictures (a frame sequence: one per frame, frame k at --time + k / --fps) and the cells
    // are published together, or not at all.
    io::OutputTransaction outputs;
    gl::Figure figure;
    for (std::size_t k = 0; k < pictures.size(); ++k) {
        request.time = args.time + float(double(k) / double(args.fps));
        figure = gl::render_figure(renderer, request, [&](int done, int total) {
            status((pictures.size() > 1 ? "frame " + std::to_string(k + 1) + "/" +
                                              std::to_string(pictures.size()) + ", "
                                        : std::string()) +
                   "rendering cell " + std::to_string(done) + "/" + std::to_string(total) +
                   " on " + context.renderer());
        });
        io::write_png(outputs.stage(pictures[k]), figure.picture, 8);
    }
    if (tty) std::fprintf(stderr, "\r\033[K");
    note_reference_noise(renderer, request);
    if (!args.cells.empty()) {
        const fs::path folder = outputs.stage_folder(args.cells);
        for (const gl::FigureCell& cell : figure.cells) {
            const std::string base =
                (folder / cell_name(cell.technique, cell.distance, cell.view)).string();
            io::write_png(base + ".png", gl::encode_srgb(cell.radiance), 8);
            if (args.cell_format == CellFormat::Exr)
                io::write_exr(base + ".exr", cell.radiance);
            else
                io::write_pfm(base + ".pfm", cell.radiance);
        }
    }
    outputs.publish();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: %zu x %zu cells of %dx%d (%s), %.2f s on %s\n",
                (pictures.size() > 1 ? pictures.front() + " .. " + pictures.back() : args.output)
                    .c_str(),
                request.techniques.size(),
                request.views.empty() ? request.distances.size() : request.views.size(),
                request.cell_width,
                request.cell_height, args.input.scene.c_str(), seconds, context.renderer().c_str());
    return 0;
}

// `--preset FILE`: the preset's values for every flag not given on the command line.
void apply_preset(RenderArgs& args, const CLI::App& app) {
    const Preset preset = read_preset(args.preset);
    set_source_defaults(preset, args.preset, app, args.input, args.shading);
    set_unless_given(app, "--techniques", args.techniques, preset.techniques);
    set_unless_given(app, "--distances", args.distances, std::vector{preset.camera.distance});
    set_unless_given(app, "--fov", args.fov, preset.camera.fov_y_degrees);
    set_unless_given(app, "--view-dir", args.view_dir, preset.camera.direction);
    set_unless_given(app, "--target", args.target, preset.camera.target);
    set_unless_given(app, "--ref-samples", args.ref_samples, preset.reference_samples);
}

const CommandRegistration registration{
    "render",
    "Render the papers' comparison figure: a column per technique (" +
        technique_names(all_techniques(), "or") + "), a row per camera distance",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<RenderArgs>();
        app.add_option("--scene", args->input.scene,
                       "Object: " + scene::scene_choices_text())
            ->capture_default_str();
        add_techniques_option(app, "--techniques", args->techniques,
                              "Columns, comma-separated: " +
                                  technique_names(all_techniques(), "and"));
        add_typed_option(
            app, "--distances", args->distances,
            [](const std::string& text) { return parse_distances(text, "--distances"); },
            "Rows: camera distances from the target (default the object's centre) in bounding "
            "radii, in (1, 1e4]",
            "3,24");
        add_size_option(app, "--size", args->size, "Size of each cell, WIDTHxHEIGHT pixels");
        app.add_option("-o,--output", args->output, "Output PNG (8-bit sRGB)")
            ->capture_default_str();
        app.add_flag("--zoom", args->zoom,
                     "Add enlarged nearest-neighbour crops of the far objects");
        app.add_option("--cells", args->cells,
                       "Also write each cell to this folder: <technique>_d<distance>.png and "
                       "linear radiance .pfm/.exr");
        add_typed_option(
            app, "--cell-format", args->cell_format,
            [](const std::string& text) {
                if (text == "pfm") return CellFormat::Pfm;
                if (text == "exr") return CellFormat::Exr;
                throw Error("--cell-format", "expected pfm or exr, got '" + text + "'");
            },
            "Float format of --cells: pfm or exr", "pfm");
        add_reference_samples_option(app, args->ref_samples);
        app.add_option("--time", args->time,
                       "Seconds since the start: moving bump layers are offset by their "
                       "--layer-velocity times this")
            ->capture_default_str();
        app.add_option("--frames", args->frames,
                       "Render a sequence of this many frames, frame k at --time + k / --fps; -o "
                       "is then a pattern with one %d or %03d field (out/ocean_%03d.png)")
            ->capture_default_str();
        app.add_option("--fps", args->fps, "Frames per second of --frames")->capture_default_str();
        add_camera_options(app, args->fov, args->view_dir, "the target", &args->target);
        app.add_option("--preset", args->preset,
                       "Start from a preset saved by `leanfade view` (JSON): its scene, bumps, "
                       "shading, camera (one row) and techniques; flags given here override it");
        add_shading_options(app, args->shading);
        add_lean_source_options(app, args->input.bumps);
        add_layer_options(app, args->input.layers);
        add_mixings_option(app, args->mixings);
        app.add_option("--table", args->mixings.table,
                       "With --mixings: also write the metrics as this CSV (and JSON beside it)")
            ->group("Bump layers (docs/math.md §6)");
        add_ocean_options(app, args->input.ocean, args->input.ocean_views);
        add_gl_options(app, args->gl);
        return [args, &app] {
            apply_scene_light(args->shading, app, args->input.scene, args->view_dir);
            if (!args->preset.empty()) apply_preset(*args, app);
            if (scene::is_ocean_scene(args->input.scene)) {
                // The ocean's defaults: 16:9 cells and its shading (docs/ocean.md); flags given
                // on the command line win.
                set_unless_given(app, "--size", args->size, FramebufferSize{480, 270});
                apply_ocean_shading(args->shading, app, scene::OceanSettings{},
                                    float(args->size.width) / float(args->size.height));
            }
            return run_render(*args);
        };
    }};

}  // namespace
}  // namespace leanfade::cli
