// leanfade calibrate: gives specular fading (the fading paper, eq. 6-7) a physical handle. Finds
// Fade (and Pmax with --fit-pmax) so that fade's specular energy relative to LEAN's, over a sweep
// of camera distances, follows exp(-SIGMA d), the scene fog's transmittance or the supersampled
// truth's specular energy relative to LEAN's in least squares;
// prints the parameters and the residual, and plots target versus achieved.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>

#include "cli_preset.hpp"
#include "cli_render_options.hpp"
#include "cli_render_scene.hpp"
#include "command.hpp"
#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/eval/calibration.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/eval/runner.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "leanfade/core/technique.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDefaultDistances = "2:64:10";

struct CalibrateArgs {
    std::optional<eval::FadeTarget> target;  // required
    bool fit_pmax = false;
    std::vector<float> distances = eval::parse_distance_sweep(kDefaultDistances);
    FramebufferSize size{128, 128};
    float fov = gl::kDefaultFovYDegrees;
    glm::vec3 view_dir = kDefaultViewDirection;  // from the object's centre toward the eye
    std::string plot = "calibration.png";
    std::string json;
    int spp = 64;
    ShadingFlags shading;
    RenderSourceFlags input;  // --scene, --bumps and the layer flags
    GlFlags gl;
};

// The plot's three files: the PNG, its data (.tsv) and script (.gp) beside it. Checked before
// the renders: names gnuplot can be given, and three distinct files.
struct PlotFiles {
    std::filesystem::path plot, data, script;
};

PlotFiles plot_files(const std::string& name) {
    PlotFiles f;
    f.plot = fs::absolute(name);
    f.data = fs::path(f.plot).replace_extension(".tsv");
    f.script = fs::path(f.plot).replace_extension(".gp");
    if (f.plot == f.data || f.plot == f.script)
        throw Error("--plot", "the plot's data and script are written beside it as .tsv and .gp; "
                              "name the plot otherwise (e.g. .png), got '" + name + "'");
    eval::gnuplot_file(f.plot.filename().string());  // throws for a control character
    return f;
}

int run_calibrate(const CalibrateArgs& args) {
    if (!args.target) throw Error("--target", "required: exp:SIGMA, fog or reference");
    const eval::FadeTarget target = *args.target;
    eval::FadeCalibrationRequest request;
    request.settings = resolve_shading(args.shading);
    request.target = target;
    request.fit_pmax = args.fit_pmax;
    request.cameras.distances = args.distances;
    request.cameras.width = args.size.width;
    request.cameras.height = args.size.height;
    request.cameras.fov_y_degrees = args.fov;
    request.cameras.view_direction = args.view_dir;
    // Checked before rendering: fog needs the scene's fog.
    if (target.kind != eval::FadeTarget::Kind::Reference)
        eval::target_attenuation(target, request.cameras.distances, request.settings);
    const int k = int(std::lround(std::sqrt(double(std::max(args.spp, 0)))));
    if (args.spp < 1 || k * k != args.spp || k > kMaxReferenceSamples)
        throw Error("--spp",
                    "the reference takes k x k samples per pixel: 1, 4, 9, ..., 256, "
                    "got " +
                        std::to_string(args.spp));
    request.reference_samples = k;
    const PlotFiles files = args.plot.empty() ? PlotFiles{} : plot_files(args.plot);
    // Every output is checked before anything is read or rendered (docs/robustness.md).
    io::OutputPlan plan;
    for (const std::string& input : scene::scene_source_inputs(args.input))
        if (!input.empty() && fs::exists(input)) plan.add_input(input);
    if (!args.plot.empty()) {
        plan.add_output(files.plot.string(), "--plot", ".png");
        plan.add_output(files.data.string(), "the plot's data");
        plan.add_output(files.script.string(), "the plot's script");
    }
    if (!args.json.empty()) plan.add_output(args.json, "--json");
    plan.check();

    const scene::Scene scene = load_render_scene(args.input, request.settings);
    gl::Context context(context_options(args.gl));
    gl::Renderer renderer(context, shader_sources(args.gl));
    renderer.set_scene(scene);
    const eval::FadeCalibration c = eval::calibrate_fade(renderer, request);

    std::printf("target %s over %zu distances (%g to %g bounding radii), %s / %s\n",
                eval::to_string(target).c_str(), c.distances.size(), c.distances.front(),
                c.distances.back(), args.input.scene.c_str(), args.input.bumps.source.c_str());
    std::printf("Fade = %.6g per bounding radius, Pmax = %.6g%s, p = %g, distance %s\n", c.fit.fade,
                c.fit.pmax, args.fit_pmax ? "" : " (fixed)", request.settings.fade_exponent,
                to_string(request.settings.fade_distance));
    std::printf("residual (RMS of fade/lean energy - target): model %.4g, rendered %.4g\n",
                c.fit.residual, c.achieved_residual);
    std::printf("%9s %9s %9s %9s\n", "distance", "target", "model", "achieved");
    for (std::size_t i = 0; i < c.distances.size(); ++i)
        std::printf("%9g %9.4f %9.4f %9.4f\n", c.distances[i], c.target[i], c.fit.model[i],
                    c.achieved[i]);

    // The plot's data and script and --json are published together; gnuplot then draws the plot.
    io::OutputTransaction outputs;
    if (!args.plot.empty()) {
        const fs::path& plot = files.plot;
        const fs::path& data = files.data;
        const fs::path& script = files.script;
        std::ostringstream tsv;
        tsv << "# distance target model achieved\n";
        for (std::size_t i = 0; i < c.distances.size(); ++i)
            tsv << c.distances[i] << "\t" << c.target[i] << "\t" << c.fit.model[i] << "\t"
                << c.achieved[i] << "\n";
        eval::write_text_file(outputs.stage(data.string()), tsv.str());
        eval::write_text_file(outputs.stage(script.string()),
                              eval::calibration_plot_script(
                                  eval::to_string(target), c.fit.fade, c.fit.pmax, c.target,
                                  c.achieved, plot.filename().string(), data.filename().string()));
    }
    if (!args.json.empty()) {
        std::ostringstream j;
        j << "{\n  \"target\": \"" << eval::to_string(target) << "\",\n  \"fade\": " << c.fit.fade
          << ",\n  \"pmax\": " << c.fit.pmax
          << ",\n  \"pmax_fitted\": " << (args.fit_pmax ? "true" : "false")
          << ",\n  \"fade_exponent\": " << request.settings.fade_exponent
          << ",\n  \"residual_model\": " << c.fit.residual
          << ",\n  \"residual_rendered\": " << c.achieved_residual << ",\n  \"points\": [";
        for (std::size_t i = 0; i < c.distances.size(); ++i)
            j << (i ? "," : "") << "\n    {\"distance\": " << c.distances[i]
              << ", \"target\": " << c.target[i] << ", \"model\": " << c.fit.model[i]
              << ", \"achieved\": " << c.achieved[i] << "}";
        j << "\n  ]\n}\n";
        eval::write_text_file(outputs.stage(args.json), j.str());
    }
    outputs.publish();
    if (!args.plot.empty()) {
        std::string note;
        if (eval::run_gnuplot(files.script.string(), note))
            std::printf("plot: %s\n", files.plot.string().c_str());
        else
            std::fprintf(stderr, "leanfade calibrate: %s\n", note.c_str());
    }
    return 0;
}

const CommandRegistration registration{
    "calibrate",
    "Fit specular fading (Fade, optionally Pmax) so that fade's energy relative to LEAN follows "
    "exp(-SIGMA d), the scene's fog or the supersampled truth over distance",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<CalibrateArgs>();
        add_typed_option(
            app, "--target", args->target,
            [](const std::string& text) {
                return std::optional{eval::parse_fade_target(text, "--target")};
            },
            "Attenuation to follow: exp:SIGMA (per bounding radius), fog (the --fog settings' "
            "transmittance) or reference (the supersampled truth's specular energy relative to "
            "LEAN's)")
            ->required();
        app.add_option("--spp", args->spp,
                       "Reference samples per pixel for --target reference (k x k; more where "
                       "the object is small)")
            ->capture_default_str();
        app.add_flag("--fit-pmax", args->fit_pmax, "Fit Pmax too (otherwise --pmax is kept)");
        app.add_option("--scene", args->input.scene,
                       "Object: " + scene::scene_choices_text())
            ->capture_default_str();
        add_distance_sweep_option(
            app, args->distances,
            "Camera distances in bounding radii: A:B:N (log-spaced) or a comma list",
            kDefaultDistances);
        add_size_option(app, "--size", args->size, "Frame WIDTHxHEIGHT pixels of the renders");
        add_camera_options(app, args->fov, args->view_dir, "the object's centre");
        app.add_option("--plot", args->plot,
                       "PNG of target versus achieved (gnuplot; empty: none); its .tsv data and "
                       ".gp script are written beside it")
            ->capture_default_str();
        app.add_option("--json", args->json, "Also write the fit as JSON to this file");
        add_shading_options(app, args->shading);
        add_lean_source_options(app, args->input.bumps);
        add_layer_options(app, args->input.layers);
        add_gl_options(app, args->gl);
        return [args] { return run_calibrate(*args); };
    }};

}  // namespace
}  // namespace leanfade::cli
