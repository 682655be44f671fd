#pragma once
// Frame times of the techniques, by the papers' protocol (LEAN Fig. 12; the fading paper §5):
// one object filling the screen (every pixel shaded), then the object at a few distances; per
// technique, scene and view the median and spread of the frame time over N frames after warm-up.
//
// A frame is: clear colour and depth, draw the object (Renderer::draw) into an offscreen RGBA8 +
// 24-bit depth framebuffer of the requested size (what a window's back buffer is). Techniques are
// interleaved frame by frame, each round drawing every technique once in an order rotated by one
// every round, so that drift of the machine (clock, load, thermal) falls on all of them alike;
// ratios are taken per round (a[i] / b[i]) and their median reported.
//
// The constant-colour "floor" (shader variant scene_constant: same geometry and vertex stage) is
// measured alongside as the fill-rate floor every technique is compared with.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "leanfade/core/settings.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/gl/detail/timer.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::gl {

// Name of the constant-colour floor in results (not a Technique).
inline constexpr const char* kFloorName = "floor";

struct FrameBenchRequest {
    int width = 1600;  // framebuffer pixels
    int height = 1200;
    std::vector<Technique> techniques{Technique::Bump, Technique::Lean, Technique::Fade};
    bool floor = true;                                // measure the constant-colour floor too
    bool fill = true;                                 // the object-filling-the-screen view
    std::vector<float> distances{3.0f, 8.0f, 24.0f};  // near / mid / far, bounding radii (> 1)
    int frames = 20;  // timed rounds (each draws every technique once), >= 1
    int warmup = 3;   // untimed rounds first, >= 0
    TimingMethod timing = TimingMethod::Auto;
    ShadingSettings settings;
    glm::vec3 view_direction = kDefaultViewDirection;
    // The animation's clock (RenderRequest::time) advances this much per round, seconds: moving
    // bump layers move, and a material mixed by height regenerates its map every round.
    float seconds_per_round = 1.0f / 60.0f;
};

struct TechniqueTiming {
    std::string name;              // "bump", "lean", ..., or kFloorName
    std::optional<Technique> technique;  // the technique timed; none for the floor
    std::vector<double> frame_ms;  // one per timed round, in round order
    SampleStats stats;             // of frame_ms
    double fps = 0.0;              // 1000 / median
};

struct ViewResult {
    std::string name;                      // "fill", or "d3", "d8", ... ("d" + distance_text)
    float distance = 0.0f;                 // camera distance from the centre, bounding radii
    float fov_y_degrees = 0.0f;            // the fill view narrows the field of view until covered
    double coverage = 0.0;                 // fraction of the framebuffer's pixels the object covers
    std::vector<TechniqueTiming> timings;  // request order, the floor (when measured) first
    // Per timed round, the indices into `timings` in the order they were drawn.
    std::vector<std::vector<int>> order;

    // The timing called `name` (a technique's name or kFloorName), or nullptr.
    const TechniqueTiming* find(const std::string& name) const;
    // The timing of `technique`, or nullptr when it was not measured.
    const TechniqueTiming* find(Technique technique) const;
    // The constant-colour floor's timing, or nullptr when it was not measured.
    const TechniqueTiming* floor() const;
    // Median over rounds of a[i] / b[i] (frame time of a over that of b); 0 when either was not
    // measured.
    double ratio(Technique a, Technique b) const;
    // The same against the constant-colour floor.
    double ratio_to_floor(Technique a) const;
};

struct SceneResult {
    std::string name;
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    std::vector<ViewResult> views;  // "fill" first (when measured), then by distance

    // The view called `name`, or nullptr.
    const ViewResult* find(const std::string& name) const;
};

// A scene to measure: `scene` (drawn with Renderer::set_scene), or else `mesh` with the LEAN map
// the renderer has (set_mesh).
struct FrameBenchScene {
    std::string name;
    const scene::Mesh* mesh = nullptr;
    const scene::Scene* scene = nullptr;
};

struct FrameBenchResult {
    TimingChoice timing;
    std::string gl_renderer;  // GL_RENDERER
    std::string gl_version;   // GL_VERSION
    std::vector<SceneResult> scenes;
};

// Checks the request (sizes, counts, distances, no reference technique, settings), throwing
// leanfade::Error(flag of `leanfade bench`, cause).
void validate_frame_bench(const FrameBenchRequest& request);

// Runs the benchmark over `scenes`; the renderer's scene is replaced (a scene given as a mesh is
// drawn with the renderer's LEAN map, set beforehand). progress(done, total) is called after each
// view when given. Throws leanfade::Error for an invalid request, a GL error or an unavailable
// timing method.
FrameBenchResult run_frame_bench(Renderer& renderer, const std::vector<FrameBenchScene>& scenes,
                                 const FrameBenchRequest& request,
                                 const std::function<void(int done, int total)>& progress = {});

// The fill view of the mesh set on `renderer`: the camera at the near distance (3 bounding radii)
// along `direction`, its field of view narrowed (by factors of 0.8 from kDefaultFovYDegrees)
// until the object covers every pixel of a probe framebuffer of the given aspect ratio, or down
// to 1.5 degrees. Returns the view; `coverage` gets the probe's covered fraction.
View fill_view(Renderer& renderer, float aspect, glm::vec3 direction, double* coverage = nullptr);

}  // namespace leanfade::gl
