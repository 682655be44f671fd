// The LEAN paper's Fig. 12 columns (cli_bench_layers.hpp).
#include "cli_bench_layers.hpp"

#include <cstdio>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/gl/renderer.hpp"

namespace leanfade::cli {
namespace {

// The fill view's timing of `technique` with `scene` drawn.
const gl::TechniqueTiming& fill_timing(const gl::FrameBenchResult& result, gl::Technique t) {
    const gl::TechniqueTiming* timing = result.scenes.front().views.front().find(t);
    if (timing == nullptr) throw Error("bench", "a column was not measured");
    return *timing;
}

}  // namespace

const std::vector<std::string>& fig12_layers() {
    static const std::vector<std::string> layers{"bumps", "noise"};
    return layers;
}

const std::vector<glm::vec2>& fig12_velocities() {
    static const std::vector<glm::vec2> velocities{{0.02f, 0.0f}, {-0.01f, 0.03f}};
    return velocities;
}

LayerSettings fig12_layer_settings(const LayerSettings& layers) {
    LayerSettings result = layers;
    if (result.sources.empty()) result.sources = fig12_layers();
    // Moving layers (their offsets change every frame), unless the command line sets them.
    if (result.velocity.empty()) result.velocity = fig12_velocities();
    return result;
}

std::vector<LayerBenchResult> run_layer_bench(gl::Context& context, const GlFlags& gl_flags,
                                              const RenderSourceFlags& input,
                                              const std::vector<std::string>& scene_names,
                                              gl::FrameBenchRequest request,
                                              const std::function<void(const std::string&)>& say) {
    RenderSourceFlags layered = input;
    layered.layers = fig12_layer_settings(input.layers);
    if (layered.layers.sources.size() != 2)
        throw Error("--layers", "the Fig. 12 columns mix two layers");
    request.fill = true;
    request.distances.clear();
    request.floor = false;
    gl::Renderer renderer(context, shader_sources(gl_flags));
    std::vector<LayerBenchResult> results;
    for (const std::string& name : scene_names) {
        LayerBenchResult result;
        result.scene = name;
        say("Fig. 12 columns on " + name);
        // Blinn-Phong and single LEAN: the first layer alone.
        RenderSourceFlags single = input;
        single.scene = name;
        single.layers = {};
        single.bumps.source = layered.layers.sources.front();
        const scene::Scene single_scene = load_render_scene(single, request.settings);
        request.techniques = {gl::Technique::Bump, gl::Technique::Lean};
        const gl::FrameBenchResult base =
            gl::run_frame_bench(renderer, {{name, nullptr, &single_scene}}, request);
        result.coverage = base.scenes.front().views.front().coverage;
        const gl::TechniqueTiming& bump = fill_timing(base, gl::Technique::Bump);
        const gl::TechniqueTiming& lean = fill_timing(base, gl::Technique::Lean);
        const double lean_ms = lean.stats.median;
        result.columns.push_back({"blinn_phong", "Blinn-Phong", bump.stats.median, bump.fps,
                                  base.scenes.front().views.front().ratio(gl::Technique::Bump, gl::Technique::Lean)});
        result.columns.push_back({"single_lean", "single LEAN", lean_ms, lean.fps, 1.0});

        // Per-frame generation and the two mixtures: the same two moving layers (docs/math.md
        // §6), drawn with LEAN; the clock advances every frame, so the height method's mixed map
        // is generated on the GPU (compute pass + MIPs) inside every timed frame.
        struct MixedColumn {
            LayerMixing mixing;
            const char* key;
            const char* label;
        };
        const MixedColumn mixed_columns[] = {
            {LayerMixing::Height, "per_frame_generation", "per-frame generation"},
            {LayerMixing::Textures, "mixture_textures", "mixture textures"},
            {LayerMixing::Approx, "mixture_approximation", "mixture approximation"}};
        for (const MixedColumn& column : mixed_columns) {
            RenderSourceFlags flags = layered;
            flags.scene = name;
            flags.layers.mixing = column.mixing;
            const scene::Scene scene = load_render_scene(flags, request.settings);
            request.techniques = {gl::Technique::Lean};
            const gl::FrameBenchResult mixed =
                gl::run_frame_bench(renderer, {{name, nullptr, &scene}}, request);
            const gl::TechniqueTiming& t = fill_timing(mixed, gl::Technique::Lean);
            result.columns.push_back(
                {column.key, column.label, t.stats.median, t.fps, t.stats.median / lean_ms});
        }
        results.push_back(std::move(result));
    }
    return results;
}

std::string layer_bench_table(const std::vector<LayerBenchResult>& results) {
    std::string out = "\nFig. 12 columns (object filling the screen; ratio = frame time / single "
                      "LEAN's)\n";
    char line[200];
    for (const LayerBenchResult& r : results) {
        std::snprintf(line, sizeof line, "%s (coverage %.3f)\n", r.scene.c_str(), r.coverage);
        out += line;
        for (const LayerBenchColumn& c : r.columns) {
            std::snprintf(line, sizeof line, "  %-24s %10.3f ms %10.1f FPS %8.3f\n",
                          c.label.c_str(), c.frame_ms, c.fps, c.ratio_to_lean);
            out += line;
        }
    }
    return out;
}

nlohmann::json layer_bench_json(const std::vector<LayerBenchResult>& results) {
    nlohmann::json out = nlohmann::json::object();
    for (const LayerBenchResult& r : results) {
        nlohmann::json scene = {{"coverage", r.coverage}};
        for (const LayerBenchColumn& c : r.columns)
            scene[c.key] = {{"label", c.label},
                            {"frame_ms", c.frame_ms},
                            {"fps", c.fps},
                            {"ratio_to_single_lean", c.ratio_to_lean}};
        out[r.scene] = scene;
    }
    return out;
}

}  // namespace leanfade::cli
