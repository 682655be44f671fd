// leanfade view: the interactive viewer (GLFW window + Dear ImGui panel) on the renderer. Thin:
// the flags become a Preset (the same flags as `leanfade render`), the viewer library does the
// rest. Registered only when the viewer library is built (LEANFADE_BUILD_VIEWER).
#ifdef LEANFADE_HAS_VIEWER

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "cli_ocean.hpp"
#include "cli_preset.hpp"
#include "cli_render_options.hpp"
#include "cli_render_scene.hpp"
#include "command.hpp"
#include "leanfade/core/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/preset.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/text.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/io/output_plan.hpp"
#include "leanfade/scene/scene.hpp"
#include "leanfade/viewer/viewer.hpp"

namespace leanfade::cli {
namespace {

struct ViewArgs {
    std::string technique = to_string(Technique::Lean);
    std::string techniques;  // panes, comma-separated; overrides --technique
    std::string layout;      // "" = single for one technique, side-by-side for more
    float distance = 3.0f;
    float fov = gl::kDefaultFovYDegrees;
    std::string view_dir = vector_text(kDefaultViewDirection);
    std::string target = "0,0,0";
    int ref_samples = 4;
    float divider = 0.5f;
    std::string size = "1280x800";
    float scale = 1.0f;  // internal resolution / window; 0 = automatic (0.5 on software renderers)
    bool fly_away = false;
    std::string timing = "auto";
    int frames = 0;
    std::string screenshot;
    std::string preset;
    ShadingFlags shading;
    RenderSourceFlags input;  // --scene, --bumps and the layer flags
    GlFlags gl;
};

void apply_preset(const Preset& preset, ViewArgs& args, CLI::App& app) {
    check_preset_techniques(preset, args.preset);
    args.input.scene = preset.scene;
    args.techniques = join(preset.techniques);
    args.layout = preset.layout;
    args.divider = preset.divider;
    args.distance = preset.camera.distance;
    args.fov = preset.camera.fov_y_degrees;
    args.view_dir = vector_text(preset.camera.direction);
    args.target = vector_text(preset.camera.target);
    args.ref_samples = preset.reference_samples;
    args.scale = preset.resolution_scale;
    set_shading_flags(preset.shading, args.shading);
    set_source_flags(preset.bumps, args.input.bumps);
    reapply_explicit_options(app);
    // An explicit single --technique replaces the preset's panes.
    if (app.count("--technique") > 0 && app.count("--techniques") == 0) {
        args.techniques.clear();
        if (app.count("--layout") == 0) args.layout.clear();
    }
}

viewer::TimingMode parse_timing(const std::string& text) {
    if (text == "auto") return viewer::TimingMode::Auto;
    if (text == "gpu") return viewer::TimingMode::Gpu;
    if (text == "cpu") return viewer::TimingMode::Cpu;
    throw Error("--timing", "expected auto, gpu or cpu, got '" + text + "'");
}

int run_view(const ViewArgs& args, const std::shared_ptr<Preset>& loaded) {
    viewer::ViewerOptions options;
    Preset& p = options.preset;
    if (loaded) {
        p.fly_away = loaded->fly_away;
        options.preset_path = args.preset;
    }
    // Every flag is checked before anything is loaded or a window opens.
    p.shading = resolve_shading(args.shading);
    const std::vector<gl::Technique> techniques =
        gl::parse_techniques(args.techniques.empty() ? args.technique : args.techniques,
                             args.techniques.empty() ? "--technique" : "--techniques");
    if (techniques.size() > 3)
        throw Error("--techniques", "at most 3 panes, got " + std::to_string(techniques.size()));
    p.techniques.clear();
    for (gl::Technique t : techniques) p.techniques.push_back(gl::to_string(t));
    p.layout =
        args.layout.empty() ? (techniques.size() == 1 ? "single" : "side-by-side") : args.layout;
    const auto& layouts = preset_layouts();
    if (std::find(layouts.begin(), layouts.end(), p.layout) == layouts.end())
        throw Error("--layout", "expected " + name_list(layouts) + ", got '" + p.layout + "'");
    if (p.layout == "single" && techniques.size() != 1)
        throw Error("--layout", "single shows one technique; --techniques gives " +
                                    std::to_string(techniques.size()));
    if (p.layout == "split" && techniques.size() != 2)
        throw Error("--layout", "split needs exactly two techniques (--techniques A,B)");
    if (p.layout == "side-by-side" && techniques.size() < 2)
        throw Error("--layout", "side-by-side needs two or three techniques (--techniques A,B)");
    check_camera_distance(args.distance, "--distance");
    p.camera.distance = args.distance;
    p.camera.fov_y_degrees = checked_fov(args.fov);
    p.camera.direction = parse_view_direction(args.view_dir);
    p.camera.target = parse_vector(args.target, "--target");
    p.reference_samples = checked_reference_samples(args.ref_samples);
    if (!(args.divider >= 0.0f && args.divider <= 1.0f))
        throw Error("--divider", "must be in [0, 1]");
    p.divider = args.divider;
    if (args.scale != 0.0f && !(args.scale >= 0.1f && args.scale <= 1.0f))
        throw Error("--scale", "must be in [0.1, 1] (or 0 for automatic)");
    p.resolution_scale = args.scale == 0.0f ? 1.0f : args.scale;
    options.auto_scale = args.scale == 0.0f;
    std::tie(options.width, options.height) = parse_size(args.size, "--size");
    options.timing = parse_timing(args.timing);
    if (args.frames < 0) throw Error("--frames", "must be >= 0");
    if (!args.screenshot.empty() && args.frames == 0)
        throw Error("--screenshot", "needs --frames N (the screenshot is taken after N frames)");
    if (!args.screenshot.empty()) {
        // The screenshot is an output: checked before the window opens (docs/robustness.md).
        io::OutputPlan plan;
        for (const std::string& input : render_source_inputs(args.input, args.preset))
            if (!input.empty() && std::filesystem::exists(input)) plan.add_input(input);
        plan.add_output(args.screenshot, "--screenshot");
        plan.check();
    }
    options.frames = args.frames;
    options.screenshot = args.screenshot;
    options.fly_away = args.fly_away;
    options.shader_dir = args.gl.shader_dir;
    // Throws for a folder that cannot be read, before a window opens.
    if (!options.shader_dir.empty()) gl::ShaderSources::directory(options.shader_dir);
    if (args.gl.egl_device >= 0)
        std::fprintf(stderr,
                     "leanfade view: --egl-device is ignored: the viewer draws with its "
                     "window's OpenGL context\n");
    p.scene = args.input.scene;
    p.bumps = to_bump_source(args.input.bumps);
    // The bump flags by their names (validate() would name the preset keys).
    parse_bake_source(p.bumps.from);
    on_the_fly_storage(args.input.bumps);
    check_texture_size(p.bumps.texture_size, args.input.bumps.max_size,
                       is_builtin_bumps(p.bumps.source));
    validate(p, "view");

    const int max_size = args.input.bumps.max_size;
    options.load_bumps = [max_size](const BumpSource& source, const ShadingSettings& settings) {
        LeanSourceFlags flags;
        set_source_flags(source, flags);
        flags.max_size = max_size;
        return load_lean_map(flags, settings);
    };
    RenderSourceFlags input = args.input;  // the preset's scene and bumps, the flags' layers
    input.scene = p.scene;
    set_source_flags(p.bumps, input.bumps);
    input.bumps.max_size = max_size;
    options.scene = load_render_scene(input, p.shading);
    if (is_ocean_scene(input.scene)) {
        // The ocean moves (a time slider and pause) and is seen from its own cameras, in the
        // renderer's world: the scene scaled to its unit bounding sphere.
        const scene::Bounds bounds = scene::scene_bounds(options.scene);
        const glm::mat4 model =
            glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / bounds.radius())) *
            glm::translate(glm::mat4(1.0f), -bounds.center());
        const scene::OceanSettings ocean;
        options.loop_seconds = ocean.loop_seconds;
        for (const auto& named : ocean_views(args.input.ocean.views, ocean, model))
            options.scene_views.emplace_back(named.name, named.view);
    }
    return viewer::run_viewer(std::move(options));
}

const CommandRegistration registration{
    "view",
    "Interactive viewer: orbit the object, tune every shading parameter live, compare techniques "
    "side by side (GLFW window with an ImGui panel; needs an X display)",
    [](CLI::App& app) -> Runner {
        auto args = std::make_shared<ViewArgs>();
        app.add_option("--scene", args->input.scene,
                       "Object: " + scene::scene_choices_text())
            ->capture_default_str();
        app.add_option("--technique", args->technique,
                       "Technique of a single view: " + technique_names(all_techniques()))
            ->capture_default_str();
        app.add_option("--techniques", args->techniques,
                       "Two or three techniques side by side (or split, see --layout), "
                       "comma-separated: " +
                           technique_names(all_techniques(), "and"));
        app.add_option("--layout", args->layout,
                       name_list(preset_layouts()) +
                           " (split: a draggable divider); default: single for one technique, "
                           "side-by-side for more");
        app.add_option("--divider", args->divider, "Split view: divider position, 0..1")
            ->capture_default_str();
        app.add_option("--distance", args->distance,
                       "Camera distance from the target in bounding radii, in (1, 1e4]")
            ->capture_default_str();
        add_camera_options(app, args->fov, args->view_dir, "the target", &args->target);
        add_reference_samples_option(app, args->ref_samples);
        app.add_option("--size", args->size, "Window size, WIDTHxHEIGHT pixels")
            ->capture_default_str();
        app.add_option("--scale", args->scale,
                       "Internal resolution / window, 0.1..1 (default: 1, full resolution; 0: "
                       "0.5 on software renderers such as llvmpipe, else 1)")
            ->capture_default_str();
        app.add_flag("--fly-away", args->fly_away,
                     "Start with the camera flying from near to far and back");
        app.add_option("--timing", args->timing,
                       "Frame time per pane: auto (GPU timer queries; CPU time on llvmpipe), "
                       "gpu, cpu")
            ->capture_default_str();
        app.add_option("--frames", args->frames,
                       "Render this many frames, then exit (automation; 0 = until closed)")
            ->capture_default_str();
        app.add_option("--screenshot", args->screenshot,
                       "With --frames: save the window (panel included) as this PNG at the end");
        app.add_option("--preset", args->preset,
                       "Start from a preset (JSON, saved by the viewer); flags given here "
                       "override it");
        add_shading_options(app, args->shading);
        add_lean_source_options(app, args->input.bumps);
        add_layer_options(app, args->input.layers);
        add_ocean_options(app, args->input.ocean);
        add_gl_options(app, args->gl);
        return [args, &app] {
            std::shared_ptr<Preset> loaded;
            if (!args->preset.empty()) {
                loaded = std::make_shared<Preset>(read_preset(args->preset));
                apply_preset(*loaded, *args, app);
            }
            if (is_ocean_scene(args->input.scene)) {
                // The ocean's shading (docs/ocean.md) for the panes' shape (the window less the
                // panel, about 30%, shared by the techniques); flags given here win.
                const auto [width, height] = parse_size(args->size, "--size");
                const std::string& names =
                    args->techniques.empty() ? args->technique : args->techniques;
                const float panes = float(std::count(names.begin(), names.end(), ',') + 1);
                apply_ocean_shading(args->shading, app, scene::OceanSettings{},
                                    0.7f * float(width) / (panes * float(height)));
            }
            return run_view(*args, loaded);
        };
    }};

}  // namespace
}  // namespace leanfade::cli

#endif  // LEANFADE_HAS_VIEWER
