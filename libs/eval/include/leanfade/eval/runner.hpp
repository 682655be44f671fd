#pragma once
// The OpenGL half of `leanfade eval` and `leanfade calibrate` (target leanfade_eval_gl): renders
// every technique and the supersampled reference (docs/math.md §7) from the same cameras and
// measures them with metrics.hpp, and fits specular fading to a physical attenuation
// (calibration.hpp).
//
// Cameras look at the object's centre from `distance` bounding radii along a fixed direction with
// a fixed field of view, so far objects are small, as in the papers. Only the square of the frame
// around the object's bounding sphere is rendered (same pixel size, same shading: a centred crop
// is a narrower symmetric frustum), which keeps far distances cheap.
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "leanfade/core/settings.hpp"
#include "leanfade/eval/calibration.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/gl/renderer.hpp"

namespace leanfade::eval {

// A camera and the size of the image to render with it.
struct Framing {
    gl::View view;
    int width = 0;
    int height = 0;
};

// The camera at `distance` along `direction` (toward the eye) looking at the origin with the
// vertical field of view of a frame_width x frame_height frame, narrowed to the centred crop that
// holds the object's bounding sphere plus `margin_pixels` on each side (never larger than the
// frame; the crop keeps the frame's parity, so its pixels are the frame's pixels).
Framing frame_object(float distance, float fov_y_degrees, glm::vec3 direction, int frame_width,
                     int frame_height, float margin_pixels);

// `view` moved along the image's +x and +y by these many pixels at the depth of its target (a
// pan: eye and target move together), for an image `image_height` pixels tall.
gl::View panned(const gl::View& view, int image_height, float pixels_x, float pixels_y = 0.0f);

// The perceptual roughness r of the Beckmann lobe matching the Blinn-Phong exponent s:
// a0^2 = 2 / (s + 2) (Walter et al. 2007, docs/math.md §9) and a0 = r^2. Clamped to
// [kMinRoughness, 1].
float roughness_for_shininess(float shininess);

struct SweepRequest {
    std::vector<gl::Technique> techniques = approximating_techniques();
    std::vector<float> distances{2.0f, 4.0f, 8.0f, 16.0f, 32.0f, 64.0f};  // bounding radii, > 1
    std::vector<float> shininesses{128.0f, 1024.0f, 13777.0f};
    int width = 256;  // the full frame, pixels
    int height = 256;
    float fov_y_degrees = gl::kDefaultFovYDegrees;
    glm::vec3 view_direction = gl::kDefaultViewDirection;
    int reference_samples = 8;  // k: the reference takes k x k samples per pixel, [1, 16]
    // Where the object covers fewer pixels than the frame, take more reference samples per
    // pixel so that the samples per frame stay those of the full frame at k: k up to 16 (the
    // renderer's limit), then up to 8 x 8 renders with sub-sample camera offsets averaged (a
    // finer regular grid, up to 16384 per pixel). Far objects, whose pixels hold many bumps, get
    // a better converged truth for the cost of a near one.
    bool adaptive_reference = true;
    int frames = 16;              // >= 2: frame 0 is measured, all frames for flicker
    float motion_pixels = 0.25f;  // camera pan per frame at the object's centre, (0, 4]
    // shininess is replaced by each of `shininesses`; with the Cook-Torrance BRDF, roughness by
    // the one of the same lobe width (roughness_for_shininess), so that the sweeps of both
    // models stand side by side. settings.reference_model picks the truth (docs/math.md §7).
    ShadingSettings settings;
    glm::vec3 background{0.0f};   // linear RGB behind the object in the images
    bool keep_images = true;      // fill SweepOutput::images
};

struct SweepOutput {
    std::vector<CaseResult> cases;  // shininess outer, distance, technique inner
    std::vector<CaseImages> images;
};

// Renders and measures every case (see CaseResult and results_json's definitions). progress(done,
// total) is called after each rendered frame of every (shininess, distance). Throws
// leanfade::Error(flag, cause) for an invalid request (no techniques, the reference among them,
// frames < 2, ...) and what the renderer throws.
SweepOutput run_sweep(gl::Renderer& renderer, const SweepRequest& request,
                      const std::function<void(int done, int total)>& progress = {});

// The cameras of a calibration: distances along one direction.
struct CameraSweep {
    std::vector<float> distances{2.0f, 3.0f, 4.5f, 6.5f, 9.5f, 14.0f, 20.0f, 30.0f, 45.0f, 64.0f};
    int width = 128;  // the full frame, pixels
    int height = 128;
    float fov_y_degrees = gl::kDefaultFovYDegrees;
    glm::vec3 view_direction = gl::kDefaultViewDirection;
};

// Renders LEAN's specular term and the fading inputs (gl::OutputMode::FadeTerms) at each
// distance: the samples of the energy-ratio model (calibration.hpp).
std::vector<FadeSamples> measure_fade_samples(gl::Renderer& renderer, const CameraSweep& cameras,
                                              const ShadingSettings& settings);
// fade's specular energy / LEAN's at each distance as the GPU renders them (sums over the image).
std::vector<double> measure_fade_ratio(gl::Renderer& renderer, const CameraSweep& cameras,
                                       const ShadingSettings& settings);

// The supersampled truth's specular energy / LEAN's at each distance (sums over the image): the
// attenuation that would make fade's energy the truth's. The reference takes k x k samples per
// pixel, more where the object is small (as SweepRequest::adaptive_reference).
std::vector<double> measure_reference_ratio(gl::Renderer& renderer, const CameraSweep& cameras,
                                            const ShadingSettings& settings,
                                            int reference_samples = 8);

struct FadeCalibrationRequest {
    CameraSweep cameras;
    ShadingSettings settings;  // Pmax when not fitted; p and the distance mode are kept
    FadeTarget target;
    bool fit_pmax = false;
    int reference_samples = 8;  // k of the reference, for FadeTarget::Kind::Reference
};

struct FadeCalibration {
    FadeFit fit;  // Fade, Pmax, the model's residual and values
    std::vector<float> distances;
    std::vector<double> target;      // the target attenuation at each distance
    std::vector<double> achieved;    // measure_fade_ratio with the fitted Fade and Pmax
    double achieved_residual = 0.0;  // RMS of achieved - target
};

// Fits Fade (and Pmax when asked) so that fade's energy relative to LEAN over the distances
// follows the target in least squares (fit_fade), then renders fade with the result to report
// what is achieved. The renderer's mesh and LEAN map are used as set. The viewer's calibration
// button and `leanfade calibrate` call this.
FadeCalibration calibrate_fade(gl::Renderer& renderer, const FadeCalibrationRequest& request);

}  // namespace leanfade::eval
