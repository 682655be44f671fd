#pragma once
// The plateau layer of two-lobe LEAN (docs/math.md §10): where a bump map is flat ground (or any
// region of one constant slope, tilted or not), a far pixel's slopes are a mirror spike plus the
// shoulder of the bumps, which one Gaussian of the same moments cannot follow. The layer stores,
// per texel, whether it lies on such a plateau and its slope, as values that filter linearly:
// a MIP level of the layer is the layer of the filtered map. GL-free.
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade {

// The rule (docs/math.md §10): a texel lies on a plateau when each component of its slope B
// differs by less than `epsilon` (slope units: height per texel spacing along the surface) from
// the slopes of its four neighbours and of the four texels `radius` away along both axes (the
// map repeats). Both numbers follow the map, so that the same surface gives the same plateaus at
// every resolution and bit depth:
// - radius = round(size / kPlateauReferenceTexels), at least 1, per axis: the texels compared
//   lie the same distance apart on the surface at every texture size, so a slowly curving flank
//   whose slope changes by less than epsilon per texel at 4096 texels (and by 16 epsilon over a
//   256th of the map) is not taken for flat ground;
// - epsilon = max(the setting, kPlateauQuantisationSteps x the map's quantisation step): a map
//   whose slopes come in steps (8-bit normals: one code is about 0.008, more than the default
//   0.005) keeps its flat faces, whose texels differ from their neighbours by a step of noise;
//   radius is then at least 2, where a ramp of one step per texel has moved two steps. The step
//   is the source's (source_slope_step) or the storage's (storage_slope_step), the larger.
// The default epsilon 0.005 is small against the base roughness of the shininess the maps are
// shaded with (sqrt(1/s) = 0.0085 at s = 13777): the plateau lobe's own width comes from the
// plateau texels' measured spread, so the rule only decides which texels form the spike.
inline constexpr int kPlateauReferenceTexels = 256;
inline constexpr float kPlateauQuantisationSteps = 1.5f;

// SpikeWindowShape, SpikeWindow and SpikeFit are declared in leanfade/core/lean_map.hpp.
const char* to_string(SpikeWindowShape shape);  // "none", "disc", "biweight"

// The window's weight w of a texel of slope (bx, by) (slope units), in [0, 1]; 0 for None.
inline float spike_window_weight(const SpikeWindow& window, float bx, float by) {
    if (window.shape == SpikeWindowShape::None) return 0.0f;
    const float dx = bx - window.anchor.x, dy = by - window.anchor.y;
    const float t = (dx * dx + dy * dy) / (window.radius * window.radius);
    if (!(t < 1.0f)) return 0.0f;
    if (window.shape == SpikeWindowShape::Disc) return 1.0f;
    return (1.0f - t) * (1.0f - t);
}

struct PlateauRule {
    float epsilon = kDefaultPlateauEpsilon;  // slope units, > 0
    int radius_x = 1;                        // texels, >= 1
    int radius_y = 1;
    float quantisation_step = 0.0f;  // the measured step it was made for (slope units), or 0
    SpikeWindow window;              // the central window; None (plateaus alone) unless fitted
};

const char* to_string(SpikeFit fit);  // "plateaus", "auto"
// The names parse_spike_fit takes: "auto", "plateaus".
const std::vector<std::string>& spike_fit_names();
// Throws leanfade::Error(setting, cause) for another name.
SpikeFit parse_spike_fit(const std::string& name, const std::string& setting = "spike_fit");

// What fit_spike_window measured: the window it chose and the fit of the far highlight
// (the largest |ln(two-lobe / truth)| over its probes, 0 = exact) with it and with the plateaus
// alone, and the fraction of the sampled texels on a plateau.
struct SpikeWindowFit {
    SpikeWindow window;
    float error = 0.0f;
    float plateaus_error = 0.0f;
    float plateau_fraction = 0.0f;
};

// Chooses the central window for the 2-channel slopes of a map's finest level (slope units)
// under `rule` (its plateaus), by measurement: on at most 65536 texels of a regular grid it
// compares two-lobe LEAN's lobe (lf_two_lobe_split of the shading header) with the texels' own
// lobes averaged (the supersampled truth of the map's footprint) at 14 half vectors (the mean
// slope, the densest slope, and rings within 0.05 of the mean), for the whole map and for
// footprints of a 16th of its side, at s = 128, 1024 and 13777 (Blinn-Phong's 1/s per axis), and
// keeps the candidate whose largest error |ln((two-lobe + c) / (truth + c))| is least (c: 5 % of
// the truth's largest probe): the plateaus alone; or a disc of radius 0.02-0.5, or a biweight of
// radius 0.5-2.5, of the slopes' standard deviation sqrt(tr S), around the mean or the densest
// slope, each with and without the plateaus. Deterministic for any thread count.
SpikeWindowFit fit_spike_window(const Image& slopes, const PlateauRule& rule, int threads = 0);

// The rule for a map of width x height texels, the setting `epsilon` (slope units, finite and
// > 0, else Error("plateau_epsilon", ...)) and the quantisation step of the map's slopes (slope
// units; 0 for continuous slopes).
PlateauRule plateau_rule(int width, int height, float epsilon, float quantisation_step = 0.0f);
// The slope change of one code of an integer source (slope units): 2 / unorm_max for a normal
// map (one code of a normal component where the surface is flat), |strength| / (4 unorm_max) for
// a height map (one code of a neighbour's height through the Sobel filter, docs/math.md §2);
// 0 for a float source (unorm_max <= 0).
float source_slope_step(BakeSource source, int unorm_max, float strength);
// One code of a stored slope: 2 sc / 255 (8-bit UNORM), 2 sc / 65535 (16-bit UNORM), 0 for the
// float storages.
float storage_slope_step(Storage storage, float sc);
// plateau_rule(slopes' size, epsilon): the rule for continuous slopes.
PlateauRule plateau_rule_for(const Image& slopes, float epsilon = kDefaultPlateauEpsilon);

// The plateau layer's finest level for 2-channel slopes B: RGBA = (1, Bx, By, Bx^2 + By^2) at a
// plateau texel and 0 elsewhere, so that filtered texels hold (f, f Bs, f |Bs|^2) with f the
// fraction of the footprint on a plateau and Bs its mean slope. The rule: `rule`, or
// plateau_rule_for(slopes, epsilon) (epsilon: slope units, > 0 and finite; continuous slopes).
// Throws leanfade::Error("plateau_epsilon", ...) for another epsilon, or Error("plateau", ...) for
// slopes that are not 2 channels. threads: as BakeOptions::threads.
Image plateau_texels(const Image& slopes, const PlateauRule& rule, int threads = 0);
Image plateau_texels(const Image& slopes, float epsilon = kDefaultPlateauEpsilon,
                     int threads = 0);

// plateau_texels with its MIP chain, finest first, filtered as the moments are
// (build_mip_chain), down to 1 x 1. threads: as BakeOptions::threads.
std::vector<Image> plateau_mips(const Image& slopes, const PlateauRule& rule, int threads = 0);
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
// The rule: plateau_rule(the map's size, epsilon, the larger of source_step (the source's
// quantisation, source_slope_step; 0 when unknown) and the storage's step).
// With SpikeFit::Auto the rule's window is fitted to the map's slopes (fit_spike_window).
void add_plateau_layer(PackedLeanMap& map, float epsilon = kDefaultPlateauEpsilon,
                       int threads = 0, float source_step = 0.0f,
                       SpikeFit fit = SpikeFit::Auto);
// The plateau layer of `map` from its float chain (f, f Bs, f |Bs|^2), one 4-channel image per
// level of the map's sizes, finest first, packed as add_plateau_layer packs it; sets
// map.plateau_epsilon (the epsilon the chain was made with). Throws Error("plateau", ...) for a
// chain that does not match the levels, Error("plateau_epsilon", ...) as add_plateau_layer.
void set_plateau_layer(PackedLeanMap& map, const std::vector<Image>& chain, float epsilon,
                       int threads = 0);
// The map without its plateau layer (as maps of older versions are).
void remove_plateau_layer(PackedLeanMap& map);

// The spike's share of `map` (the coarsest level's f, in [0, 1]: the fraction of its texels on a
// plateau, plus the central window's weights); 0 for a map without the layer.
float plateau_fraction(const PackedLeanMap& map);

// The stored plateau layer decoded to the renderer's floats (f, f Bs.x, f Bs.y, f |Bs|^2) (slope
// units), one image per level, finest first; texels with f = 0 decode to exactly 0 (two-lobe LEAN
// shades them as LEAN). Empty when the map has no plateau layer. Throws Error("plateau", ...) when
// the layer's byte counts do not match the levels.
std::vector<Image> unpack_plateau_layer(const PackedLeanMap& map, int threads = 0);
// One stored texel (its four channels decoded to [0, 1], or the float storages' values) as
// (f, f Bs.x, f Bs.y, f |Bs|^2) for a map of slope scale sc and encoding offset o
// (lean_offset(map.encoding): 1 for UNORM maps, 0 for signed float maps): exactly 0 where f = 0.
glm::vec4 decode_plateau_texel(glm::vec4 stored, float sc, float offset);

}  // namespace leanfade
