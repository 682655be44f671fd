// Fade calibration: the energy-ratio model, the targets and the least-squares fit.
#include "leanfade/eval/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <sstream>

#include "leanfade/core/error.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/eval/results.hpp"

namespace leanfade::eval {
namespace {

constexpr double kMaxFade = 100.0;  // per bounding radius: sf saturates within 0.1 radii
constexpr double kMinFade = 1e-4;   // below this sf - 1 < 1e-4 d^p at d <= 100: no fading
constexpr double kMaxPmax = 1.0e4;

// Golden-section search of f over [a, b] (f unimodal there); returns the best x found.
double golden_minimum(const std::function<double(double)>& f, double a, double b, int steps) {
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    double c = b - g * (b - a), d = a + g * (b - a);
    double fc = f(c), fd = f(d);
    for (int i = 0; i < steps; ++i) {
        if (fc <= fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    return fc <= fd ? c : d;
}

// Minimises f over log-spaced values of [lo, hi] (count values), then refines by golden section
// between the neighbours of the best; `zero` is tried too when given (log scale cannot hold it).
double scan_and_refine(const std::function<double(double)>& f, double lo, double hi, int count,
                       bool try_zero) {
    const double log_lo = std::log(lo), log_hi = std::log(hi);
    auto at = [&](int i) { return std::exp(log_lo + (log_hi - log_lo) * i / (count - 1)); };
    int best = 0;
    double best_value = f(at(0));
    for (int i = 1; i < count; ++i) {
        const double v = f(at(i));
        if (v < best_value) {
            best_value = v;
            best = i;
        }
    }
    const double a = std::log(at(std::max(0, best - 1)));
    const double b = std::log(at(std::min(count - 1, best + 1)));
    const double refined =
        std::exp(golden_minimum([&](double u) { return f(std::exp(u)); }, a, b, 32));
    double result = f(refined) <= best_value ? refined : at(best);
    if (try_zero && f(0.0) < f(result)) result = 0.0;
    return result;
}

// The samples as the search evaluates them: weight, ln NdotL and ln d, so that a trial costs two
// exp per pixel: (d Fade)^p = exp(p (ln d + ln Fade)) and NdotL^(sf - 1) = exp((sf - 1) ln NdotL),
// the values of fade_energy_ratio (in float). Pixels without specular energy are left out.
struct FastSamples {
    std::vector<float> weight, log_n_dot_l, log_distance;
    double total = 0.0;
};

FastSamples prepare(const FadeSamples& s) {
    FastSamples f;
    for (std::size_t i = 0; i < s.specular.size(); ++i) {
        if (!(s.specular[i] > 0.0f) || !(s.n_dot_l[i] > 0.0f)) continue;  // LEAN's S is 0 too
        f.weight.push_back(s.specular[i]);
        f.log_n_dot_l.push_back(std::log(std::min(s.n_dot_l[i], 1.0f)));
        f.log_distance.push_back(std::log(std::max(s.fade_distance[i], 0.0f)));  // 0: -inf
        f.total += double(s.specular[i]);
    }
    return f;
}

double fast_ratio(const FastSamples& s, double fade, double pmax, double exponent) {
    if (fade == 0.0 || s.total == 0.0) return 1.0;
    const float log_fade = float(std::log(fade)), p = float(exponent);
    const float top = float(std::max(pmax, 1.0));
    double sum = 0.0;
    for (std::size_t i = 0; i < s.weight.size(); ++i) {
        const float sf = std::min(1.0f + std::exp(p * (s.log_distance[i] + log_fade)), top);
        sum += double(s.weight[i]) *
               (sf == 1.0f ? 1.0 : double(std::exp((sf - 1.0f) * s.log_n_dot_l[i])));
    }
    return sum / s.total;
}

}  // namespace

double fade_energy_ratio(const FadeSamples& samples, float fade, float pmax, float exponent) {
    double lean = 0.0, faded = 0.0;
    for (std::size_t i = 0; i < samples.specular.size(); ++i) {
        const double s = samples.specular[i];
        lean += s;
        if (fade == 0.0f) {
            faded += s;
            continue;
        }
        const float sf = shading::lf_fade_factor(samples.fade_distance[i], fade, exponent, pmax);
        // NdotL^sf / NdotL (eq. 7); sf == 1 leaves the pixel as LEAN's (lf_combine's exact path).
        faded += sf == 1.0f ? s : s * std::pow(double(samples.n_dot_l[i]), double(sf) - 1.0);
    }
    return lean > 0.0 ? faded / lean : 1.0;
}

FadeTarget parse_fade_target(const std::string& text, const std::string& flag) {
    FadeTarget target;
    // The supersampled ground truth is named as the technique table names it.
    const std::string truth = to_string(Technique::Reference);
    if (text == "fog" || text == truth) {
        target.kind = text == "fog" ? FadeTarget::Kind::Fog : FadeTarget::Kind::Reference;
        return target;
    }
    if (text.rfind("exp:", 0) == 0) {
        const std::string value = text.substr(4);
        const std::optional<float> sigma = parse_finite_float(value);
        if (sigma && *sigma >= 0.0f) {
            target.kind = FadeTarget::Kind::Exponential;
            target.sigma = *sigma;
            return target;
        }
        throw Error::setting(
            flag, "exp:SIGMA needs a finite SIGMA >= 0 (per bounding radius), got '" + value + "'");
    }
    throw Error::setting(flag, "expected exp:SIGMA, fog or reference, got '" + text + "'");
}

std::string to_string(const FadeTarget& target) {
    if (target.kind == FadeTarget::Kind::Fog) return "fog";
    if (target.kind == FadeTarget::Kind::Reference) return to_string(Technique::Reference);
    std::ostringstream out;
    out << "exp:" << target.sigma;
    return out.str();
}

std::vector<double> target_attenuation(const FadeTarget& target,
                                       const std::vector<float>& distances,
                                       const ShadingSettings& settings) {
    if (target.kind == FadeTarget::Kind::Reference)
        throw Error::setting("target",
                             "reference: the truth's energy is measured by rendering "
                             "(measure_reference_ratio)");
    if (target.kind == FadeTarget::Kind::Fog && settings.fog == FogMode::None)
        throw Error::setting("target",
                             "fog: the scene has no fog (set the fog mode to linear, exp or exp2, "
                             "and its parameters)");
    std::vector<double> values;
    for (float d : distances) {
        if (target.kind == FadeTarget::Kind::Exponential) {
            values.push_back(std::exp(-double(target.sigma) * double(d)));
        } else {
            values.push_back(shading::lf_fog_factor(d, to_shader_constant(settings.fog),
                                                    settings.fog_start, settings.fog_end,
                                                    settings.fog_density));
        }
    }
    return values;
}

FadeFit fit_fade(const std::vector<FadeSamples>& samples, const std::vector<double>& target,
                 const FadeFitOptions& options) {
    if (samples.empty()) throw Error("calibrate", "no distances to fit");
    if (samples.size() != target.size())
        throw Error("calibrate", "the target has " + std::to_string(target.size()) +
                                     " values for " + std::to_string(samples.size()) +
                                     " distances");
    std::vector<FastSamples> fast;
    for (const FadeSamples& s : samples) fast.push_back(prepare(s));
    auto cost = [&](double fade, double pmax) {
        double sum = 0.0;
        for (std::size_t i = 0; i < fast.size(); ++i) {
            const double r = fast_ratio(fast[i], fade, pmax, options.exponent);
            sum += (r - target[i]) * (r - target[i]);
        }
        return sum;
    };
    auto best_fade = [&](double pmax) {
        return scan_and_refine([&](double f) { return cost(f, pmax); }, kMinFade, kMaxFade, 41,
                               true);
    };

    FadeFit fit;
    if (options.fit_pmax) {
        // Pmax - 1 on a log scale: Pmax = 1 (no fading) up to 10^4.
        auto pmax_cost = [&](double excess) {
            const double pmax = 1.0 + excess;
            return cost(best_fade(pmax), pmax);
        };
        const double excess = scan_and_refine(pmax_cost, 1e-3, kMaxPmax - 1.0, 21, false);
        fit.pmax = float(1.0 + excess);
    } else {
        fit.pmax = std::max(1.0f, options.pmax);
    }
    fit.fade = float(best_fade(fit.pmax));
    if (fit.fade == 0.0f) fit.pmax = std::max(1.0f, options.pmax);  // no fading: Pmax is moot
    double sum = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        fit.model.push_back(fade_energy_ratio(samples[i], fit.fade, fit.pmax, options.exponent));
        sum += (fit.model.back() - target[i]) * (fit.model.back() - target[i]);
    }
    fit.residual = std::sqrt(sum / double(samples.size()));
    return fit;
}

std::string calibration_plot_script(const std::string& target_name, double fade, double pmax,
                                    const std::vector<double>& target,
                                    const std::vector<double>& achieved,
                                    const std::string& plot_file, const std::string& data_file) {
    double top = 1.05;  // ratios above 1 (the truth brighter than LEAN) stay in view
    for (const std::vector<double>* values : {&target, &achieved})
        for (double v : *values)
            if (std::isfinite(v)) top = std::max(top, 1.05 * v);
    std::ostringstream title;
    title << "target " << target_name << ": Fade = " << fade << ", Pmax = " << pmax;
    const std::string data = gnuplot_file(data_file);
    std::ostringstream gp;
    gp << "# gnuplot script written by leanfade calibrate\n"
       << "set terminal pngcairo size 640,420 font 'sans,10'\n"
       << "set output " << gnuplot_file(plot_file) << "\n"
       << "set logscale x 2\nset grid\nset key top right\n"
       << "set xlabel " << gnuplot_string("camera distance (bounding radii)") << "\n"
       << "set ylabel " << gnuplot_string("specular energy, fade / lean") << "\n"
       << "set yrange [0:" << top << "]\n"
       << "set title " << gnuplot_string(title.str()) << "\n"
       << "plot " << data << " using 1:2 with lines lw 2 lc rgb '#000000' title 'target', "
       << data << " using 1:4 with linespoints lw 2 pt 7 lc rgb '#2ca02c' "
       << "title 'achieved (rendered)', " << data
       << " using 1:3 with points pt 6 ps 2 lc rgb '#1f77b4' title 'model of the fit'\n";
    return gp.str();
}

}  // namespace leanfade::eval
