#pragma once
// LEAN maps (Olano & Baker 2010; docs/math.md §2-3): the float moments of a bump map with their
// MIP chain, and their packing into the two RGBA textures lean1 / lean2.
//
// All vectors are in tangent space: x along +u, y along +v (OpenGL normal-map convention), z out
// of the surface. Slopes B are projected normals n.xy / n.z (dimensionless). Image rows are stored
// top row first (as in image files); the GL upload flips them so that +v points up.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "leanfade/core/image.hpp"

namespace leanfade {

enum class Wrap { Repeat, Clamp };
enum class NormalConvention { OpenGL, DirectX };  // DirectX: green is -v, flipped on read
enum class Storage { Unorm8, Unorm16, Float16, Float32 };

const char* to_string(Wrap);
// "repeat", "clamp" with their values: the border handling's choices as settings name them.
const std::vector<std::pair<std::string, Wrap>>& wrap_names();
const char* to_string(NormalConvention);
const char* to_string(Storage);  // "8", "16", "16f", "32f": the bits of a channel
// Every storage's name, in enum order.
const std::vector<std::string>& storage_names();
// Throws leanfade::Error(setting, cause) for a name that is not a storage's.
Storage parse_storage(std::string_view name, const std::string& setting = "bits");
// The storage choices of a bake: storage_names() and "auto" (16-bit UNORM, baked again as half
// float by the caller for a map with texels beyond sc: docs/ktx2.md, "Choosing storage and sc").
const std::vector<std::string>& bake_storage_names();
// The storage a bake starts with: Unorm16 for "auto", else parse_storage's. Throws
// leanfade::Error(setting, "expected 8, 16, 16f, 32f or auto, got ...").
Storage parse_bake_storage(std::string_view name, const std::string& setting = "bits");
int bytes_per_texel(Storage);  // one RGBA texel of one slice (lean1 or lean2)

// How the signed quantities of a LEAN map (n, B, Mxy; the plateau layer's f Bs) are stored
// (docs/math.md §3, docs/ktx2.md): a stored value s decodes to v = (1 + o) s - o with o the
// encoding's offset (lean_offset).
// - Offset (o = 1): s = 0.5 v + 0.5, so that [-1, 1] fits UNORM's [0, 1]. Every UNORM map, and
//   the float maps of leanfade 0.1 (KTX2 layout "... v1").
// - Signed (o = 0): s = v, what float storages write from 0.2 on (layout "... v2"). Half floats
//   then keep 11 significant bits of small B and M, where the offset left them 11 bits of the
//   whole range (B to sc / 2^11 absolute, worse than 16-bit UNORM's sc / 65535).
enum class LeanEncoding { Offset, Signed };
const char* to_string(LeanEncoding);  // "offset", "signed"
// What a bake writes in `storage`: Signed for the float storages, Offset for UNORM.
LeanEncoding default_encoding(Storage storage);
// The o of v = (1 + o) s - o (1 for Offset, 0 for Signed): what lf_unpack takes.
float lean_offset(LeanEncoding encoding);
// The sc a Signed map of `storage` is stored with, from the top level's max |Bx|, |By| and max
// Mxx, Myy: 1 for Float32; for Float16 the smallest power of two >= 1 with max M / sc^2 <=
// 2^15 (below the half range's 65504: slopes up to 181 store with sc = 1). Powers of two divide
// exactly, and small values keep half's normal range (down to 6.1e-5, a base variance 1/s of
// s = 16384) instead of becoming subnormal, as they would divided by a large sc.
float signed_encoding_scale(Storage storage, double max_b, double max_m);

// The imperfect texels of a normal map that a bake repairs (docs/math.md §2) unless
// BakeOptions::strict_normals: texels encoded (0, 0, 0), the padding of image editors and bakers
// outside the UV islands, are taken as flat (0, 0, 1); texels with z <= -kNormalZRejectEpsilon
// (authored slightly below the surface, or a channel shifted) are raised to kMinNormalZ as the
// bake raises z near 0.
struct NormalRepairs {
    std::uint64_t padding_texels = 0;  // (0, 0, 0) taken as flat
    std::uint64_t raised_texels = 0;   // z <= -kNormalZRejectEpsilon raised
    bool any() const { return padding_texels > 0 || raised_texels > 0; }
};

// One MIP level of float moments. Index i = y * width + x, rows top first.
struct MomentLevel {
    int width = 0;
    int height = 0;
    std::vector<glm::vec3> normal;  // filtered normal, NOT renormalised (length < 1 = bumpier)
    std::vector<glm::vec2> mean;    // B = E[b~]
    std::vector<glm::vec3> second;  // M = (E[Bx^2], E[By^2], E[Bx*By]), plus 1/s on xx, yy if baked
};

struct LeanMap {
    std::vector<MomentLevel> levels;  // 0 = finest, last = 1x1
    float scale = 1.0f;  // sc of docs/math.md §3: |Bx|,|By| <= sc and Mxx,Myy <= sc^2, except:
    // the outliers, top-level texels at least twice as steep as the 99.9th percentile, left
    // beyond sc (docs/ktx2.md, "Choosing storage and sc"): UNORM storages clamp their packed
    // values to [0, 1], float storages keep them.
    std::uint64_t texels_beyond_scale = 0;
    bool roughness_baked = false;     // 1/s added to Mxx, Myy at bake time (LEAN eq. 6)
    float baked_shininess = 0.0f;     // s when roughness_baked
    NormalConvention source_convention = NormalConvention::OpenGL;
    NormalRepairs normal_repairs;     // what the bake repaired in its normal map
};

// The layers of a packed LEAN map, described once: each a slice of RGBA texels of the map's
// storage and size at every level, in this order in the containers (the KTX2 file's array layers,
// the PNG files NAME.<name>.png), the renderer's texture arrays and the GPU generation. The
// optional ones are present when the map has them (PackedLeanMap::has_layer).
enum class LeanLayer { Lean1, Lean2, Plateau };
inline constexpr std::size_t kLeanLayerCount = 3;
struct LeanLayerInfo {
    LeanLayer layer;
    std::string_view name;   // "lean1": in file names (NAME.lean1.png) and messages
    std::string_view label;  // for people: "the plateau layer"
    bool optional;           // absent from maps without it (two-lobe LEAN's plateau layer)
    std::string_view holds;  // what a texel holds (Offset encoding; Signed without 0.5 offsets)
};
inline constexpr std::array<LeanLayerInfo, kLeanLayerCount> kLeanLayers{{
    {LeanLayer::Lean1, "lean1", "lean1", false, "(0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5)"},
    {LeanLayer::Lean2, "lean2", "lean2", false, "(0.5 B / sc + 0.5, Mxx / sc^2, Myy / sc^2)"},
    {LeanLayer::Plateau, "plateau", "the plateau layer", true,
     "(f, 0.5 f Bs / sc + 0.5, 0.5 f |Bs|^2 / sc^2): two-lobe LEAN's spike (docs/math.md §10)"},
}};
constexpr const LeanLayerInfo& info(LeanLayer layer) { return kLeanLayers[std::size_t(layer)]; }
constexpr bool lean_layer_table_is_ordered() {
    for (std::size_t i = 0; i < kLeanLayers.size(); ++i) {
        if (std::size_t(kLeanLayers[i].layer) != i) return false;
        // The optional layers come last: a map's layers are always a prefix of the table.
        if (i > 0 && kLeanLayers[i - 1].optional && !kLeanLayers[i].optional) return false;
    }
    return true;
}
static_assert(lean_layer_table_is_ordered());

// One packed MIP level: the layers' slices (lean1, lean2 and, where the map has it, the plateau
// layer) of RGBA texels in the storage format, rows top first, tightly packed
// (width * bytes_per_texel(storage) bytes per row). Float16/Float32 are IEEE little-endian;
// Unorm16 is little-endian.
struct PackedLevel {
    int width = 0;
    int height = 0;
    // Encoding Offset (LeanEncoding):
    std::vector<std::uint8_t> lean1;  // (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5)
    std::vector<std::uint8_t> lean2;  // (0.5 B / sc + 0.5, Mxx / sc^2, Myy / sc^2)
    // Encoding Signed: lean1 = (n, Mxy / sc^2), lean2 = (B / sc, Mxx / sc^2, Myy / sc^2).
    // Two-lobe LEAN's plateau layer (docs/math.md §10), empty when the map has none
    // (PackedLeanMapMetadata::plateau_epsilon = 0): the same storage and size as lean1, holding
    // (f, 0.5 f Bs / sc + 0.5, 0.5 f |Bs|^2 / sc^2) (Offset) or (f, f Bs / sc, f |Bs|^2 / sc^2)
    // (Signed) with f the fraction of the texel's footprint on a plateau and Bs its slope; every
    // channel affine in (f, f Bs, f |Bs|^2), so filtering the stored values filters the layer
    // (leanfade/core/detail/plateau.hpp).
    std::vector<std::uint8_t> plateau;

    // The slice of `layer` (kLeanLayers).
    std::vector<std::uint8_t>& slice(LeanLayer layer) {
        return layer == LeanLayer::Lean1 ? lean1 : layer == LeanLayer::Lean2 ? lean2 : plateau;
    }
    const std::vector<std::uint8_t>& slice(LeanLayer layer) const {
        return const_cast<PackedLevel*>(this)->slice(layer);
    }
};

// The plateau rule's threshold a bake uses unless told otherwise (leanfade/core/detail/plateau.hpp): a
// texel is on a plateau when its slope differs from each of its four neighbours' by less than this
// per component, in slope units.
inline constexpr float kDefaultPlateauEpsilon = 0.005f;

// The spike of maps without flat ground (docs/math.md §10, "The central window"): the slopes of
// natural ground, rock or worn bricks are peakier at their centre than a Gaussian of the same
// covariance, which costs LEAN 20-90 % of a far highlight. Two-lobe LEAN's spike then takes the
// texels whose slope lies near the map's mean or densest slope (`anchor`), with a weight w in
// [0, 1] per texel:
//   Disc      w = 1 where |B - anchor| < radius, 0 elsewhere;
//   Biweight  w = (1 - |B - anchor|^2 / radius^2)^2 where positive, 0 elsewhere;
// and a plateau texel has w = 1 when with_plateaus. The layer stores w (1, B, |B|^2), linear as
// before, so the shaders and files do not change. None: the plateau rule alone.
enum class SpikeWindowShape { None, Disc, Biweight };
struct SpikeWindow {
    SpikeWindowShape shape = SpikeWindowShape::None;
    glm::vec2 anchor{0.0f};     // slope units: the map's mean or densest slope
    float radius = 0.0f;        // slope units, > 0 unless None
    bool with_plateaus = true;  // plateau texels (PlateauRule) join the spike with w = 1
};
// How a bake chooses the spike's texels (BakeOptions::spike_fit).
enum class SpikeFit {
    Plateaus,  // the plateau rule alone (leanfade 0.2 and earlier)
    Auto,      // the rule's plateaus and/or the central window that fit the map best
};

// What a packed LEAN map records besides its levels: the storage, sc and how it was baked (what
// a KTX2 file keeps in its key/value data, docs/ktx2.md).
struct PackedLeanMapMetadata {
    Storage storage = Storage::Unorm16;
    // Offset for UNORM storages; Signed or (files of leanfade 0.1) Offset for float storages.
    LeanEncoding encoding = LeanEncoding::Offset;
    float scale = 1.0f;
    bool roughness_baked = false;
    float baked_shininess = 0.0f;
    NormalConvention source_convention = NormalConvention::OpenGL;
    NormalRepairs normal_repairs;  // as LeanMap::normal_repairs
    // The source normal map fits the other convention clearly better
    // (NormalConventionCheck::looks_flipped), as noted by a bake that checked it.
    bool source_looks_flipped = false;
    std::string generator;  // e.g. "leanfade 0.1.0"
    // The plateau rule's epsilon (slope units) the map's plateau layer was made with, or 0 when
    // the map has no plateau layer (maps of older versions: two-lobe LEAN shades them with f = 0,
    // as LEAN).
    float plateau_epsilon = 0.0f;
    bool has_plateau() const { return plateau_epsilon > 0.0f; }
    // Whether the map has `layer` (every one that is not optional; the plateau layer with
    // has_plateau()), and how many layers it has: the first layer_count() rows of kLeanLayers.
    bool has_layer(LeanLayer layer) const {
        return !info(layer).optional || (layer == LeanLayer::Plateau && has_plateau());
    }
    int layer_count() const {
        int count = 0;
        for (const LeanLayerInfo& row : kLeanLayers) count += has_layer(row.layer) ? 1 : 0;
        return count;
    }
};

// The metadata's fields are the map's own (map.scale, map.storage, ...); metadata() is all of
// them as one value.
struct PackedLeanMap : PackedLeanMapMetadata {
    std::vector<PackedLevel> levels;

    PackedLeanMapMetadata& metadata() { return *this; }
    const PackedLeanMapMetadata& metadata() const { return *this; }
};

// Unit of BakeOptions::strength (docs/math.md §2).
enum class StrengthUnit {
    Texel,  // height per texel spacing: the same heights give half the slopes at twice the size
    Uv,     // height per UV unit (the map's width along u, its height along v): the same slopes
            // at any resolution of the same map
};
// "texel", "uv" with their values.
const std::vector<std::pair<std::string, StrengthUnit>>& strength_unit_names();
const char* to_string(StrengthUnit unit);

struct BakeOptions {
    float strength = 1.0f;  // height of one unit of value in strength_unit (height maps only);
                            // negative inverts the heights
    StrengthUnit strength_unit = StrengthUnit::Texel;
    // sc (docs/ktx2.md, "Choosing storage and sc"): false = the steepest slope of the map, so no
    // texel is beyond it; true = outliers (at least twice as steep as the 99.9th percentile)
    // lie beyond sc, for the precision of all others (LeanMap::texels_beyond_scale).
    bool scale_excludes_outliers = true;
    Wrap wrap = Wrap::Repeat;
    NormalConvention convention = NormalConvention::OpenGL;  // normal maps only
    float bake_roughness_shininess = 0.0f;                   // s > 0: bake 1/s into M (eq. 6)
    int threads = 0;                                         // 0 = hardware concurrency
    // Normal maps: refuse texels with z <= -kNormalZRejectEpsilon, (0, 0, 0) padding included,
    // instead of repairing them (NormalRepairs).
    bool strict_normals = false;
    // The packed bakes (bake_packed*) add the plateau layer of two-lobe LEAN with this epsilon
    // (slope units, finite, >= 0; 0 = no layer). The float LeanMap has no such layer.
    float plateau_epsilon = kDefaultPlateauEpsilon;
    // Which texels form two-lobe LEAN's spike (leanfade/core/detail/plateau.hpp, fit_spike_window).
    SpikeFit spike_fit = SpikeFit::Auto;
    // The largest code of the source's integer samples when a bake is given them as floats
    // (255 for 8 bits, 65535 for 16; 0: a bake of integer samples knows their own, float
    // samples have none). The plateau rule takes one code's slope as the map's quantisation
    // step (leanfade/core/detail/plateau.hpp).
    int source_max_code = 0;
};

// Normals with z below this (after decoding 2*rgb-1) are raised to it, and counted; normals with
// z <= -kNormalZRejectEpsilon are rejected as not being a tangent-space normal map. The epsilon is
// one 8-bit quantisation step of the encoding, so a z of 0 written to 8 bits is accepted.
inline constexpr float kMinNormalZ = 1.0f / 64.0f;
inline constexpr float kNormalZRejectEpsilon = 2.0f / 255.0f;

// Largest accepted slope component |Bx|, |By| (a surface at 89.99994 degrees). Steeper slopes
// come only from absurd data (height steps of millions of texel spacings times the strength,
// normal map components far outside [0, 1]); past about 1e19 the second moments B^2 overflow
// the float range and the map becomes NaN, so they are refused, naming the first such texel.
inline constexpr float kMaxSlope = 1.0e6f;
// Largest sc a bake writes: kMaxSlope, or sqrt(kMaxSlope^2 + 1/s) with roughness baked at the
// smallest shininess (1e-3), rounded up to a float (1000000.0625). The readers of LEAN maps
// (KTX2, PNG pairs) refuse a larger sc: no bake wrote it, and its squares leave the range the
// shading computes in.
inline constexpr float kMaxLeanScale = 1.000001e6f;

struct SlopeResult {
    Image slopes;                     // 2 channels: B~ (tangent space)
    std::size_t clamped_texels = 0;   // normal maps: texels whose z was raised to kMinNormalZ
};

// Height map (first channel used; values in height units where one unit = one texel spacing at
// strength 1) -> projected slopes with the 3x3 Sobel filter / 8 (docs/math.md §2). Throws on
// NaN/Inf and on a slope steeper than kMaxSlope.
SlopeResult slopes_from_height(const Image& height, const BakeOptions& options,
                               const std::string& source_name = "");
// Normal map (>= 3 channels, encoded 0.5 n + 0.5 in [0,1]) -> B = n.xy / n.z (docs/math.md §2).
// Throws on NaN/Inf, z <= -kNormalZRejectEpsilon and a slope steeper than kMaxSlope (the bakes
// below repair such texels first unless BakeOptions::strict_normals: repair_normal_map).
SlopeResult slopes_from_normals(const Image& normals, const BakeOptions& options,
                                const std::string& source_name = "");

// The texels of a normal map (>= 3 channels, encoded 0.5 n + 0.5) that repair_normal_map changes.
NormalRepairs count_normal_repairs(const Image& normals);
NormalRepairs count_normal_repairs(const UnormImage& normals);
// `normals` with its (0, 0, 0) texels set to the flat (0.5, 0.5, 1) and the z of texels with z <=
// -kNormalZRejectEpsilon set to 0 (encoded 0.5; the bake raises it to kMinNormalZ). NaN and Inf
// are left for the bake to refuse. Other channels (alpha) are kept.
Image repair_normal_map(const Image& normals);

// Top level moments from slopes, then the full MIP chain (area-weighted linear filter, exact for
// odd sizes: every level's mean equals the top level's mean up to float rounding; the 2x2 box of
// even sizes sums in float, the 3-tap filters of odd sizes in double), then sc. Throws when a
// slope is not finite or steeper than kMaxSlope.
LeanMap build_lean_map(const Image& slopes, const BakeOptions& options);

// The MIP chain of any linear 4-channel quantity (level 0 = `top`), filtered exactly as
// build_lean_map filters the moments, so that sums of such chains and of moments commute with
// filtering (the cross-term textures of bump layers, leanfade/core/detail/layers.hpp). `threads` as
// BakeOptions::threads.
std::vector<Image> build_mip_chain(const Image& top, int threads = 0);

// Whole bake from a decoded image: slopes (height or normal map) then build_lean_map.
// Auto: 1-2 channels are a height map (first channel), 3-4 channels a normal map, except a grey
// image (r = g = b at every texel: a height map saved as RGB, RGBA or palette), a height map.
enum class BakeSource { Auto, Height, Normal };
const char* to_string(BakeSource source);  // "auto", "height", "normal"
// Every source's name, in enum order.
const std::vector<std::string>& bake_source_names();
// Throws leanfade::Error(setting, cause) for a name that is not a source's.
BakeSource parse_bake_source(std::string_view name, const std::string& setting = "from");
// What `requested` means for this image: Height or Normal as given, Auto resolved as above.
BakeSource resolve_bake_source(BakeSource requested, const Image& input);
BakeSource resolve_bake_source(BakeSource requested, const UnormImage& input);
// True for an image of 3 or 4 channels whose first three are equal at every texel.
bool is_grey_colour_image(const Image& image);
bool is_grey_colour_image(const UnormImage& image);
struct BakeResult {
    LeanMap map;
    BakeSource source = BakeSource::Height;  // what the input was taken as
    std::size_t clamped_texels = 0;          // normal maps: z raised to kMinNormalZ
    // map.texels_beyond_scale: top-level texels steeper than sc (clamped by UNORM packing).
};
BakeResult bake_lean_map(const Image& input, BakeSource source, const BakeOptions& options,
                         const std::string& source_name = "");

// Whether a normal map reads as a height field in `convention` or in the other one. The slopes B
// of a height field are a gradient, so their curl dBx/dv - dBy/du is 0 (up to quantisation and
// the z clamp); read with the wrong green sign it becomes dBx/dv + dBy/du, which is not. Both
// are mean squares (slope per texel, squared) over every step-th texel (at most
// max_samples_per_side per side, wrapping at the edges).
struct NormalConventionCheck {
    double curl_as_read = 0.0;  // mean squared curl of the slopes read in `convention`
    double curl_flipped = 0.0;  // the same with green flipped (the other convention)
    std::size_t samples = 0;
    // The other convention fits clearly better (4 times less curl) and the map varies along
    // both axes: a reliable cue to warn about (maps of 1-D ridges never trigger it).
    bool looks_flipped() const;
};
NormalConventionCheck check_normal_convention(const Image& normals, NormalConvention convention,
                                              int max_samples_per_side = 512);

// MIP chain sizes: floor halving down to 1x1, as OpenGL does.
int mip_level_count(int width, int height);

// Pack (docs/math.md §3) each level separately from the floats, quantising to the storage in its
// default_encoding: UNORM codes are round-to-nearest (ties to even) of one multiply-add per
// channel, clamped to [0, 2^bits - 1] (lean_map_internal.hpp, unorm_texel); float storages keep
// B / sc etc. (Signed, sc = signed_encoding_scale of the top level), half floats rounded to
// nearest, ties to even.
PackedLeanMap pack_lean_map(const LeanMap& map, Storage storage, const std::string& generator);
// The same in `encoding`: Offset in any storage (a float map as leanfade 0.1 wrote it, sc =
// map.scale), Signed in the float storages; throws Error("bits", ...) for Signed UNORM.
PackedLeanMap pack_lean_map(const LeanMap& map, Storage storage, LeanEncoding encoding,
                            const std::string& generator);
// Inverse of pack_lean_map within the storage's quantisation.
LeanMap unpack_lean_map(const PackedLeanMap& packed);

// Decoded RGBA floats of one packed texel of one slice, 0 = lean1, 1 = lean2, 2 = the plateau
// layer's stored values (for tests and the CPU reference).
glm::vec4 fetch_packed_texel(const PackedLeanMap& map, int level, int slice, int x, int y);

// Statistics for the bake summary. Slopes are dimensionless; covariance in slope^2.
struct LeanMapSummary {
    int width = 0, height = 0, levels = 0;
    float scale = 0.0f;
    float mean_slope = 0.0f;  // mean |B| over the top level
    float max_slope = 0.0f;   // max |B| over the top level
    glm::vec3 coarsest_covariance{0.0f};  // (Sxx, Syy, Sxy) of the 1x1 level, M - B B^T
    float coarsest_anisotropy = 1.0f;     // sqrt(lambda_max / lambda_min) of that covariance
    // Two-lobe LEAN's plateau layer (leanfade/core/detail/plateau.hpp), where the bake made one: the
    // fraction of the texels on a plateau, and the rule's epsilon (slope units) and radius
    // (texels, per axis) as the map's size and quantisation set them. 0 without a layer.
    // plateau_fraction is the spike's share (the coarsest level's f: the plateaus plus the
    // central window's weights); flat_fraction the share of the texels on a plateau (measured
    // on the fit's grid when a window was fitted); spike_window the window (None: the plateaus
    // alone), spike_fit_error and plateaus_fit_error the fit's largest |ln(two-lobe / truth)|
    // with it and with the plateaus alone (0 when not fitted).
    float plateau_fraction = 0.0f;
    float plateau_rule_epsilon = 0.0f;
    int plateau_radius_x = 0, plateau_radius_y = 0;
    float flat_fraction = 0.0f;
    SpikeWindow spike_window;
    float spike_fit_error = 0.0f, plateaus_fit_error = 0.0f;
};
LeanMapSummary summarize(const LeanMap& map);

// Texels [x, x + count) of row y of one level of the fused bake's float moments (slopes, tangent
// space, dimensionless): exactly bake_lean_map's MomentLevel values there, bit for bit. Each
// pointer holds `count` floats, valid during the call only.
struct MomentRun {
    int level = 0, y = 0, x = 0, count = 0;
    const float* bx = nullptr;  // B = E[(Bx, By)]
    const float* by = nullptr;
    const float* mxx = nullptr;  // M = E[(Bx Bx, By By, Bx By)]
    const float* myy = nullptr;
    const float* mxy = nullptr;
};
// Sees every texel of every level once, in runs, from the bake's threads (runs of different rows
// at the same time, in no fixed order): what computes the engine textures in the same pass
// (RoughnessTextureBuilder, leanfade/core/roughness.hpp).
using MomentRunSink = std::function<void(const MomentRun&)>;

// Fast path (bake_packed.cpp): bake_lean_map, pack_lean_map and summarize fused row by row, with
// no float MIP chain in memory. The packed bytes, sc and the flags are exactly those of
// pack_lean_map(bake_lean_map(input, source, options).map, storage, generator), for any thread
// count (options.threads is used throughout); the summary equals summarize() of that map within
// float rounding (|B| is taken in float, summed in double row by row). Throws what
// bake_lean_map throws, with the same messages.
struct PackedBakeResult {
    PackedLeanMap packed;
    BakeSource source = BakeSource::Height;  // what the input was taken as
    std::size_t clamped_texels = 0;          // normal maps: z raised to kMinNormalZ
    std::uint64_t texels_beyond_scale = 0;   // as LeanMap::texels_beyond_scale
    LeanMapSummary summary;
    // --bits auto (bake_with_auto_storage): StorageProbe::psnr of 16-bit UNORM and of half floats
    // (dB), what the storage was chosen by; NaN for a bake in a storage given.
    double probe_unorm16_psnr = std::numeric_limits<double>::quiet_NaN();
    double probe_float16_psnr = std::numeric_limits<double>::quiet_NaN();
};

// --bits auto (docs/ktx2.md, "Choosing storage and sc"): of the two storages of 8 bytes per
// texel, the one whose rounding changes a render of the map less, measured on the map. A
// StorageProbe keeps the float moments of a grid of at most kStorageProbeSide^2 texels of every
// level (from the first bake's MomentRunSink, or a float map), rounds them as 16-bit UNORM (with
// the bake's sc, outliers clamped) and as signed half floats store them, and shades each texel
// as a render with the default material does (the LEAN lobe with 1/s, s =
// kStorageProbeShininess; Ks 1 and a light of radiance 1) under every half vector whose slope
// lies within kStorageProbeRadius of the texel's mean (a 41 x 41 grid), clamped to [0, 1] as a
// displayed render is. psnr() is the PSNR (dB) of those values against the float moments';
// choose() takes the storage with the higher one (16-bit UNORM on a tie). It compares the two;
// its absolute value is not a render's PSNR (docs/ktx2.md has both for the corpus).
inline constexpr float kStorageProbeShininess = 800.0f;  // the default s (ShadingSettings)
inline constexpr float kStorageProbeRadius = 0.5f;       // slope units
inline constexpr int kStorageProbeSide = 32;
class StorageProbe {
  public:
    // The size of the map's finest level; `threads` as BakeOptions::threads (for psnr()).
    StorageProbe(int width, int height, int threads = 0);
    // Takes a bake's float moments (every run of every level; runs of different threads at once).
    void add(const MomentRun& run);
    // add() as a sink for a bake; the probe must outlive the bake.
    MomentRunSink sink();
    // Takes a float map's levels.
    void add(const LeanMap& map);
    // PSNR (dB) of `storage`'s rounding against the floats; `unorm_scale`: the sc a UNORM bake
    // of the map has. Infinity when nothing changes.
    double psnr(Storage storage, float unorm_scale) const;
    // The same for several storages at once (one pass over the samples).
    std::vector<double> psnr(const std::vector<Storage>& storages, float unorm_scale) const;
    struct Scores {
        double unorm16 = 0.0, float16 = 0.0;  // psnr() of Unorm16 and Float16
    };
    Scores scores(float unorm_scale) const;
    Storage choose(float unorm_scale) const;  // Unorm16 or Float16 as above

  private:
    struct Texel {
        glm::vec2 mean{0.0f};
        glm::vec3 second{0.0f};
        bool sampled = false;
    };
    struct Level {
        int width = 0, height = 0, step_x = 1, step_y = 1, columns = 0;
        std::vector<Texel> texels;
    };
    std::vector<Level> levels_;
    int threads_ = 0;
    std::mutex maxima_mutex_;
    double max_b_ = 0.0, max_m_ = 0.0;  // of the finest level (signed_encoding_scale)
};
// How a bake stores its map: in `storage`, or, with `automatic` (`--bits auto`, docs/ktx2.md,
// "Choosing storage and sc"), 16-bit UNORM first and baked again as half float where the
// StorageProbe measures half floats closer to the float moments (bake_with_auto_storage).
struct StoragePolicy {
    Storage storage = Storage::Unorm16;  // the storage; Unorm16 (the first bake's) when automatic
    bool automatic = false;

    static constexpr StoragePolicy fixed(Storage storage) { return {storage, false}; }
    // `--bits auto`: chosen by the StorageProbe.
    static constexpr StoragePolicy measured() { return {Storage::Unorm16, true}; }
    bool operator==(const StoragePolicy&) const = default;
};
// "auto", or the storage's name ("8", "16", "16f", "32f").
const char* to_string(const StoragePolicy& policy);
// The policy of a storage name: storage_names() or "auto". Throws leanfade::Error(setting, cause)
// as parse_bake_storage does.
StoragePolicy parse_storage_policy(std::string_view name, const std::string& setting = "bits");

// Where a bake writes each level's packed texels: the first byte of lean1, of lean2 and
// of the plateau layer, each width * height * bytes_per_texel(storage) bytes, rows top first,
// tightly packed.
struct PackedLevelTarget {
    std::uint8_t* lean1 = nullptr;
    std::uint8_t* lean2 = nullptr;
    // The plateau layer's texels (as many bytes as lean1) when the layout has a plateau layer,
    // else unused (may be nullptr).
    std::uint8_t* plateau = nullptr;

    // The target of `layer` (kLeanLayers).
    std::uint8_t*& slice(LeanLayer layer) {
        return layer == LeanLayer::Lean1 ? lean1 : layer == LeanLayer::Lean2 ? lean2 : plateau;
    }
    std::uint8_t* slice(LeanLayer layer) const {
        return layer == LeanLayer::Lean1 ? lean1 : layer == LeanLayer::Lean2 ? lean2 : plateau;
    }
};
// Called by a bake once sc is known (the input has been read and validated) and before
// the first texel is packed, with the map's metadata and every level's width and height (its
// slices empty); returns one target per level, level 0 first. It may throw (the bake then stops).
using PackedOutputOpener = std::function<std::vector<PackedLevelTarget>(const PackedLeanMap&)>;

// ---- The bake: bake(input, settings, sink) --------------------------------------------------
// One entry for every bake of an image into a packed LEAN map: the fused fast path
// (bake_packed.cpp, docs/perf.md), which makes the bytes of pack_lean_map(bake_lean_map(...)) and
// the summary row by row with no float MIP chain in memory, for any thread count.

// What a bake reads: float samples (Image), or integer samples (UnormImage: an 8- or 16-bit
// file's, half the memory; the plateau rule takes their own quantisation step), how to read them
// (a height map, a normal map, or Auto: resolve_bake_source), and the name errors give. It refers
// to the image, which must outlive the bake.
class BakeInput {
  public:
    BakeInput(const Image& image, BakeSource read_as = BakeSource::Auto, std::string name = "")
        : floats_(&image), read_as(read_as), name(std::move(name)) {}
    BakeInput(const UnormImage& image, BakeSource read_as = BakeSource::Auto,
              std::string name = "")
        : integers_(&image), read_as(read_as), name(std::move(name)) {}
    BakeInput(const std::variant<Image, UnormImage>& image, BakeSource read_as = BakeSource::Auto,
              std::string name = "")
        : floats_(std::get_if<Image>(&image)), integers_(std::get_if<UnormImage>(&image)),
          read_as(read_as), name(std::move(name)) {}
    // Not from a temporary, which would be gone before the bake reads it.
    BakeInput(Image&&, BakeSource = BakeSource::Auto, std::string = "") = delete;
    BakeInput(UnormImage&&, BakeSource = BakeSource::Auto, std::string = "") = delete;
    BakeInput(std::variant<Image, UnormImage>&&, BakeSource = BakeSource::Auto,
              std::string = "") = delete;
    // Exactly one of the two is set.
    const Image* floats() const { return floats_; }
    const UnormImage* integers() const { return integers_; }
    int width() const { return floats_ != nullptr ? floats_->width : integers_->width; }
    int height() const { return floats_ != nullptr ? floats_->height : integers_->height; }
    int channels() const { return floats_ != nullptr ? floats_->channels : integers_->channels; }

  private:
    const Image* floats_ = nullptr;
    const UnormImage* integers_ = nullptr;

  public:
    BakeSource read_as = BakeSource::Auto;
    std::string name;  // the file (or any name) the errors give
};

// How to bake: what the map holds (options), how it is stored (a storage, or `--bits auto`), and
// the generator the container records (e.g. "leanfade 0.3.0").
struct BakeSettings {
    BakeOptions options;
    StoragePolicy storage;
    std::string generator;
    // A map whose plateau rule found nothing flat keeps its plateau layer of zeros (two-lobe
    // LEAN shades it as LEAN either way). false: the layer is left out, as `leanfade bake` does.
    bool keep_empty_plateau = false;
};

// Where a bake's map goes. A bake calls open() once sc is known (the input read and validated)
// and before the first texel is packed, once per storage it tries (`--bits auto` may bake twice:
// the later open replaces what the earlier one opened), then finish() with the result of the
// bake it keeps. Sinks in the library: PackedMapSink (memory), LevelTargetsSink (memory the
// caller provides), MomentsOnlySink (no map: the float moments only) and io::Ktx2FileSink (a
// KTX2 file written in place).
class BakeSink {
  public:
    virtual ~BakeSink() = default;
    // One target per level of `layout` (its metadata and level sizes; slices empty), level 0
    // first, each as large as PackedLevelTarget says. `threads`: the bake's thread count
    // (BakeOptions::threads resolved), for a sink that allocates. May throw (the bake then stops).
    virtual std::vector<PackedLevelTarget> open(const PackedLeanMap& layout, int threads) = 0;
    // The kept bake is complete. `drop_plateau`: its plateau layer is empty and leaves the map
    // (result.packed.plateau_epsilon is already 0). The sink may fill result.packed's slices.
    virtual void finish(PackedBakeResult& result, bool drop_plateau) = 0;
    // false: the sink takes no packed map (every target null); the bake then skips packing and
    // the plateau layer and only feeds `moments`.
    virtual bool takes_map() const { return true; }
    // When set, sees the float moments of every level as they are made, from the bake's threads
    // (e.g. RoughnessTextureBuilder, leanfade/core/roughness.hpp). The moments do not depend on
    // the storage: a `--bits auto` bake that bakes twice gives the same runs twice.
    MomentRunSink moments;
};

// The map in memory: finish() puts the layers into result.packed. `reuse`: the levels of an
// earlier result (result.packed.levels), whose buffers a map of the same size and storage takes
// without allocating.
class PackedMapSink : public BakeSink {
  public:
    explicit PackedMapSink(std::vector<PackedLevel> reuse = {}) : levels_(std::move(reuse)) {}
    // Sizes the buffers with the bake's threads (first touch).
    std::vector<PackedLevelTarget> open(const PackedLeanMap& layout, int threads) override;
    void finish(PackedBakeResult& result, bool drop_plateau) override;

  private:
    std::vector<PackedLevel> levels_;
};

// The map written into memory the caller provides (e.g. a mapped output file): `open` gives the
// targets; result.packed keeps the metadata and the level sizes, its slices empty. A plateau
// layer to drop stays in the caller's memory: the caller leaves it out.
class LevelTargetsSink : public BakeSink {
  public:
    explicit LevelTargetsSink(PackedOutputOpener open) : open_(std::move(open)) {}
    std::vector<PackedLevelTarget> open(const PackedLeanMap& layout, int) override {
        return open_(layout);
    }
    void finish(PackedBakeResult&, bool) override {}

  private:
    PackedOutputOpener open_;
};

// No map: the bake validates the input, gives every run of float moments to `moments` and
// returns the summary and the source (the engine textures without a LEAN map).
class MomentsOnlySink : public BakeSink {
  public:
    explicit MomentsOnlySink(MomentRunSink runs) { moments = std::move(runs); }
    std::vector<PackedLevelTarget> open(const PackedLeanMap& layout, int) override {
        return std::vector<PackedLevelTarget>(layout.levels.size());
    }
    void finish(PackedBakeResult&, bool) override {}
    bool takes_map() const override { return false; }
};

// Bakes `input` with `settings` into `sink`: slopes (a normal map's repaired copy where it has
// texels to repair, unless options.strict_normals), moments, the MIP chain, sc, packing, the
// plateau layer with options.plateau_epsilon > 0, and the summary; under `--bits auto` first
// 16-bit UNORM, measured by a StorageProbe, baked again as half floats where those render closer
// (result.probe_*_psnr). Returns the result; its packed map holds the metadata and level sizes
// (and the layers where the sink puts them there). Throws leanfade::Error naming input.name for
// bad samples (NaN, a slope steeper than kMaxSlope, a rejected normal), and what the sink throws.
PackedBakeResult bake(const BakeInput& input, const BakeSettings& settings, BakeSink& sink);
// bake() into memory (a PackedMapSink): result.packed holds the map.
inline PackedBakeResult bake(const BakeInput& input, const BakeSettings& settings) {
    PackedMapSink sink;
    return bake(input, settings, sink);
}

// bake_packed uses AVX2 kernels where the CPU has them (checked at run time), else portable C++;
// both give the same bytes. For tests and benchmarks: switch AVX2 off or on again (returns the
// previous setting), and whether it is in use.
bool set_bake_simd(bool enabled);
bool bake_simd_active();

}  // namespace leanfade
