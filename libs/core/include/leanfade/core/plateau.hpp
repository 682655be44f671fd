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

// The rule (kDefaultPlateauEpsilon, lean_map.hpp): a texel lies on a plateau when each
// component of its slope B differs from each of its four neighbours' (the map repeats) by less
// than epsilon, in slope units (height per texel spacing along the surface). The default 0.005
// is small against the base roughness of the shininess the maps are shaded with (sqrt(1/s) =
// 0.0085 at s = 13777): the plateau lobe's own width comes from the plateau texels' measured
// spread, so the threshold only decides which texels form the spike.

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

// The plateau layer stored in a packed LEAN map (PackedLevel::plateau, docs/ktx2.md): every level
// of plateau_mips(packed_top_slopes(map), epsilon) in the map's storage, per texel
//   (f, 0.5 f Bs.x / sc + 0.5, 0.5 f Bs.y / sc + 0.5, 0.5 f |Bs|^2 / sc^2),
// UNORM codes rounded as the moments are (lean_map_internal.hpp). Each channel is affine in the
// filtered quantities, so a trilinear fetch of the stored layer decodes to the layer of the
// filtered map. Replaces any layer the map had and sets map.plateau_epsilon. epsilon: slope
// units, finite and > 0 (else Error("plateau_epsilon", ...)). The packed bakes
// (BakeOptions::plateau_epsilon) write exactly these bytes.
void add_plateau_layer(PackedLeanMap& map, float epsilon = kDefaultPlateauEpsilon,
                       int threads = 0);
// The plateau layer of `map` from its float chain (f, f Bs, f |Bs|^2), one 4-channel image per
// level of the map's sizes, finest first, packed as add_plateau_layer packs it; sets
// map.plateau_epsilon (the epsilon the chain was made with). Throws Error("plateau", ...) for a
// chain that does not match the levels, Error("plateau_epsilon", ...) as add_plateau_layer.
void set_plateau_layer(PackedLeanMap& map, const std::vector<Image>& chain, float epsilon,
                       int threads = 0);
// The map without its plateau layer (as maps of older versions are).
void remove_plateau_layer(PackedLeanMap& map);

// The stored plateau layer decoded to the renderer's floats (f, f Bs.x, f Bs.y, f |Bs|^2) (slope
// units), one image per level, finest first; texels with f = 0 decode to exactly 0 (two-lobe LEAN
// shades them as LEAN). Empty when the map has no plateau layer. Throws Error("plateau", ...) when
// the layer's byte counts do not match the levels.
std::vector<Image> unpack_plateau_layer(const PackedLeanMap& map, int threads = 0);
// One stored texel (its four channels decoded to [0, 1], or the float storages' values) as
// (f, f Bs.x, f Bs.y, f |Bs|^2) for a map of slope scale sc: exactly 0 where f = 0.
glm::vec4 decode_plateau_texel(glm::vec4 stored, float sc);

}  // namespace leanfade
