#pragma once
// Calibration of specular fading (the fading paper, eq. 6-7), GL-free part: the model of fade's
// specular energy relative to LEAN's from per-pixel samples of a LEAN render, the physical
// targets, and the least-squares fit of Fade (and optionally Pmax).
//
// Model. Fading multiplies LEAN's specular term S of a pixel by NdotL^(sf - 1) (eq. 7: Ks
// NdotL^sf D F instead of Ks NdotL D F), with sf = clamp(1 + (d Fade)^p, 1, Pmax) (eq. 6) taken
// from the shared header (shading::lf_fade_factor). Over the object's pixels at one camera
// distance, fade's energy relative to LEAN's is
//     ratio(Fade, Pmax) = sum_i S_i NdotL_i^(sf(d_i) - 1) / sum_i S_i,
// exactly what the GPU's fade technique gives up to float rounding, so the fit needs one LEAN
// render per distance and no re-rendering per trial.
#include <string>
#include <vector>

#include "leanfade/core/settings.hpp"

namespace leanfade::eval {

// The object's pixels at one camera distance, from a LEAN render: S (specular radiance, mean of
// the three channels), NdotL and the fading distance d (lf_fade_terms) of each pixel with S > 0.
struct FadeSamples {
    float camera_distance = 0.0f;  // bounding radii
    std::vector<float> specular;
    std::vector<float> n_dot_l;
    std::vector<float> fade_distance;
};

// fade's specular energy / LEAN's at these samples (1 when there is no specular energy).
// fade = 0 gives exactly 1.
double fade_energy_ratio(const FadeSamples& samples, float fade, float pmax, float exponent);

// The attenuation that fading should follow over distance.
struct FadeTarget {
    enum class Kind {
        Exponential,  // exp(-sigma d), d the camera distance in bounding radii
        Fog,          // the scene fog's transmittance f at the eye depth d of the object's centre
        Reference,    // the supersampled truth's specular energy / LEAN's (measured: runner.hpp)
    };
    Kind kind = Kind::Exponential;
    float sigma = 0.05f;  // per bounding radius (Exponential)
};

// "exp:SIGMA" (SIGMA >= 0, finite), "fog" or "reference". Throws leanfade::Error(flag, cause).
FadeTarget parse_fade_target(const std::string& text, const std::string& flag = "target");
std::string to_string(const FadeTarget& target);  // "exp:0.05", "fog", "reference"

// The target's values at the camera distances. Fog uses settings.fog (lf_fog_factor, docs/math.md
// §4, with the eye depth = the distance); throws leanfade::Error("target", ...) when the settings
// have no fog, and for Reference, which needs renders (measure_reference_ratio).
std::vector<double> target_attenuation(const FadeTarget& target,
                                       const std::vector<float>& distances,
                                       const ShadingSettings& settings);

struct FadeFitOptions {
    bool fit_pmax = false;  // false: Pmax stays `pmax`
    float pmax = 16.0f;     // Pmax when not fitted
    float exponent = 2.0f;  // p of eq. 6 (not fitted)
};

struct FadeFit {
    float fade = 0.0f;
    float pmax = 1.0f;
    double residual = 0.0;      // root mean square of model - target over the distances
    std::vector<double> model;  // the ratio at each distance with the fitted parameters
};

// Least squares over the distances: minimises sum_d (ratio_d(Fade, Pmax) - target_d)^2 over
// Fade in [0, 100] per bounding radius (and Pmax in [1, 10^4] when fitted): a scan of log-spaced
// values, then golden-section refinement around the best (ratio is monotone in each parameter).
// When the best Fade is 0 (the target asks for no attenuation, or more energy than LEAN has),
// Pmax has no effect and is returned as options.pmax.
// Throws leanfade::Error("calibrate", ...) when the sizes differ or there are no distances.
FadeFit fit_fade(const std::vector<FadeSamples>& samples, const std::vector<double>& target,
                 const FadeFitOptions& options);

// The gnuplot script of `leanfade calibrate`'s plot: target (column 2), model (3) and achieved
// (4) against distance from `data_file`, drawn into `plot_file` (both names relative to the
// script's folder, where run_gnuplot runs it). `target_name` is the title's (to_string(target));
// `target` and `achieved` set the y range. Names and titles are gnuplot_string / gnuplot_file
// literals (results.hpp); throws leanfade::Error(name, cause) for a file name gnuplot cannot be
// given (a control character).
std::string calibration_plot_script(const std::string& target_name, double fade, double pmax,
                                    const std::vector<double>& target,
                                    const std::vector<double>& achieved,
                                    const std::string& plot_file, const std::string& data_file);

}  // namespace leanfade::eval
