#include "leanfade/core/detail/procedural.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/gabor_noise.hpp"
#include "leanfade/core/detail/random.hpp"

namespace leanfade {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The bump sets' generator (its own stream constant keeps the sets as they were).
class Rng : public SplitMix64 {
public:
    explicit Rng(std::uint64_t seed) : SplitMix64(seed, 0x632BE59BD9B4E019ull) {}
};

Image make_bumps(int size, Rng& rng) {
    // Round bumps with a C1 profile H (1 - (r/R)^2)^2, placed at random, tileable.
    Image img(size, size, 1);
    struct Bump { double x, y, radius, height; };
    std::vector<Bump> bumps;
    const int count = 48;
    for (int i = 0; i < count; ++i) {
        const double radius = size * rng.uniform(0.035, 0.075);
        bumps.push_back({rng.uniform(0, size), rng.uniform(0, size), radius,
                         radius * rng.uniform(0.25, 0.45)});
    }
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            double h = 0.0;
            for (const Bump& b : bumps) {
                const double dx = wrapped_delta(x + 0.5, b.x, size);
                const double dy = wrapped_delta(y + 0.5, b.y, size);
                const double q = (dx * dx + dy * dy) / (b.radius * b.radius);
                if (q < 1.0) h += b.height * (1.0 - q) * (1.0 - q);
            }
            img.at(x, y) = float(h);
        }
    }
    return img;
}

// h = A sin(2 pi x / lambda): waves along u, constant along v.
Image make_waves_along_u(int size, const RidgeParameters& r) {
    Image img(size, size, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            img.at(x, y) = float(r.amplitude * std::sin(kTwoPi * x / r.wavelength));
    return img;
}

Image make_checker(int size) {
    // Raised checker grid: smooth square waves in x and y multiplied; 8 cells per side.
    const double cell = size / 8.0;
    const double height = cell / 6.0;
    const double sharpness = 3.0;
    Image img(size, size, 1);
    auto square = [&](double t) {
        return std::clamp(sharpness * std::sin(std::numbers::pi * t / cell), -1.0, 1.0);
    };
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            img.at(x, y) = float(0.5 * height * (1.0 + square(x + 0.5) * square(y + 0.5)));
    return img;
}

// Tileable value-gradient noise on a lattice of `period` cells.
class PeriodicNoise {
public:
  PeriodicNoise(int period, Rng& rng) : period_(period), gradients_(std::size_t(period * period)) {
      for (auto& g : gradients_) {
          const double a = rng.uniform(0, kTwoPi);
          g = {std::cos(a), std::sin(a)};
      }
  }
    // x, y in lattice cells; result roughly in [-0.7, 0.7].
    double operator()(double x, double y) const {
        const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
        const double fx = x - x0, fy = y - y0;
        auto dot_grad = [&](int ix, int iy, double dx, double dy) {
            const auto& g = gradients_[std::size_t(wrap(iy) * period_ + wrap(ix))];
            return g[0] * dx + g[1] * dy;
        };
        auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
        const double u = fade(fx), v = fade(fy);
        const double a = dot_grad(x0, y0, fx, fy), b = dot_grad(x0 + 1, y0, fx - 1, fy);
        const double c = dot_grad(x0, y0 + 1, fx, fy - 1),
                     d = dot_grad(x0 + 1, y0 + 1, fx - 1, fy - 1);
        return (a + (b - a) * u) + ((c + (d - c) * u) - (a + (b - a) * u)) * v;
    }

private:
    int wrap(int i) const { return ((i % period_) + period_) % period_; }
    int period_;
    std::vector<std::array<double, 2>> gradients_;
};

Image make_noise(int size, Rng& rng) {
    // fBm: 5 octaves from 4 cells per side, amplitude proportional to the wavelength so that every
    // octave contributes a similar slope.
    Image img(size, size, 1);
    std::vector<PeriodicNoise> octaves;
    int cells = 4;
    for (int o = 0; o < 5 && cells <= size / 2; ++o, cells *= 2) octaves.emplace_back(cells, rng);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            double h = 0.0;
            int c = 4;
            for (const auto& n : octaves) {
                const double wavelength = double(size) / c;
                h += 0.12 * wavelength * n((x + 0.5) / wavelength, (y + 0.5) / wavelength);
                c *= 2;
            }
            img.at(x, y) = float(h);
        }
    }
    return img;
}

Image make_waves(int size, Rng& rng) {
    // Directional waves around one wind direction; integer wave vectors keep it tileable.
    struct Wave { int kx, ky; double amplitude, phase; };
    std::vector<Wave> waves;
    const double wind = rng.uniform(0, kTwoPi);
    for (int i = 0; i < 12; ++i) {
        const double angle = wind + rng.uniform(-0.6, 0.6);
        const double cycles = rng.uniform(3, 24);
        const int kx = int(std::lround(cycles * std::cos(angle)));
        const int ky = int(std::lround(cycles * std::sin(angle)));
        if (kx == 0 && ky == 0) continue;
        const double wavelength = size / std::hypot(double(kx), double(ky));
        waves.push_back({kx, ky, 0.025 * wavelength, rng.uniform(0, kTwoPi)});
    }
    Image img(size, size, 1);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            double h = 0.0;
            for (const Wave& w : waves)
                h += w.amplitude * std::sin(kTwoPi * (w.kx * x + w.ky * y) / size + w.phase);
            img.at(x, y) = float(h);
        }
    }
    return img;
}

}  // namespace

const std::vector<std::string>& builtin_bump_names() {
    static const std::vector<std::string> names = {"bumps", "ridges", "checker", "noise",
                                                   "waves", "sine",   "flat",    "gabor"};
    return names;
}

RidgeParameters ridge_parameters(int size) {
    const float wavelength = float(size) / std::max(1, std::min(16, size / 8));
    // Maximum slope A * 2 pi / lambda = 0.5.
    return {0.5f * wavelength / float(kTwoPi), wavelength};
}

RidgeParameters sine_parameters(int size) {
    // 8-texel waves (4 at the smallest size): fine enough that the MIP levels from the third on
    // average a whole period, so that their variance is all the sine has.
    const float wavelength = size >= 16 ? 8.0f : 4.0f;
    return {0.5f * wavelength / float(kTwoPi), wavelength};
}

GaborNoiseSettings builtin_gabor_settings(int size, std::uint32_t seed) {
    // 12 x 3 cycles per tile (fewer on small tiles, at least 8 texels per wavelength), kernels of
    // 2 wavelengths (1/2 wavelength at the smallest), RMS slope 0.12.
    GaborNoiseSettings s;
    s.size = size;
    const int cycles = std::max(1, std::min(12, size / 8));
    s.cycles_u = cycles;
    s.cycles_v = cycles / 4;
    s.kernel_wavelengths = std::clamp(0.5f * float(cycles), 0.5f, 2.0f);
    s.seed = seed;
    return s;
}

Image make_builtin_height(const std::string& name, int size, std::uint32_t seed) {
    if (size < 4 || size > kDefaultMaxImageDimension)
        throw Error::setting("builtin", "'" + name + "': size " + std::to_string(size) +
                                            " outside [4, " +
                                            std::to_string(kDefaultMaxImageDimension) + "]");
    Rng rng(seed);
    if (name == "bumps") return make_bumps(size, rng);
    if (name == "ridges") return make_waves_along_u(size, ridge_parameters(size));
    if (name == "checker") return make_checker(size);
    if (name == "noise") return make_noise(size, rng);
    if (name == "waves") return make_waves(size, rng);
    if (name == "sine") return make_waves_along_u(size, sine_parameters(size));
    if (name == "flat") return Image(size, size, 1);
    if (name == "gabor") return make_gabor_noise(builtin_gabor_settings(size, seed));
    std::string valid;
    for (const auto& n : builtin_bump_names()) valid += (valid.empty() ? "" : ", ") + n;
    throw Error::setting("builtin", "unknown bump set '" + name + "' (valid: " + valid + ")");
}

}  // namespace leanfade
