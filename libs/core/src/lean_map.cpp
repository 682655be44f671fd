// LEAN moments, MIP chain and packing (docs/math.md §2-3; LEAN §3, §5).
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/bake.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include <glm/gtc/packing.hpp>
#include <glm/vec4.hpp>

#include "lean_map_internal.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/core/detail/text.hpp"

namespace leanfade {

const char* to_string(Wrap w) { return w == Wrap::Repeat ? "repeat" : "clamp"; }
const char* to_string(NormalConvention c) {
    return c == NormalConvention::OpenGL ? "opengl" : "directx";
}
const char* to_string(Storage s) {
    switch (s) {
        case Storage::Unorm8: return "8";
        case Storage::Unorm16: return "16";
        case Storage::Float16: return "16f";
        case Storage::Float32: return "32f";
    }
    return "?";
}

const std::vector<std::string>& storage_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> all;
        for (Storage s : {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32})
            all.push_back(to_string(s));
        return all;
    }();
    return names;
}

Storage parse_storage(std::string_view name, const std::string& setting) {
    for (Storage s : {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32})
        if (name == to_string(s)) return s;
    throw Error::setting(
        setting, "expected " + name_list(storage_names()) + ", got '" + std::string(name) + "'");
}

const std::vector<std::string>& bake_storage_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> all = storage_names();
        all.push_back("auto");
        return all;
    }();
    return names;
}

Storage parse_bake_storage(std::string_view name, const std::string& setting) {
    if (name == "auto") return Storage::Unorm16;
    const auto& names = bake_storage_names();
    if (std::find(names.begin(), names.end(), name) == names.end())
        throw Error::setting(setting,
                             "expected " + name_list(names) + ", got '" + std::string(name) + "'");
    return parse_storage(name, setting);
}

const char* to_string(BakeSource source) {
    switch (source) {
        case BakeSource::Auto:
            return "auto";
        case BakeSource::Height:
            return "height";
        case BakeSource::Normal:
            return "normal";
    }
    return "?";
}

const std::vector<std::pair<std::string, Wrap>>& wrap_names() {
    static const std::vector<std::pair<std::string, Wrap>> names{
        {to_string(Wrap::Repeat), Wrap::Repeat}, {to_string(Wrap::Clamp), Wrap::Clamp}};
    return names;
}

const char* to_string(StrengthUnit unit) {
    return unit == StrengthUnit::Uv ? "uv" : "texel";
}

const std::vector<std::pair<std::string, StrengthUnit>>& strength_unit_names() {
    static const std::vector<std::pair<std::string, StrengthUnit>> names{
        {to_string(StrengthUnit::Texel), StrengthUnit::Texel},
        {to_string(StrengthUnit::Uv), StrengthUnit::Uv}};
    return names;
}

const std::vector<std::string>& bake_source_names() {
    static const std::vector<std::string> names{to_string(BakeSource::Auto),
                                                to_string(BakeSource::Height),
                                                to_string(BakeSource::Normal)};
    return names;
}

BakeSource parse_bake_source(std::string_view name, const std::string& setting) {
    for (BakeSource s : {BakeSource::Auto, BakeSource::Height, BakeSource::Normal})
        if (name == to_string(s)) return s;
    throw Error::setting(setting, "expected " + name_list(bake_source_names()) + ", got '" +
                                      std::string(name) + "'");
}

int bytes_per_texel(Storage s) {
    switch (s) {
        case Storage::Unorm8: return 4;
        case Storage::Unorm16: return 8;
        case Storage::Float16: return 8;
        case Storage::Float32: return 16;
    }
    return 0;
}

const char* to_string(LeanEncoding encoding) {
    return encoding == LeanEncoding::Offset ? "offset" : "signed";
}

LeanEncoding default_encoding(Storage storage) {
    return storage == Storage::Float16 || storage == Storage::Float32 ? LeanEncoding::Signed
                                                                      : LeanEncoding::Offset;
}

float lean_offset(LeanEncoding encoding) {
    return encoding == LeanEncoding::Offset ? 1.0f : 0.0f;
}

float signed_encoding_scale(Storage storage, double max_b, double max_m) {
    if (storage != Storage::Float16) return 1.0f;
    // max M / sc^2 <= 2^15 (and |B| / sc <= 2^15, which follows for |B| >= 1 as M >= B^2).
    constexpr double kLimit = 32768.0;
    const double largest = std::max(max_m, max_b);
    float scale = 1.0f;
    while (double(scale) * double(scale) * kLimit < largest && scale < 1.0e6f) scale *= 2.0f;
    return scale;
}

int mip_level_count(int width, int height) {
    int levels = 1;
    while (width > 1 || height > 1) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        ++levels;
    }
    return levels;
}

namespace {

// The eight float moments of a texel, filtered together.
using Moments = std::array<float, 8>;  // n.xyz, B.xy, M.xx, M.yy, M.xy

using detail::reduction_taps;
using detail::Tap;

MomentLevel from_moments(int width, int height, const std::vector<Moments>& in) {
    MomentLevel level;
    level.width = width;
    level.height = height;
    level.normal.resize(in.size());
    level.mean.resize(in.size());
    level.second.resize(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
        const Moments& v = in[i];
        level.normal[i] = {v[0], v[1], v[2]};
        level.mean[i] = {v[3], v[4]};
        level.second[i] = {v[5], v[6], v[7]};
    }
    return level;
}

// One MIP step of texels of N float channels: the 2x2 box in float (box4) for even sizes, the
// separable area filter in double for others. The moments and every other linear quantity
// (cross-term textures) share it, so that their levels stay consistent.
template <std::size_t N>
std::vector<std::array<float, N>> reduce(const std::vector<std::array<float, N>>& src, int sw,
                                         int sh, int dw, int dh, int threads) {
    using Texel = std::array<float, N>;
    std::vector<Texel> dst(std::size_t(dw) * std::size_t(dh));
    if (sw == 2 * dw && sh == 2 * dh) {  // the 2x2 box, in float (box4)
        parallel_for_rows(dh, threads, [&](int first, int end) {
            for (int y = first; y < end; ++y) {
                const Texel* a = &src[std::size_t(2 * y) * std::size_t(sw)];
                const Texel* c = a + sw;
                Texel* out = &dst[std::size_t(y) * std::size_t(dw)];
                for (int x = 0; x < dw; ++x)
                    for (std::size_t m = 0; m < N; ++m)
                        out[x][m] = detail::box4(a[2 * x][m], a[2 * x + 1][m], c[2 * x][m],
                                                 c[2 * x + 1][m]);
            }
        });
        return dst;
    }
    // Other sizes (odd ones have 3 taps): separable, in double.
    const auto xtaps = reduction_taps(sw, dw);
    const auto ytaps = reduction_taps(sh, dh);
    parallel_for_rows(dh, threads, [&](int first, int end) {
        std::vector<std::array<double, N>> row(static_cast<std::size_t>(sw));
        for (int y = first; y < end; ++y) {
            // Vertical pass into a double row, then horizontal pass.
            std::fill(row.begin(), row.end(), std::array<double, N>{});
            for (const Tap& ty : ytaps[std::size_t(y)]) {
                const Texel* s = &src[std::size_t(ty.index) * std::size_t(sw)];
                for (int x = 0; x < sw; ++x)
                    for (std::size_t c = 0; c < N; ++c)
                        row[std::size_t(x)][c] += ty.weight * s[x][c];
            }
            for (int x = 0; x < dw; ++x) {
                std::array<double, N> acc{};
                for (const Tap& tx : xtaps[std::size_t(x)])
                    for (std::size_t c = 0; c < N; ++c)
                        acc[c] += tx.weight * row[std::size_t(tx.index)][c];
                Texel& d = dst[std::size_t(y) * std::size_t(dw) + std::size_t(x)];
                for (std::size_t c = 0; c < N; ++c) d[c] = float(acc[c]);
            }
        }
    });
    return dst;
}

}  // namespace

LeanMap build_lean_map(const Image& slopes, const BakeOptions& options) {
    if (slopes.channels != 2 || slopes.empty())
        throw Error("", "build_lean_map needs a non-empty 2-channel slope image");
    const int w = slopes.width, h = slopes.height;
    const float inv_s =
        options.bake_roughness_shininess > 0.0f ? 1.0f / options.bake_roughness_shininess : 0.0f;

    // Top level: n = normalize(B, 1), M = (Bx^2, By^2, Bx By) (+1/s on the diagonal, eq. 6).
    std::vector<Moments> top(slopes.texel_count());
    parallel_for_rows(h, options.threads, [&](int first, int end) {
        for (int y = first; y < end; ++y) {
            for (int x = 0; x < w; ++x) {
                const float bx = slopes.at(x, y, 0), by = slopes.at(x, y, 1);
                const float inv_len = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
                top[std::size_t(y) * std::size_t(w) + std::size_t(x)] = {
                    bx * inv_len, by * inv_len, inv_len, bx,
                    by,           bx * bx + inv_s, by * by + inv_s, bx * by};
            }
        }
    });

    LeanMap map;
    map.roughness_baked = inv_s > 0.0f;
    map.baked_shininess = map.roughness_baked ? options.bake_roughness_shininess : 0.0f;
    map.source_convention = options.convention;

    // sc (LEAN §5): the smallest value with |B| <= sc and M.xx, M.yy <= sc^2 over the top level,
    // so every packed channel stays in range, unless a few texels are far steeper than the rest
    // (choose_lean_scale). Floor avoids a zero scale for a flat map.
    double max_b = 0.0, max_m = 0.0;
    detail::SlopeHistogram histogram;
    for (const Moments& t : top) {
        histogram.add(std::max(std::abs(t[3]), std::abs(t[4])));
        for (const float b : {t[3], t[4]}) {
            if (!(std::abs(b) <= kMaxSlope)) {  // NaN fails the comparison too
                throw Error("", "slope " + std::to_string(b) +
                                    " not finite or steeper than the limit of 1e6");
            }
        }
        max_b = std::max({max_b, double(std::abs(t[3])), double(std::abs(t[4]))});
        max_m = std::max({max_m, double(t[5]), double(t[6])});
    }
    const detail::ScaleChoice scale =
        options.scale_excludes_outliers
            ? detail::choose_lean_scale(histogram, max_b, max_m, inv_s)
            : detail::ScaleChoice{detail::lean_scale(max_b, max_m), 0};
    map.scale = scale.scale;
    map.texels_beyond_scale = scale.beyond;

    int lw = w, lh = h;
    std::vector<Moments> current = std::move(top);
    const int levels = mip_level_count(w, h);
    map.levels.reserve(std::size_t(levels));
    for (int level = 0; level < levels; ++level) {
        if (level > 0) {
            const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
            current = reduce(current, lw, lh, nw, nh, options.threads);
            lw = nw;
            lh = nh;
        }
        map.levels.push_back(from_moments(lw, lh, current));
    }
    return map;
}

std::vector<Image> build_mip_chain(const Image& top, int threads) {
    if (top.empty() || top.channels != 4)
        throw Error("", "build_mip_chain needs a non-empty 4-channel image");
    using Texel = std::array<float, 4>;
    std::vector<Texel> current(top.texel_count());
    for (std::size_t i = 0; i < current.size(); ++i)
        for (std::size_t c = 0; c < 4; ++c) current[i][c] = top.pixels[i * 4 + c];
    std::vector<Image> chain;
    int lw = top.width, lh = top.height;
    const int levels = mip_level_count(lw, lh);
    for (int level = 0; level < levels; ++level) {
        if (level > 0) {
            const int nw = std::max(1, lw / 2), nh = std::max(1, lh / 2);
            current = reduce(current, lw, lh, nw, nh, threads);
            lw = nw;
            lh = nh;
        }
        Image image(lw, lh, 4);
        for (std::size_t i = 0; i < current.size(); ++i)
            for (std::size_t c = 0; c < 4; ++c) image.pixels[i * 4 + c] = current[i][c];
        chain.push_back(std::move(image));
    }
    return chain;
}

namespace {

template <class Samples>
bool grey_samples(const Samples& samples, int channels) {
    if (channels < 3) return false;
    const auto step = std::size_t(channels);
    for (std::size_t i = 0; i + 2 < samples.size(); i += step)
        if (samples[i] != samples[i + 1] || samples[i] != samples[i + 2]) return false;
    return true;
}

}  // namespace

bool is_grey_colour_image(const Image& image) { return grey_samples(image.pixels, image.channels); }

bool is_grey_colour_image(const UnormImage& image) {
    return grey_samples(image.samples, image.channels);
}

BakeSource resolve_bake_source(BakeSource requested, const Image& input) {
    if (requested != BakeSource::Auto) return requested;
    return input.channels >= 3 && !is_grey_colour_image(input) ? BakeSource::Normal
                                                               : BakeSource::Height;
}

BakeSource resolve_bake_source(BakeSource requested, const UnormImage& input) {
    if (requested != BakeSource::Auto) return requested;
    return input.channels >= 3 && !is_grey_colour_image(input) ? BakeSource::Normal
                                                               : BakeSource::Height;
}

MomentRunSink both_sinks(const MomentRunSink& first, const MomentRunSink& second) {
    if (!first) return second;
    if (!second) return first;
    return [first, second](const MomentRun& run) {
        first(run);
        second(run);
    };
}

BakeResult bake_lean_map(const Image& input, BakeSource source, const BakeOptions& options,
                         const std::string& source_name) {
    BakeResult result;
    result.source = resolve_bake_source(source, input);
    NormalRepairs repairs;
    if (result.source == BakeSource::Normal && !options.strict_normals)
        repairs = count_normal_repairs(input);
    SlopeResult slopes =
        result.source == BakeSource::Normal
            ? slopes_from_normals(repairs.any() ? repair_normal_map(input) : input, options,
                                  source_name)
            : slopes_from_height(input, options, source_name);
    result.clamped_texels = slopes.clamped_texels;
    result.map = build_lean_map(slopes.slopes, options);
    result.map.normal_repairs = repairs;
    return result;
}

namespace {
// max |Bx|, |By| and max Mxx, Myy of one level.
std::pair<double, double> largest_moments(const MomentLevel& level) {
    double max_b = 0.0, max_m = 0.0;
    for (std::size_t i = 0; i < level.mean.size(); ++i) {
        max_b =
            std::max({max_b, double(std::abs(level.mean[i].x)), double(std::abs(level.mean[i].y))});
        max_m = std::max({max_m, double(level.second[i].x), double(level.second[i].y)});
    }
    return {max_b, max_m};
}
}  // namespace

PackedLeanMap pack_lean_map(const LeanMap& map, Storage storage, const std::string& generator) {
    return pack_lean_map(map, storage, default_encoding(storage), generator);
}

PackedLeanMap pack_lean_map(const LeanMap& map, Storage storage, LeanEncoding encoding,
                            const std::string& generator) {
    if (encoding == LeanEncoding::Signed && default_encoding(storage) != LeanEncoding::Signed)
        throw Error::setting(
            "bits",
            std::string("the signed encoding needs a float storage, not ") + to_string(storage));
    PackedLeanMap packed;
    packed.storage = storage;
    packed.encoding = encoding;
    packed.scale = map.scale;
    if (packed.encoding == LeanEncoding::Signed && !map.levels.empty()) {
        // signed_encoding_scale from the top level's maxima (as the fused bake's scan).
        const auto [max_b, max_m] = largest_moments(map.levels.front());
        packed.scale = signed_encoding_scale(storage, max_b, max_m);
    }
    packed.roughness_baked = map.roughness_baked;
    packed.baked_shininess = map.baked_shininess;
    packed.source_convention = map.source_convention;
    packed.normal_repairs = map.normal_repairs;
    packed.generator = generator;
    const int bpt = bytes_per_texel(storage);
    const float sc = packed.scale, sc2 = packed.scale * packed.scale;
    // Float storages: s = gain v + offset for n, B, Mxy (0.5 v + 0.5 or v: LeanEncoding).
    const float gain = packed.encoding == LeanEncoding::Offset ? 0.5f : 1.0f;
    const float offset = packed.encoding == LeanEncoding::Offset ? 0.5f : 0.0f;
    const bool unorm = storage == Storage::Unorm8 || storage == Storage::Unorm16;
    const detail::UnormPacking unorm_factors = detail::unorm_packing(storage, sc, sc2);
    for (const MomentLevel& level : map.levels) {
        PackedLevel out;
        out.width = level.width;
        out.height = level.height;
        const std::size_t texels = level.normal.size();
        out.lean1.resize(texels * std::size_t(bpt));
        out.lean2.resize(texels * std::size_t(bpt));
        parallel_for_rows(level.height, 0, [&](int first, int end) {
            for (std::size_t i = std::size_t(first) * std::size_t(level.width);
                 i < std::size_t(end) * std::size_t(level.width); ++i) {
                const glm::vec3 n = level.normal[i];
                const glm::vec2 b = level.mean[i];
                const glm::vec3 m = level.second[i];
                std::uint8_t* t1 = &out.lean1[i * std::size_t(bpt)];
                std::uint8_t* t2 = &out.lean2[i * std::size_t(bpt)];
                if (unorm) {  // docs/math.md §3, one multiply-add per channel (unorm_texel)
                    std::uint16_t q1[4], q2[4];
                    detail::unorm_texel(unorm_factors, n, b, m, q1, q2);
                    detail::store_unorm_texel(t1, q1, storage);
                    detail::store_unorm_texel(t2, q2, storage);
                    continue;
                }
                // docs/math.md §3: lean1 = (g n + o, g Mxy / sc^2 + o)
                //          lean2 = (g B / sc + o, Mxx / sc^2, Myy / sc^2)
                const float l1[4] = {gain * n.x + offset, gain * n.y + offset, gain * n.z + offset,
                                     gain * m.z / sc2 + offset};
                const float l2[4] = {gain * b.x / sc + offset, gain * b.y / sc + offset, m.x / sc2,
                                     m.y / sc2};
                for (int c = 0; c < 4; ++c) {
                    detail::store_float_channel(t1, c, l1[c], storage);
                    detail::store_float_channel(t2, c, l2[c], storage);
                }
            }
        });
        packed.levels.push_back(std::move(out));
    }
    return packed;
}

glm::vec4 fetch_packed_texel(const PackedLeanMap& map, int level, int slice, int x, int y) {
    const PackedLevel& l = map.levels.at(std::size_t(level));
    const auto& bytes = l.slice(kLeanLayers.at(std::size_t(slice)).layer);
    const int bpt = bytes_per_texel(map.storage);
    const std::uint8_t* t =
        &bytes.at((std::size_t(y) * std::size_t(l.width) + std::size_t(x)) * std::size_t(bpt));
    return {detail::load_channel(t, 0, map.storage), detail::load_channel(t, 1, map.storage),
            detail::load_channel(t, 2, map.storage), detail::load_channel(t, 3, map.storage)};
}

LeanMap unpack_lean_map(const PackedLeanMap& packed) {
    LeanMap map;
    map.scale = packed.scale;
    map.roughness_baked = packed.roughness_baked;
    map.baked_shininess = packed.baked_shininess;
    map.source_convention = packed.source_convention;
    map.normal_repairs = packed.normal_repairs;
    for (std::size_t li = 0; li < packed.levels.size(); ++li) {
        const PackedLevel& pl = packed.levels[li];
        MomentLevel level;
        level.width = pl.width;
        level.height = pl.height;
        const std::size_t texels = std::size_t(pl.width) * std::size_t(pl.height);
        level.normal.resize(texels);
        level.mean.resize(texels);
        level.second.resize(texels);
        for (int y = 0; y < pl.height; ++y) {
            for (int x = 0; x < pl.width; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(pl.width) + std::size_t(x);
                const auto m = shading::lf_unpack(fetch_packed_texel(packed, int(li), 0, x, y),
                                                  fetch_packed_texel(packed, int(li), 1, x, y),
                                                  packed.scale, lean_offset(packed.encoding));
                level.normal[i] = m.normal;
                level.mean[i] = m.mean;
                level.second[i] = m.second;
            }
        }
        map.levels.push_back(std::move(level));
    }
    if (packed.encoding == LeanEncoding::Signed && !map.levels.empty()) {
        // The stored sc of a Signed map is a storage detail (signed_encoding_scale); the map's
        // own is the steepest slope's, so that packing it again in UNORM clamps nothing.
        const auto [max_b, max_m] = largest_moments(map.levels.front());
        map.scale = detail::lean_scale(max_b, max_m);
    }
    return map;
}

LeanMapSummary summarize(const LeanMap& map) {
    LeanMapSummary s;
    if (map.levels.empty()) return s;
    const MomentLevel& top = map.levels.front();
    s.width = top.width;
    s.height = top.height;
    s.levels = int(map.levels.size());
    s.scale = map.scale;
    double sum = 0.0;
    for (const glm::vec2& b : top.mean) {
        const double len = std::hypot(double(b.x), double(b.y));
        sum += len;
        s.max_slope = std::max(s.max_slope, float(len));
    }
    s.mean_slope = float(sum / double(top.mean.size()));
    const MomentLevel& last = map.levels.back();
    detail::summarize_coarsest(s, last.mean[0], last.second[0]);
    return s;
}

}  // namespace leanfade
