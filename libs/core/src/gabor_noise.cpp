#include "leanfade/core/detail/gabor_noise.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/detail/random.hpp"

namespace leanfade {
namespace {

constexpr double kPi = std::numbers::pi;
// The envelope at the kernel's radius, where it is cut: exp(-pi a^2 r^2) = kEnvelopeCut.
constexpr double kEnvelopeCut = 1e-3;
// Impulses of one field at most (each is 48 bytes): a bound on memory and time.
constexpr double kMaxImpulses = double(1 << 24);

// The noise's generator (its own stream constant keeps the fields as they were).
class Rng : public SplitMix64 {
  public:
    explicit Rng(std::uint64_t seed) : SplitMix64(seed, 0x2545F4914F6CDD1Dull) {}
};

double kernel_radius(const GaborNoiseSettings& s) {
    const double cycles = std::hypot(double(s.cycles_u), double(s.cycles_v));
    return double(s.kernel_wavelengths) * double(s.size) / cycles;
}

double impulse_count(const GaborNoiseSettings& s) {
    const double r = kernel_radius(s);
    return std::round(double(s.impulses_per_kernel) * double(s.size) * double(s.size) /
                      (kPi * r * r));
}

}  // namespace

void validate(const GaborNoiseSettings& s) {
    if (s.size < 4 || s.size > 16384)
        throw Error::setting("size", "must be in [4, 16384] texels, got " + std::to_string(s.size));
    const int half = s.size / 2;
    if (s.cycles_u == 0 && s.cycles_v == 0)
        throw Error::setting("cycles", "the wave vector is zero");
    if (std::abs(s.cycles_u) > half || std::abs(s.cycles_v) > half)
        throw Error::setting("cycles",
                             "at most " + std::to_string(half) +
                                 " cycles per period along u and v (2 texels per wavelength)");
    if (!(s.orientation_spread >= 0.0f && s.orientation_spread <= float(kPi)))
        throw Error::setting("orientation-spread", "must be in [0, pi] radians");
    if (!(s.kernel_wavelengths >= 0.5f && s.kernel_wavelengths <= 64.0f))
        throw Error::setting("kernel-wavelengths", "must be in [0.5, 64]");
    if (kernel_radius(s) > 0.5 * double(s.size))
        throw Error::setting(
            "kernel-wavelengths",
            "the kernel's radius (" + std::to_string(kernel_radius(s)) +
                " texels) exceeds half the period; use fewer wavelengths or more cycles");
    if (!(s.impulses_per_kernel > 0.0f && s.impulses_per_kernel <= 1000.0f))
        throw Error::setting("impulses-per-kernel", "must be in (0, 1000]");
    if (impulse_count(s) > kMaxImpulses)
        throw Error::setting("impulses-per-kernel", "more than 2^24 impulses in the field");
    if (!(s.slope_rms >= 0.0f && s.slope_rms <= 1e3f))
        throw Error::setting("slope-rms", "must be in [0, 1000]");
}

double gabor_bandwidth(const GaborNoiseSettings& settings) {
    return std::sqrt(-std::log(kEnvelopeCut) / kPi) / kernel_radius(settings);
}

struct GaborNoise::Impulse {
    double u, v, weight, fu, fv;
};

GaborNoise::GaborNoise(const GaborNoiseSettings& s) : settings_(s) {
    validate(s);
    const double period = double(s.size);
    radius_ = kernel_radius(s);
    const double a = gabor_bandwidth(s);
    envelope_rate_ = kPi * a * a;  // exp(-pi a^2 r^2), Lagae et al. eq. 1
    // Cells of at least the kernel's radius on the torus: a point's kernels lie in its cell and
    // the 8 around it.
    cells_ = std::max(1, int(std::floor(period / radius_)));
    cell_size_ = period / double(cells_);
    buckets_.assign(std::size_t(cells_) * std::size_t(cells_), {});
    const int count = int(std::max(1.0, impulse_count(s)));
    Rng rng(s.seed);
    const double fu = double(s.cycles_u) / period, fv = double(s.cycles_v) / period;
    const double half_spread = 0.5 * double(s.orientation_spread);
    for (int i = 0; i < count; ++i) {
        Impulse impulse{};
        impulse.u = rng.uniform(0.0, period);
        impulse.v = rng.uniform(0.0, period);
        impulse.weight = rng.uniform(-1.0, 1.0);
        // The kernel's wave vector: F rotated by its share of the orientation spread.
        const double angle = rng.uniform(-half_spread, half_spread);
        impulse.fu = fu * std::cos(angle) - fv * std::sin(angle);
        impulse.fv = fu * std::sin(angle) + fv * std::cos(angle);
        const int cu = std::min(cells_ - 1, int(impulse.u / cell_size_));
        const int cv = std::min(cells_ - 1, int(impulse.v / cell_size_));
        buckets_[std::size_t(cv) * std::size_t(cells_) + std::size_t(cu)].push_back(impulse);
    }
}

GaborNoise::~GaborNoise() = default;
GaborNoise::GaborNoise(GaborNoise&&) noexcept = default;
GaborNoise& GaborNoise::operator=(GaborNoise&&) noexcept = default;

double GaborNoise::evaluate(double u, double v) const {
    const double period = double(settings_.size);
    // The point on the torus, its cell and the distinct cells around it (fewer than 9 on a torus
    // of 1 or 2 cells).
    const double wu = u - period * std::floor(u / period);
    const double wv = v - period * std::floor(v / period);
    const int cu = std::clamp(int(wu / cell_size_), 0, cells_ - 1);
    const int cv = std::clamp(int(wv / cell_size_), 0, cells_ - 1);
    int around[9];
    int around_count = 0;
    for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
            const int index = ((cv + dv + cells_) % cells_) * cells_ + (cu + du + cells_) % cells_;
            if (std::find(around, around + around_count, index) == around + around_count)
                around[around_count++] = index;
        }
    const double radius_squared = radius_ * radius_;
    double h = 0.0;
    for (int c = 0; c < around_count; ++c)
        for (const Impulse& k : buckets_[std::size_t(around[c])]) {
            const double du = wrapped_delta(wu, k.u, period);
            const double dv = wrapped_delta(wv, k.v, period);
            const double r2 = du * du + dv * dv;
            if (r2 >= radius_squared) continue;
            // Lagae et al. eq. 1: K exp(-pi a^2 |x|^2) cos(2 pi F . x), x from the impulse.
            h += k.weight * std::exp(-envelope_rate_ * r2) *
                 std::cos(2.0 * kPi * (k.fu * du + k.fv * dv));
        }
    return h;
}

Image GaborNoise::image(int threads) const {
    const int size = settings_.size;
    Image heights(size, size, 1);
    parallel_for_rows(size, threads, [&](int first, int end) {
        for (int y = first; y < end; ++y)
            for (int x = 0; x < size; ++x)
                heights.at(x, y) =
                    float(evaluate(double(x) + 0.5, double(size) - (double(y) + 0.5)));
    });
    // Scale to the requested RMS slope (central differences on the torus).
    double sum = 0.0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double gx = 0.5 * (double(heights.at((x + 1) % size, y)) -
                                     double(heights.at((x + size - 1) % size, y)));
            const double gy = 0.5 * (double(heights.at(x, (y + 1) % size)) -
                                     double(heights.at(x, (y + size - 1) % size)));
            sum += gx * gx + gy * gy;
        }
    const double rms = std::sqrt(sum / (double(size) * double(size)));
    const double scale = rms > 0.0 ? double(settings_.slope_rms) / rms : 0.0;
    for (float& h : heights.pixels) h = float(double(h) * scale);
    return heights;
}

Image make_gabor_noise(const GaborNoiseSettings& settings, int threads) {
    return GaborNoise(settings).image(threads);
}

}  // namespace leanfade
