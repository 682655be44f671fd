// Sweeps of `leanfade eval` and the renders of `leanfade calibrate`.
#include "leanfade/eval/runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/eval/metrics.hpp"
#include "leanfade/core/technique.hpp"

namespace leanfade::eval {
namespace {

// Background marker of the single-sample techniques: shading values are never negative, so a
// negative pixel is one the object does not cover (covered_pixels).
constexpr float kMarker = -1.0f;

int crop_side(int frame, int half) {
    return std::min(frame, 2 * half + (frame & 1));
}

void validate(const SweepRequest& r) {
    if (r.techniques.empty()) throw Error::setting("techniques", "no technique to measure");
    for (gl::Technique t : r.techniques)
        if (info(t).supersampled)
            throw Error::setting("techniques",
                                 std::string("the ") + to_string(t) +
                                     " is what every technique is measured against; it "
                                     "cannot be one of them");
    if (r.distances.empty()) throw Error::setting("distances", "no distance");
    for (float d : r.distances)
        if (!(d > 1.0f) || !(d <= 1e4f))
            throw Error::setting("distances", "distances must be in (1, 1e4] bounding radii");
    if (r.shininesses.empty()) throw Error::setting("shininess", "no shininess");
    for (float s : r.shininesses)
        if (!(s > 0.0f) || !std::isfinite(s)) throw Error::setting("shininess", "must be > 0");
    if (r.reference_samples < 1 || r.reference_samples > kMaxReferenceSamples)
        throw Error::setting("spp", "the reference takes k x k samples per pixel with k in [1, " +
                                        std::to_string(kMaxReferenceSamples) + "]");
    if (r.frames < 2 || r.frames > 1000)
        throw Error::setting("frames",
                             "flicker needs 2 to 1000 frames, got " + std::to_string(r.frames));
    if (!(r.motion_pixels > 0.0f && r.motion_pixels <= 4.0f))
        throw Error::setting("motion", "the pan per frame must be in (0, 4] pixels");
    if (r.width < 16 || r.height < 16 || r.width > 8192 || r.height > 8192)
        throw Error::setting("size", "each side must be in [16, 8192] pixels");
}

std::string number_text(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", v);
    return buffer;
}

// Every measurement of a case is a finite number: a NaN or infinity is an error, never a value
// in the tables. Only the ratios whose denominator is 0 stay undefined (NaN, null in
// results.json): energy when the reference has no specular energy, flicker when the reference
// does not change.
void require_finite_case(const CaseResult& c) {
    const struct {
        double value;
        const char* name;
        bool may_be_undefined;
    } values[] = {{c.specular_mean, "specular energy", false},
                  {c.reference_specular_mean, "reference specular energy", false},
                  {c.reference_mean, "reference mean", false},
                  {c.rmse, "relative RMSE", false},
                  {c.ssim, "SSIM", false},
                  {c.change, "frame-to-frame change", false},
                  {c.reference_change, "reference frame-to-frame change", false},
                  {c.reference_noise, "reference noise", false},
                  {c.energy, "energy ratio", c.reference_specular_mean == 0.0},
                  {c.energy_total, "energy ratio over all covered pixels",
                   c.reference_specular_total == 0.0},
                  {c.flicker, "flicker ratio", c.reference_change == 0.0}};
    for (const auto& v : values)
        if (!std::isfinite(v.value) && !v.may_be_undefined)
            throw Error("eval", std::string(to_string(c.technique)) + " at distance " + number_text(c.distance) +
                                    ", shininess " + number_text(c.shininess) + ": the " +
                                    v.name + " is " + number_text(v.value) +
                                    " (not a finite number)");
}

// Sum of the three colour channels over every pixel.
double channel_sum(const Image& image) {
    double sum = 0.0;
    const std::size_t stride = std::size_t(image.channels);
    for (std::size_t i = 0; i < image.texel_count(); ++i)
        for (std::size_t c = 0; c < 3; ++c) sum += double(image.pixels[i * stride + c]);
    return sum;
}

// Samples of the reference: k x k per pixel in each of passes x passes renders, each shifted by
// a fraction of the sample spacing, so that their mean is the box filter of a (k passes)^2 grid.
struct Sampling {
    int k = 1;
    int passes = 1;
    int per_pixel() const { return k * passes * k * passes; }
};

constexpr int kMaxPasses = 8;

// The reference's sampling for one framing (SweepRequest::adaptive_reference): as many samples
// per frame as the full frame at the requested k, but no fewer per pixel than k x k.
Sampling reference_sampling(int k, bool adaptive, int frame_width, int frame_height,
                            const Framing& framing) {
    Sampling s;
    s.k = k;
    if (!adaptive) return s;
    const double side = double(k) * std::sqrt(double(frame_width) * double(frame_height) /
                                              (double(framing.width) * double(framing.height)));
    s.k = std::clamp(int(std::floor(side)), k, 16);
    s.passes = std::clamp(int(std::floor(side / double(s.k))), 1, kMaxPasses);
    return s;
}

// The reference (request.technique is ignored) with `sampling`: the mean of passes^2 renders
// whose cameras are panned by sub-sample offsets (a regular grid of the pixel's samples).
Image render_reference(gl::Renderer& renderer, gl::RenderRequest request,
                       const Sampling& sampling) {
    request.technique = gl::Technique::Reference;
    request.reference_samples = sampling.k;
    if (sampling.passes == 1) return renderer.render(request);
    const gl::View view = request.view;
    Image sum;
    const int q = sampling.passes;
    for (int j = 0; j < q; ++j)
        for (int i = 0; i < q; ++i) {
            // Offsets in pixels, centred: the k x k grid's cells split q x q.
            const float dx = ((float(i) + 0.5f) / float(q) - 0.5f) / float(sampling.k);
            const float dy = ((float(j) + 0.5f) / float(q) - 0.5f) / float(sampling.k);
            request.view = panned(view, request.height, dx, dy);
            const Image pass = renderer.render(request);
            if (sum.empty()) {
                sum = pass;
            } else {
                for (std::size_t p = 0; p < sum.pixels.size(); ++p) sum.pixels[p] += pass.pixels[p];
            }
        }
    const float scale = 1.0f / float(q * q);
    for (float& v : sum.pixels) v *= scale;
    return sum;
}

// A quarter of `s`'s samples, for the estimate of the reference's own error.
Sampling quarter(const Sampling& s) {
    Sampling q = s;
    if (s.passes >= 2)
        q.passes = s.passes / 2;
    else if (s.k >= 2)
        q.k = s.k / 2;
    else
        q.k = 2;  // k = 1: compare with four times the samples instead
    return q;
}

}  // namespace

Framing frame_object(float distance, float fov_y_degrees, glm::vec3 direction, int frame_width,
                     int frame_height, float margin_pixels) {
    const gl::View full = gl::view_at_distance(distance, fov_y_degrees, direction);
    const float radius = gl::projected_radius_pixels(full, frame_height);
    const int half = int(std::ceil(radius + std::max(0.0f, margin_pixels)));
    Framing f;
    f.width = crop_side(frame_width, half);
    f.height = crop_side(frame_height, half);
    // Same pixel size: tan(fov'/2) / height' = tan(fov/2) / height.
    const float fov = 2.0f * glm::degrees(std::atan(std::tan(glm::radians(fov_y_degrees) * 0.5f) *
                                                    float(f.height) / float(frame_height)));
    f.view = gl::view_at_distance(distance, fov, direction);
    return f;
}

gl::View panned(const gl::View& view, int image_height, float pixels_x, float pixels_y) {
    const glm::vec3 forward = view.target - view.eye;
    const float depth = glm::length(forward);
    const glm::vec3 right = glm::normalize(glm::cross(forward, view.up));
    const glm::vec3 up = glm::normalize(glm::cross(right, forward));
    const float pixel =
        2.0f * depth * std::tan(glm::radians(view.fov_y_degrees) * 0.5f) / float(image_height);
    const glm::vec3 shift = (right * pixels_x + up * pixels_y) * pixel;
    gl::View out = view;
    out.eye += shift;
    out.target += shift;
    return out;
}

float roughness_for_shininess(float shininess) {
    const float alpha0 = std::sqrt(2.0f / (shininess + 2.0f));
    return std::clamp(std::sqrt(alpha0), kMinRoughness, 1.0f);
}

SweepOutput run_sweep(gl::Renderer& renderer, const SweepRequest& request,
                      const std::function<void(int done, int total)>& progress) {
    validate(request);
    const std::size_t nt = request.techniques.size();
    const int total = int(request.shininesses.size() * request.distances.size()) * request.frames;
    int done = 0;
    SweepOutput output;
    const glm::vec3 bg = request.background;

    for (float shininess : request.shininesses) {
        ShadingSettings settings = request.settings;
        settings.shininess = shininess;
        if (settings.brdf == Brdf::CookTorrance)
            settings.roughness = roughness_for_shininess(shininess);
        for (float distance : request.distances) {
            const float margin = request.motion_pixels * float(request.frames - 1) + 2.0f;
            const Framing framing =
                frame_object(distance, request.fov_y_degrees, request.view_direction, request.width,
                             request.height, margin);
            gl::RenderRequest base;
            base.width = framing.width;
            base.height = framing.height;
            base.settings = settings;
            const Sampling sampling =
                reference_sampling(request.reference_samples, request.adaptive_reference,
                                   request.width, request.height, framing);

            std::vector<CaseResult> cases(nt);
            std::vector<Image> previous(nt);
            std::vector<double> change(nt, 0.0);
            Image reference_previous;
            double reference_change = 0.0;
            Mask previous_mask;
            CaseImages kept;
            kept.shininess = shininess;
            kept.distance = distance;

            for (int frame = 0; frame < request.frames; ++frame) {
                base.view =
                    panned(framing.view, framing.height, request.motion_pixels * float(frame));
                gl::RenderRequest r = base;
                r.output = gl::OutputMode::Color;
                r.background = bg;
                const Image reference = render_reference(renderer, r, sampling);
                const Image reference_srgb = encode_srgb(reference);

                std::vector<Image> colors(nt);
                r.background = glm::vec3(kMarker);
                for (std::size_t t = 0; t < nt; ++t) {
                    r.technique = request.techniques[t];
                    colors[t] = renderer.render(r);
                }
                const Mask covered = covered_pixels(colors[0]);
                const Mask mask = erode(covered);
                if (frame == 0 && mask.count() == 0)
                    throw Error::setting(
                        "distances", "at distance " + number_text(distance) +
                                         " the object covers no whole pixel of the " +
                                         std::to_string(request.width) + "x" +
                                         std::to_string(request.height) +
                                         " frame: nothing to measure (use smaller distances or a "
                                         "larger image size)");
                std::vector<Image> srgb(nt);
                for (std::size_t t = 0; t < nt; ++t) {
                    colors[t] = fill_outside(colors[t], covered, bg.r, bg.g, bg.b);
                    srgb[t] = encode_srgb(colors[t]);
                }

                if (frame == 0) {
                    gl::RenderRequest s = base;
                    s.output = gl::OutputMode::Specular;
                    const Image reference_specular_image = render_reference(renderer, s, sampling);
                    const double reference_specular = masked_mean(reference_specular_image, mask);
                    // Over the whole image: every covered pixel, the reference's partly covered
                    // edge pixels with their share (the background is black).
                    const double reference_specular_total = channel_sum(reference_specular_image);
                    const double reference_mean = masked_mean(reference, mask);
                    // The reference's own error, from one with a quarter of the samples:
                    // var(check) = n var(reference), so the difference has 1 + n times the
                    // reference's variance.
                    const Sampling fewer = quarter(sampling);
                    const double n = double(sampling.per_pixel()) / double(fewer.per_pixel());
                    const double spread = std::sqrt(1.0 + n);
                    gl::RenderRequest check = r;
                    check.background = bg;
                    const double reference_noise =
                        relative_rmse(render_reference(renderer, check, fewer), reference, mask) /
                        spread;
                    check.output = gl::OutputMode::Specular;
                    const double check_specular =
                        masked_mean(render_reference(renderer, check, fewer), mask);
                    const double reference_energy_error =
                        reference_specular > 0.0 ? std::abs(check_specular - reference_specular) /
                                                       (reference_specular * spread)
                                                 : std::nan("");
                    for (std::size_t t = 0; t < nt; ++t) {
                        s.technique = request.techniques[t];
                        CaseResult& c = cases[t];
                        c.technique = request.techniques[t];
                        c.distance = distance;
                        c.shininess = shininess;
                        const Image specular = renderer.render(s);
                        c.specular_mean = masked_mean(specular, mask);
                        c.specular_total = channel_sum(specular);
                        c.reference_specular_total = reference_specular_total;
                        c.energy_total = reference_specular_total > 0.0
                                             ? c.specular_total / reference_specular_total
                                             : std::nan("");
                        c.reference_specular_mean = reference_specular;
                        c.energy = reference_specular > 0.0 ? c.specular_mean / reference_specular
                                                            : std::nan("");
                        c.reference_mean = reference_mean;
                        c.rmse = relative_rmse(colors[t], reference, mask);
                        c.ssim = ssim(srgb[t], reference_srgb, mask);
                        c.object_pixels = mask.count();
                        c.reference_spp = sampling.per_pixel();
                        c.reference_noise = reference_noise;
                        c.reference_energy_error = reference_energy_error;
                    }
                    if (request.keep_images) {
                        kept.reference = reference;
                        for (std::size_t t = 0; t < nt; ++t)
                            kept.techniques.emplace_back(cases[t].technique, colors[t]);
                    }
                } else {
                    const Mask both = intersect(mask, previous_mask);
                    for (std::size_t t = 0; t < nt; ++t)
                        change[t] += mean_absolute_difference(srgb[t], previous[t], both);
                    reference_change +=
                        mean_absolute_difference(reference_srgb, reference_previous, both);
                }
                previous = std::move(srgb);
                reference_previous = reference_srgb;
                previous_mask = mask;
                ++done;
                if (progress) progress(done, total);
            }

            const double steps = double(request.frames - 1);
            for (std::size_t t = 0; t < nt; ++t) {
                CaseResult& c = cases[t];
                c.change = change[t] / steps;
                c.reference_change = reference_change / steps;
                c.flicker = c.reference_change > 0.0 ? c.change / c.reference_change : std::nan("");
                require_finite_case(c);
                output.cases.push_back(c);
            }
            if (request.keep_images) output.images.push_back(std::move(kept));
        }
    }
    return output;
}

namespace {

// The calibration sweeps' camera at `distance`: the object framed with a 2-pixel margin.
Framing frame_sweep_camera(const CameraSweep& cameras, float distance) {
    return frame_object(distance, cameras.fov_y_degrees, cameras.view_direction, cameras.width,
                        cameras.height, 2.0f);
}

// LEAN's specular term alone (the quantity fading scales), from `framing`'s camera.
gl::RenderRequest lean_specular_request(const Framing& framing, const ShadingSettings& settings) {
    gl::RenderRequest r;
    r.technique = gl::Technique::Lean;
    r.width = framing.width;
    r.height = framing.height;
    r.view = framing.view;
    r.settings = settings;
    r.output = gl::OutputMode::Specular;
    return r;
}

}  // namespace

std::vector<FadeSamples> measure_fade_samples(gl::Renderer& renderer, const CameraSweep& cameras,
                                              const ShadingSettings& settings) {
    std::vector<FadeSamples> result;
    for (float distance : cameras.distances) {
        const Framing framing = frame_sweep_camera(cameras, distance);
        gl::RenderRequest r = lean_specular_request(framing, settings);
        const Image specular = renderer.render(r);
        r.output = gl::OutputMode::FadeTerms;
        const Image terms = renderer.render(r);
        FadeSamples samples;
        samples.camera_distance = distance;
        for (std::size_t i = 0; i < specular.texel_count(); ++i) {
            const std::size_t p = i * std::size_t(specular.channels);
            const float s =
                (specular.pixels[p] + specular.pixels[p + 1] + specular.pixels[p + 2]) / 3.0f;
            if (!(s > 0.0f)) continue;
            const std::size_t q = i * std::size_t(terms.channels);
            samples.specular.push_back(s);
            samples.n_dot_l.push_back(terms.pixels[q]);
            samples.fade_distance.push_back(terms.pixels[q + 1]);
        }
        result.push_back(std::move(samples));
    }
    return result;
}

std::vector<double> measure_fade_ratio(gl::Renderer& renderer, const CameraSweep& cameras,
                                       const ShadingSettings& settings) {
    std::vector<double> ratios;
    for (float distance : cameras.distances) {
        const Framing framing = frame_sweep_camera(cameras, distance);
        gl::RenderRequest r = lean_specular_request(framing, settings);
        const double lean = channel_sum(renderer.render(r));
        r.technique = gl::Technique::Fade;
        const double fade = channel_sum(renderer.render(r));
        ratios.push_back(lean > 0.0 ? fade / lean : 1.0);
    }
    return ratios;
}

std::vector<double> measure_reference_ratio(gl::Renderer& renderer, const CameraSweep& cameras,
                                            const ShadingSettings& settings,
                                            int reference_samples) {
    std::vector<double> ratios;
    for (float distance : cameras.distances) {
        const Framing framing = frame_sweep_camera(cameras, distance);
        gl::RenderRequest r = lean_specular_request(framing, settings);
        const double lean = channel_sum(renderer.render(r));
        const Sampling sampling =
            reference_sampling(reference_samples, true, cameras.width, cameras.height, framing);
        const double truth = channel_sum(render_reference(renderer, r, sampling));
        ratios.push_back(lean > 0.0 ? truth / lean : 1.0);
    }
    return ratios;
}

FadeCalibration calibrate_fade(gl::Renderer& renderer, const FadeCalibrationRequest& request) {
    if (request.cameras.distances.empty()) throw Error::setting("distances", "no distance");
    for (float d : request.cameras.distances)
        if (!(d > 1.0f) || !(d <= 1e4f))
            throw Error::setting("distances", "distances must be in (1, 1e4] bounding radii");
    leanfade::validate(request.settings);
    FadeCalibration result;
    result.distances = request.cameras.distances;
    result.target =
        request.target.kind == FadeTarget::Kind::Reference
            ? measure_reference_ratio(renderer, request.cameras, request.settings,
                                      request.reference_samples)
            : target_attenuation(request.target, request.cameras.distances, request.settings);
    const std::vector<FadeSamples> samples =
        measure_fade_samples(renderer, request.cameras, request.settings);
    FadeFitOptions options;
    options.fit_pmax = request.fit_pmax;
    options.pmax = request.settings.pmax;
    options.exponent = request.settings.fade_exponent;
    result.fit = fit_fade(samples, result.target, options);

    ShadingSettings fitted = request.settings;
    fitted.fade = result.fit.fade;
    fitted.pmax = result.fit.pmax;
    result.achieved = measure_fade_ratio(renderer, request.cameras, fitted);
    double sum = 0.0;
    for (std::size_t i = 0; i < result.achieved.size(); ++i)
        sum += (result.achieved[i] - result.target[i]) * (result.achieved[i] - result.target[i]);
    result.achieved_residual = std::sqrt(sum / double(result.achieved.size()));
    return result;
}

}  // namespace leanfade::eval
