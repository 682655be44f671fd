#pragma once
// Periodic anisotropic Gabor noise (Lagae, Lefebvre, Drettakis and Dutré 2009, "Procedural noise
// using sparse Gabor convolution"): a height field that is a sum of Gabor kernels
//   g(x) = w_i exp(-pi a^2 |x - x_i|^2) cos(2 pi F_i . (x - x_i))
// at random impulse positions x_i with random weights w_i in [-1, 1] (the paper's eq. 1-3, sparse
// convolution). Its power spectrum is a pair of Gaussian blobs around +-F, so it looks like
// waves of one wavelength travelling along one direction: the wave layers of the ocean (LEAN
// §3.5, Fig. 1 and 11).
//
// Made periodic so that it tiles: the impulses lie on a torus of `size` x `size` texels and each
// kernel is evaluated at the wrapped (shortest) offset, so h(x + size) = h(x) exactly. The mean
// wave vector F is a whole number of cycles per period along u and v, so the spectrum's peak lies
// on the tile's frequency lattice. Each kernel's wave vector is F rotated by a random angle within
// +-spread/2 (the orientation spread of the waves).
//
// Deterministic from the seed (a portable generator; same numbers on every platform). Heights are
// in texel units (one unit = one texel spacing), like the built-in bump sets of procedural.hpp, and
// scaled so that the RMS slope of the field (central differences) is `slope_rms`.
#include <cstdint>
#include <vector>

#include "leanfade/core/image.hpp"

namespace leanfade {

struct GaborNoiseSettings {
    int size = 256;                   // texels per side = the period (4 to 16384)
    int cycles_u = 12;                // mean wave vector F, whole cycles per period along +u ...
    int cycles_v = 3;                 // ... and along +v (not both 0)
    float orientation_spread = 0.5f;  // radians, full width of the kernels' direction spread,
                                      // [0, pi]
    // Radius of a kernel (where its envelope falls to 0.1%; it is cut there) in wavelengths 1/|F|:
    // larger = longer, more regular crests, a narrower spectrum. In [0.5, 64], and the radius must
    // fit in half a period.
    float kernel_wavelengths = 2.0f;
    float impulses_per_kernel = 24.0f;  // mean impulses in a kernel's disc (> 0, <= 1000)
    float slope_rms = 0.12f;            // RMS of |grad h| of the result (>= 0, dimensionless)
    std::uint32_t seed = 1;
};

// Throws leanfade::Error(setting, cause) for settings outside the ranges above; settings are named
// "size", "cycles", "orientation-spread", "kernel-wavelengths", "impulses-per-kernel" and
// "slope-rms".
void validate(const GaborNoiseSettings& settings);

// The Gaussian width a (per texel) of the kernels of `settings`: the envelope exp(-pi a^2 r^2)
// is 0.1% at the kernel radius r = kernel_wavelengths / |F| (texels).
double gabor_bandwidth(const GaborNoiseSettings& settings);

// A field of impulses placed once from the settings (validated; throws as validate()).
class GaborNoise {
  public:
    explicit GaborNoise(const GaborNoiseSettings& settings);
    ~GaborNoise();
    GaborNoise(GaborNoise&&) noexcept;
    GaborNoise& operator=(GaborNoise&&) noexcept;

    // The unscaled sum of kernels at (u, v) in texel coordinates of the tile (u right, v up; any
    // real values: the field is periodic, evaluate(u + size, v) = evaluate(u, v + size) =
    // evaluate(u, v) up to rounding).
    double evaluate(double u, double v) const;

    // size x size, 1 channel, heights in texel units scaled to the settings' RMS slope, sampled at
    // texel centres: texel (x, y) is evaluate(x + 0.5, size - y - 0.5) times one factor (row 0
    // is the top: v = 1 - (y + 0.5) / size in uv, as for every Image). threads <= 0: all hardware
    // threads; the result does not depend on the thread count.
    Image image(int threads = 0) const;

    const GaborNoiseSettings& settings() const { return settings_; }

  private:
    // One kernel: position (texel coordinates u, v; v up), weight K in [-1, 1] and wave vector
    // (cycles per texel along u and v).
    struct Impulse;
    GaborNoiseSettings settings_;
    double radius_ = 0.0;                        // kernel radius, texels
    double envelope_rate_ = 0.0;                 // pi a^2
    int cells_ = 1;                              // cells per side of the torus
    double cell_size_ = 1.0;                     // texels
    std::vector<std::vector<Impulse>> buckets_;  // impulses by cell, row-major (v, u)
};

// GaborNoise(settings).image(threads).
Image make_gabor_noise(const GaborNoiseSettings& settings, int threads = 0);

}  // namespace leanfade
