// leanfade view: the interactive viewer (GLFW window + Dear ImGui panel) on the renderer. Thin:
// the flags become a Preset (the same flags as `leanfade render`), the viewer library does the
// rest. Registered only when the viewer library is built (LEANFADE_BUILD_VIEWER).
#ifdef LEANFADE_HAS_VIEWER

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "cli_ocean.hpp"
#include "cli_preset.hpp"
#include "cli_render_options.hpp"
#include "cli_render_scene.hpp"
#include "command.hpp"
#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "leanfade/viewer/viewer.hpp"

namespace leanfade::cli {
namespace {

struct ViewArgs {
    std::vector<Technique> technique{Technique::Lean};  // --technique: one pane
    std::vector<Technique> techniques;  // --techniques: panes; overrides --technique
    std::optional<PaneLayout> layout;   // none: single for one technique, side-by-side for more
    float distance = 3.0f;
    float fov = gl::kDefaultFovYDegrees;
    glm::vec3 view_dir = kDefaultViewDirection;
    glm::vec3 target{0.0f};
    int ref_samples = 4;
    float divider = 0.5f;
    FramebufferSize size{1280, 800};
    float scale = 1.0f;  // internal resolution / window; 0 = automatic (0.5 on software renderers)
    bool fly_away = false;
    viewer::TimingMode timing = viewer::TimingMode::Auto;
    int frames = 0;
    std::string screenshot;
    std::string preset;
    ShadingFlags shading;
    RenderSourceFlags input;  // --scene, --bumps and the layer flags
    GlFlags gl;
};

// The preset's values for every flag not given on the command line.
void apply_preset(const Preset& preset, ViewArgs& args, const CLI::App& app) {
    set_source_defaults(preset, args.preset, app, args.input, args.shading);
    // An explicit single --technique replaces the preset's panes.
    if (!given(app, "--technique")) set_unless_given(app, "--techniques", args.techniques,
                                                     preset.techniques);
    if (!given(app, "--layout") && (!given(app, "--technique") || given(app, "--techniques")))
        args.layout = preset.layout;
    set_unless_given(app, "--divider", args.divider, preset.divider);
    set_unless_given(app, "--distance", args.distance, preset.camera.distance);
    set_unless_given(app, "--fov", args.fov, preset.camera.fov_y_degrees);
    set_unless_given(app, "--view-dir", args.view_dir, preset.camera.direction);
    set_unless_given(app, "--target", args.target, preset.camera.target);
    set_unless_given(app, "--ref-samples", args.ref_samples, preset.reference_samples);
    set_unless_given(app, "--scale", args.scale, preset.resolution_scale);
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
    const std::vector<Technique>& techniques =
        args.techniques.empty() ? args.technique : args.techniques;
    if (techniques.size() > 3)
        throw Error("--techniques", "at most 3 panes, got " + std::to_string(techniques.size()));
    p.techniques = techniques;
    p.layout = args.layout.value_or(techniques.size() == 1 ? PaneLayout::Single
                                                           : PaneLayout::SideBySide);
    if (p.layout == PaneLayout::Single && techniques.size() != 1)
        throw Error("--layout", "single shows one technique; --techniques gives " +
                                    std::to_string(techniques.size()));
    if (p.layout == PaneLayout::Split && techniques.size() != 2)
        throw Error("--layout", "split needs exactly two techniques (--techniques A,B)");
    if (p.layout == PaneLayout::SideBySide && techniques.size() < 2)
        throw Error("--layout", "side-by-side needs two or three techniques (--techniques A,B)");
    p.camera.distance = args.distance;
    p.camera.fov_y_degrees = args.fov;
    p.camera.direction = args.view_dir;
    p.camera.target = args.target;
    p.reference_samples = checked_reference_samples(args.ref_samples);
    if (!(args.divider >= 0.0f && args.divider <= 1.0f))
        throw Error("--divider", "must be in [0, 1]");
    p.divider = args.divider;
    if (args.scale != 0.0f && !(args.scale >= 0.1f && args.scale <= 1.0f))
        throw Error("--scale", "must be in [0.1, 1] (or 0 for automatic)");
    p.resolution_scale = args.scale == 0.0f ? 1.0f : args.scale;
    options.auto_scale = args.scale == 0.0f;
    options.width = args.size.width;
    options.height = args.size.height;
    options.timing = args.timing;
    if (args.frames < 0) throw Error("--frames", "must be >= 0");
    if (!args.screenshot.empty() && args.frames == 0)
        throw Error("--screenshot", "needs --frames N (the screenshot is taken after N frames)");
    if (!args.screenshot.empty()) {
        // The screenshot is an output: checked before the window opens (docs/robustness.md).
        io::OutputPlan plan;
        for (const std::string& input : scene::scene_source_inputs(args.input, args.preset))
            if (!input.empty() && std::filesystem::exists(input)) plan.add_input(input);
        plan.add_output(args.screenshot, "--screenshot", ".png");
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
    set_preset_source(args.input, p);
    const bool builtin =
        scene::is_builtin_bumps(p.bumps.source) ||
        std::any_of(p.layers.sources.begin(), p.layers.sources.end(), scene::is_builtin_bumps);
    // The flags' ranges by their names first (validate(Preset) would name the preset keys).
    check_texture_size(p.bumps.texture_size, args.input.bumps.max_size, builtin);
    validate(p.layers);
    validate(p, "view");

    const scene::BumpMapSource bake_flags = args.input.bumps;  // --max-size, --strict-normals, ...
    options.load_bumps = [bake_flags](const BumpSource& source, const ShadingSettings& settings) {
        scene::BumpMapSource flags = bake_flags;
        static_cast<BumpSource&>(flags) = source;
        return load_lean_map_and_report(flags, settings);
    };
    const RenderSourceFlags& input = args.input;
    options.scene = load_render_scene(input, p.shading);
    if (scene::is_ocean_scene(input.scene)) {
        // The ocean moves (a time slider and pause) and is seen from its own cameras, in the
        // renderer's world: the scene scaled to its unit bounding sphere.
        const scene::Bounds bounds = scene::scene_bounds(options.scene);
        const glm::mat4 model =
            glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / bounds.radius())) *
            glm::translate(glm::mat4(1.0f), -bounds.center());
        const scene::OceanSettings ocean;
        options.loop_seconds = ocean.loop_seconds;
        for (const auto& named : ocean_views(args.input.ocean_views, ocean, model))
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
        add_typed_option(
            app, "--technique", args->technique,
            [](const std::string& text) {
                return std::vector{parse_technique(text, "--technique")};
            },
            "Technique of a single view: " + technique_names(all_techniques()),
            to_string(args->technique.front()));
        add_techniques_option(app, "--techniques", args->techniques,
                              "Two or three techniques side by side (or split, see --layout), "
                              "comma-separated: " +
                                  technique_names(all_techniques(), "and"));
        add_typed_option(
            app, "--layout", args->layout,
            [](const std::string& text) {
                return std::optional{parse_pane_layout(text, "--layout")};
            },
            name_list(preset_layouts()) +
                " (split: a draggable divider); default: single for one technique, "
                "side-by-side for more");
        app.add_option("--divider", args->divider, "Split view: divider position, 0..1")
            ->capture_default_str();
        add_typed_option(
            app, "--distance", args->distance,
            [](const std::string& text) {
                double distance = 0.0;
                if (!parse_finite(text, distance))
                    throw Error("--distance", "expected a finite number, got '" + text + "'");
                check_camera_distance(distance, "--distance", text);
                return float(distance);
            },
            "Camera distance from the target in bounding radii, in (1, 1e4]",
            number_text(args->distance));
        add_camera_options(app, args->fov, args->view_dir, "the target", &args->target);
        add_reference_samples_option(app, args->ref_samples);
        add_size_option(app, "--size", args->size, "Window size, WIDTHxHEIGHT pixels");
        app.add_option("--scale", args->scale,
                       "Internal resolution / window, 0.1..1 (default: 1, full resolution; 0: "
                       "0.5 on software renderers such as llvmpipe, else 1)")
            ->capture_default_str();
        app.add_flag("--fly-away", args->fly_away,
                     "Start with the camera flying from near to far and back");
        add_typed_option(app, "--timing", args->timing, parse_timing,
                         "Frame time per pane: auto (GPU timer queries; CPU time on llvmpipe), "
                         "gpu, cpu",
                         "auto");
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
        add_ocean_options(app, args->input.ocean, args->input.ocean_views);
        add_gl_options(app, args->gl);
        return [args, &app] {
            apply_scene_light(args->shading, app, args->input.scene, args->view_dir);
            std::shared_ptr<Preset> loaded;
            if (!args->preset.empty()) {
                loaded = std::make_shared<Preset>(read_preset(args->preset));
                apply_preset(*loaded, *args, app);
            }
            if (scene::is_ocean_scene(args->input.scene)) {
                // The ocean's shading (docs/ocean.md) for the panes' shape (the window less the
                // panel, about 30%, shared by the techniques); flags given here win.
                const float panes = float(
                    (args->techniques.empty() ? args->technique : args->techniques).size());
                apply_ocean_shading(args->shading, app, scene::OceanSettings{},
                                    0.7f * float(args->size.width) /
                                        (panes * float(args->size.height)));
            }
            return run_view(*args, loaded);
        };
    }};

}  // namespace
}  // namespace leanfade::cli

#endif  // LEANFADE_HAS_VIEWER
