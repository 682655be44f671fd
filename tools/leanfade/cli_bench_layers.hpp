#pragma once
// `leanfade bench --layers-columns`: the LEAN paper's Fig. 12 columns, each object filling the
// screen: Blinn-Phong bump mapping, single LEAN, per-frame generation (two moving layers mixed by
// height: their mixed map generated on the GPU inside every frame, then drawn with LEAN), mixture
// textures and mixture approximation (the same layers mixed at shading time), with FPS and the
// ratio of each to single LEAN.
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_render_scene.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/detail/frame_bench.hpp"

namespace leanfade::cli {

// The two layers when --layers is not given, and their velocities (uv per second) in the mixed
// columns when --layer-velocity is not given.
const std::vector<std::string>& fig12_layers();       // bumps, noise
const std::vector<glm::vec2>& fig12_velocities();      // 0.02:0, -0.01:0.03
// The layers and velocities the columns use: `layers`' own, else those above.
LayerSettings fig12_layer_settings(const LayerSettings& layers);

struct LayerBenchColumn {
    std::string key;    // JSON key: blinn_phong, single_lean, per_frame_generation, ...
    std::string label;  // column title
    double frame_ms = 0.0;  // median frame time
    double fps = 0.0;
    double ratio_to_lean = 0.0;  // frame time over single LEAN's (per-round median)
};

struct LayerBenchResult {
    std::string scene;
    double coverage = 0.0;
    std::vector<LayerBenchColumn> columns;
};

// Measures the columns on each of `scene_names` with `request`'s size, frames, warm-up and timing
// (its techniques, views and floor are set here). `input` gives the bumps (its --layers: two
// sources, default bumps,noise). Throws leanfade::Error.
std::vector<LayerBenchResult> run_layer_bench(gl::Context& context, const GlFlags& gl_flags,
                                              const RenderSourceFlags& input,
                                              const std::vector<std::string>& scene_names,
                                              gl::FrameBenchRequest request,
                                              const std::function<void(const std::string&)>& say);

std::string layer_bench_table(const std::vector<LayerBenchResult>& results);
nlohmann::json layer_bench_json(const std::vector<LayerBenchResult>& results);

}  // namespace leanfade::cli
