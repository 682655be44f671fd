#pragma once
// The plateau layer of two-lobe LEAN (docs/math.md §10): where a bump map is flat ground (or any
// region of one constant slope, tilted or not), a far pixel's slopes are a mirror spike plus the
// shoulder of the bumps, which one Gaussian of the same moments cannot follow. The layer stores,
// per texel, whether it lies on such a plateau and its slope, as values that filter linearly:
// a MIP level of the layer is the layer of the filtered map. GL-free.
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade {

// A texel lies on a plateau when each component of its slope B differs from each of its four
// neighbours' (the map repeats) by less than this, in slope units (height per texel spacing
// along the surface). Small against the base roughness of the shininess the maps are shaded
// with (sqrt(1/s) = 0.0085 at s = 13777): the plateau lobe's own width comes from the plateau
// texels' measured spread, so the threshold only decides which texels form the spike.
inline constexpr float kDefaultPlateauEpsilon = 0.005f;

// The plateau layer's finest level for 2-channel slopes B: RGBA = (1, Bx, By, Bx^2 + By^2) at a
// plateau texel and 0 elsewhere, so that filtered texels hold (f, f Bs, f |Bs|^2) with f the
// fraction of the footprint on a plateau and Bs its mean slope. epsilon: slope units, > 0 and
// finite. Throws leanfade::Error("plateau_epsilon", ...) for another epsilon, or
// Error("plateau", ...) for slopes that are not 2 channels. threads: as BakeOptions::threads.
Image plateau_texels(const Image& slopes, float epsilon = kDefaultPlateauEpsilon,
                     int threads = 0);

// plateau_texels with its MIP chain, finest first, filtered as the moments are
// (build_mip_chain), down to 1 x 1. threads: as BakeOptions::threads.
std::vector<Image> plateau_mips(const Image& slopes, float epsilon = kDefaultPlateauEpsilon,
                                int threads = 0);

// The 2-channel slopes B of a packed LEAN map's finest level, in slope units. threads: as
// BakeOptions::threads.
Image packed_top_slopes(const PackedLeanMap& map, int threads = 0);

}  // namespace leanfade
