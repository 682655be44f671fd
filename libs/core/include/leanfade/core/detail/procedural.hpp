#pragma once
// Built-in procedural bump sets, each a tileable height map deterministic from a seed.
// Heights are in texel units (one unit = one texel spacing), so at strength 1 the slopes do not
// depend on the size: the same set baked at 256 or 4096 has the same slope statistics.
#include <cstdint>
#include <string>
#include <vector>

#include "leanfade/core/detail/gabor_noise.hpp"
#include "leanfade/core/image.hpp"

namespace leanfade {

// "bumps" (random round bumps, as the papers' figures), "ridges" (anisotropic sine ridges along
// v, LEAN Fig. 2d), "checker" (raised checker grid, LEAN Fig. 14), "noise" (fBm), "waves" (a sum
// of directional waves), "sine" (h = A sin(2 pi x / lambda) along u with 8-texel waves: the
// coherent layer of LEAN §3.5, mixed with its negation it must give "flat"), "flat" (h = 0),
// "gabor" (periodic Gabor noise of gabor_noise.hpp: waves along one direction).
const std::vector<std::string>& builtin_bump_names();

// size x size, 1 channel. Throws Error for an unknown name or a size outside [4, 16384].
Image make_builtin_height(const std::string& name, int size, std::uint32_t seed = 1);

// The Gabor noise settings of the "gabor" set at `size` texels per side.
GaborNoiseSettings builtin_gabor_settings(int size, std::uint32_t seed = 1);

// Parameters of the analytic ridge set, so tests can compare with h = A sin(2 pi x / lambda).
struct RidgeParameters {
    float amplitude;   // A, texel units
    float wavelength;  // lambda, texels (size / cycles)
};
RidgeParameters ridge_parameters(int size);
// The same for "sine" (maximum slope 0.5).
RidgeParameters sine_parameters(int size);

}  // namespace leanfade
