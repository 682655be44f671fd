// Fast bake (docs/math.md §2-3): slopes -> top-level moments -> packing -> MIP chain, fused row by
// row, without the float MIP chain in memory. Every value is computed with the same float / double
// operations, in the same order, as the reference path (slopes.cpp, build_lean_map, pack_lean_map),
// so the packed bytes are identical; docs/perf.md has the design and the measurements.
//
//   pass 0  validate the input, find max |B| and max M (sc, docs/math.md §3, must be known
//           before the first texel can be packed) and take the summary's statistics of |B|;
//   pass 1  the rows of a "store level" S (64 rows for 4096^2), each to whichever thread is free.
//           A row is made by making the (2 or 3) rows of the level above that it filters,
//           recursively up to the top level, which is computed from the input in cache-sized
//           chunks (moments into L1-resident planes, then packed from them) and box-filtered
//           into level 1. Each level keeps
//           only its last 3 rows. A row is packed by the thread that makes it for its first
//           consumer, so exactly once, whatever the number of threads;
//   pass 2  the levels below S, serially, from the stored float rows of level S.
//
// Kernels: bake_packed_kernels.hpp, one table per instruction set (AVX2 where the CPU has it,
// checked at run time, else portable C++); both give the same bytes.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <variant>
#include <vector>

#include "bake_packed_kernels.hpp"
#include "lean_map_internal.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/detail/memory.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "plateau_internal.hpp"

namespace leanfade {
namespace {

using namespace bake_kernels;

constexpr int kChunk = 256;        // top-level texels per chunk of the fused pass (fits L1)
constexpr int kMaxStoreLevel = 6;  // pass 1 ends at most here (64 rows of a 4096^2 map)
constexpr int kMinStoreRows = 16;  // ... and at a level with at least this many rows
constexpr int kScanGrain = 16;     // top rows per chunk of pass 0

std::atomic<bool> g_simd_enabled{true};

// ---- Integer input: rows converted to float as they are read ---------------------------------

// The last two rows this thread converted (pass 1 alternates between two top rows).
struct ConvertedRows {
    std::uint64_t bake_id = 0;
    int y[2] = {-1, -1};
    int next = 0;
    std::vector<float> rows[2];
};
thread_local ConvertedRows t_converted;
std::atomic<std::uint64_t> g_next_bake_id{1};

}  // namespace

const float* bake_kernels::TopInput::converted_row(int y) const {
    ConvertedRows& cache = t_converted;
    if (cache.bake_id != bake_id) cache = ConvertedRows{bake_id, {-1, -1}, 0, {}};
    for (int k = 0; k < 2; ++k)
        if (cache.y[k] == y) return cache.rows[k].data();
    const int k = cache.next;
    cache.next ^= 1;
    std::vector<float>& out = cache.rows[k];
    out.resize(row_values());
    const std::uint16_t* samples = unorm + std::size_t(y) * row_values();
    unorm_to_float(samples, row_values(), unorm_max, out.data());
    cache.y[k] = y;
    return out.data();
}

namespace {

// ---- The plan and the row pipeline ---------------------------------------------------------

struct LevelPlan {
    int width = 0;
    int height = 0;
    std::size_t stride = 0;           // floats per plane in row buffers (width rounded up to 8)
    bool box = false;                 // made from the level above by the 2x2 box (even sizes)
    TapTable ytaps, xtaps;            // from the level above (levels > 0)
    std::vector<int> first_consumer;  // per row: the first row of the next level that filters it
};

struct Plan {
    TopInput top;
    std::vector<LevelPlan> levels;
    int store_level = 0;
    PackScale scale;
    Kernels kernels;
    int texel_bytes = 0;
    std::vector<PackedLevelTarget> targets;  // where each level's rows are packed
    bool pack = true;                        // false: targets are null, nothing is packed
    const MomentRunSink* moments = nullptr;  // sees every texel's float moments once
    std::vector<float> stored;  // the planes of every row of the store level

    // A made row's texels [x, x + count) (planes indexed from x) to the moment sink.
    void emit(int level, int y, int x, int count, Planes p) const {
        if (moments == nullptr) return;
        (*moments)(MomentRun{level, y, x, count, p[kBx], p[kBy], p[kMxx], p[kMyy], p[kMxy]});
    }

    Planes stored_row(int y) {
        const std::size_t stride = levels[std::size_t(store_level)].stride;
        return {stored.data() + std::size_t(y) * kMoments * stride, stride};
    }
    RowDest dest(int level, int y) const {
        const LevelPlan& lp = levels[std::size_t(level)];
        const PackedLevelTarget& out = targets[std::size_t(level)];
        const std::size_t offset =
            std::size_t(y) * std::size_t(lp.width) * std::size_t(texel_bytes);
        return {out.lean1 + offset, out.lean2 + offset};
    }
};

// Makes rows of any level on demand, keeping the last 3 rows of each level.
class RowMaker {
  public:
    // from_stored: the store level's rows are read from plan.stored (pass 2); otherwise the top
    // level is computed from the input and the store level's rows are written to plan.stored.
    RowMaker(Plan& plan, bool from_stored)
        : plan_(plan),
          from_stored_(from_stored),
          rings_(plan.levels.size()),
          ring_rows_(plan.levels.size(), std::array<int, 3>{-1, -1, -1}) {}

    // Row y of `level`; packs it (and the rows it is made from that it is the first consumer
    // of) when `owned`. The planes stay valid until the next 3 rows of that level are made.
    Planes row(int level, int y, bool owned) {
        const LevelPlan& lp = plan_.levels[std::size_t(level)];
        if (level == plan_.store_level) {
            if (from_stored_) return plan_.stored_row(y);
            const Planes out = plan_.stored_row(y);
            make(level, y, owned, out);
            return out;
        }
        std::vector<float>& ring = rings_[std::size_t(level)];
        if (ring.empty()) ring.resize(3 * kMoments * lp.stride);
        const int slot = y % 3;
        const Planes out{ring.data() + std::size_t(slot) * kMoments * lp.stride, lp.stride};
        int& cached = ring_rows_[std::size_t(level)][std::size_t(slot)];
        if (cached == y) return out;
        make(level, y, owned, out);
        cached = y;
        return out;
    }

  private:
    void make(int level, int y, bool owned, Planes out) {
        const LevelPlan& lp = plan_.levels[std::size_t(level)];
        if (level == 0) {
            make_top(y, 0, lp.width, out, owned);
            return;
        }
        if (level == 1 && lp.box && !from_stored_) {
            make_first_box(y, out, owned);
            return;
        }
        const LevelPlan& up = plan_.levels[std::size_t(level - 1)];
        const auto& taps = lp.ytaps[std::size_t(y)];
        const int count = int(taps.size());
        if (count > 3) throw std::logic_error("bake_packed: more than 3 filter taps");
        Planes src[3];
        double weights[3];
        for (int k = 0; k < count; ++k) {
            const int s = taps[std::size_t(k)].index;
            src[k] = row(level - 1, s, owned && up.first_consumer[std::size_t(s)] == y);
            weights[k] = taps[std::size_t(k)].weight;
        }
        if (lp.box) {
            for (int c = 0; c < kMoments; ++c)
                plan_.kernels.reduce_box(src[0][c], src[1][c], out[c], 0, lp.width);
        } else {
            if (vertical_.size() < std::size_t(up.width)) vertical_.resize(std::size_t(up.width));
            for (int c = 0; c < kMoments; ++c) {
                const float* rows[3] = {src[0][c], count > 1 ? src[1][c] : nullptr,
                                        count > 2 ? src[2][c] : nullptr};
                filter_channel(rows, weights, count, up.width, lp, out[c]);
            }
        }
        if (owned) {
            if (plan_.pack) plan_.kernels.pack_range(out, 0, lp.width, plan_.dest(level, y), plan_.scale);
            plan_.emit(level, y, 0, lp.width, out);
        }
    }

    void filter_channel(const float* const* rows, const double* weights, int count, int sw,
                        const LevelPlan& lp, float* out) {
        plan_.kernels.vertical(rows, weights, count, 0, sw, vertical_.data());
        plan_.kernels.horizontal(vertical_.data(), sw, lp.width, lp.xtaps, 0, out);
    }

    // Top-level texels [x0, x1) of row y into planes indexed from x0.
    void make_top(int y, int x0, int x1, Planes out, bool owned) {
        plan_.kernels.top_range(plan_.top, y, x0, x1, out);
        if (!owned) return;
        plan_.emit(0, y, x0, x1 - x0, out);
        if (plan_.pack) {
            const RowDest row = plan_.dest(0, y);
            const std::size_t offset = std::size_t(x0) * std::size_t(plan_.texel_bytes);
            plan_.kernels.pack_range(out, 0, x1 - x0,
                                     RowDest{row.lean1 + offset, row.lean2 + offset},
                                     plan_.scale);
        }
    }

    // Level 1 row y from top rows 2y, 2y + 1 (even sizes), chunk by chunk so that the top
    // moments never leave L1: compute, pack, box-filter.
    void make_first_box(int y, Planes out, bool owned) {
        const int w0 = plan_.levels[0].width;
        if (chunk_.empty()) chunk_.resize(2 * kMoments * std::size_t(kChunk));
        const Planes a{chunk_.data(), kChunk}, c{chunk_.data() + kMoments * kChunk, kChunk};
        for (int x0 = 0; x0 < w0; x0 += kChunk) {
            const int x1 = std::min(w0, x0 + kChunk);
            make_top(2 * y, x0, x1, a, owned);
            make_top(2 * y + 1, x0, x1, c, owned);
            for (int m = 0; m < kMoments; ++m)
                plan_.kernels.reduce_box(a[m], c[m], out[m] + x0 / 2, 0, (x1 - x0) / 2);
        }
        if (owned) {
            const int w1 = plan_.levels[1].width;
            if (plan_.pack) plan_.kernels.pack_range(out, 0, w1, plan_.dest(1, y), plan_.scale);
            plan_.emit(1, y, 0, w1, out);
        }
    }

    Plan& plan_;
    bool from_stored_;
    std::vector<std::vector<float>> rings_;
    std::vector<std::array<int, 3>> ring_rows_;
    std::vector<float> chunk_;
    std::vector<double> vertical_;
};

std::vector<LevelPlan> plan_levels(int width, int height) {
    const int count = mip_level_count(width, height);
    std::vector<LevelPlan> levels(static_cast<std::size_t>(count));
    for (int l = 0; l < count; ++l) {
        LevelPlan& lp = levels[std::size_t(l)];
        lp.width = width;
        lp.height = height;
        lp.stride = (std::size_t(width) + 7) / 8 * 8;
        if (l > 0) {
            const LevelPlan& up = levels[std::size_t(l - 1)];
            lp.box = up.width == 2 * width && up.height == 2 * height;
            lp.ytaps = detail::reduction_taps(up.height, height);
            lp.xtaps = detail::reduction_taps(up.width, width);
        }
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
    }
    for (int l = 0; l + 1 < count; ++l) {
        LevelPlan& lp = levels[std::size_t(l)];
        lp.first_consumer.assign(std::size_t(lp.height), -1);
        const TapTable& taps = levels[std::size_t(l + 1)].ytaps;
        for (std::size_t r = 0; r < taps.size(); ++r)
            for (const Tap& t : taps[r])
                if (lp.first_consumer[std::size_t(t.index)] < 0)
                    lp.first_consumer[std::size_t(t.index)] = int(r);
    }
    return levels;
}

int choose_store_level(const std::vector<LevelPlan>& levels) {
    int store = 0;
    for (int l = 1; l < int(levels.size()) && l <= kMaxStoreLevel; ++l)
        if (levels[std::size_t(l)].height >= kMinStoreRows) store = l;
    return store;
}

// Pass 0: validation as slopes_from_normals (first bad texel in row-major order; every NaN and
// z check before any slope check), the clamped count and the maxima for sc.
struct ScanTotals {
    double max_b = 0.0, max_m = 0.0;
    std::size_t clamped = 0;
    double sum_slope = 0.0;  // sum of |B|, row by row in order
    float max_slope = 0.0f;  // max |B|
    detail::SlopeHistogram histogram;  // of max(|Bx|, |By|), every texel
};

ScanTotals scan_input(const TopInput& in, int height, int threads, ScanFn scan,
                      const std::string& source_name, const char* steep_cause) {
    std::vector<RowScan> rows(static_cast<std::size_t>(height));
    std::vector<detail::SlopeHistogram> histograms(
        static_cast<std::size_t>(resolve_thread_count(threads)));
    // Chunks are handed out in increasing order, so once a bad texel is found every row before
    // it has been (or is being) scanned and no further chunk is needed.
    std::atomic<bool> bad{false};
    parallel_for_dynamic(height, threads, kScanGrain, [&](int worker, int first, int end) {
        if (bad.load(std::memory_order_relaxed)) return;
        for (int y = first; y < end; ++y) {
            rows[std::size_t(y)].histogram = &histograms[std::size_t(worker)];
            if (!scan(in, y, rows[std::size_t(y)])) {
                bad = true;
                return;
            }
        }
    });
    for (int y = 0; y < height; ++y) {
        const RowScan& r = rows[std::size_t(y)];
        if (r.bad_x < 0) continue;
        const float* t = in.row(y) + std::size_t(r.bad_x) * std::size_t(in.channels);
        if (!std::isfinite(t[0]) || !std::isfinite(t[1]) || !std::isfinite(t[2]))
            detail::throw_non_finite_normal(source_name, r.bad_x, y);
        detail::throw_negative_normal_z(source_name, r.bad_x, y, 2.0f * t[2] - 1.0f);
    }
    ScanTotals totals;
    float max_b = 0.0f;
    bool nan_slope = false;
    for (const RowScan& r : rows) {
        max_b = std::max(max_b, r.max_b);
        nan_slope = nan_slope || r.nan_slope;
        totals.clamped += r.clamped;
        totals.sum_slope += r.stats.total();
        totals.max_slope = std::max(totals.max_slope, r.stats.max);
    }
    // A slope steeper than the limit, or NaN (n is finite, but 2 n - 1 may overflow; found by
    // fuzz_image_bake), exists exactly when max |B| exceeds it or a row saw a NaN; then find the
    // first one.
    if (!(max_b <= kMaxSlope) || nan_slope) {
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < in.width; ++x) {
                float bx, by;
                const float* t = in.row(y) + std::size_t(x) * std::size_t(in.channels);
                if (in.channels == 2) {
                    bx = t[0];
                    by = t[1];
                } else {
                    normal_slope(t, in.green_sign, bx, by);
                }
                if (!(std::abs(bx) <= kMaxSlope))
                    detail::throw_steep_slope(source_name, x, y, bx, steep_cause);
                if (!(std::abs(by) <= kMaxSlope))
                    detail::throw_steep_slope(source_name, x, y, by, steep_cause);
            }
    }
    // build_lean_map takes max M over Mxx = fl(Bx * Bx + 1/s) and Myy; that is non-decreasing
    // in |B| (each rounding is monotonic), so max M = fl(max|B| * max|B| + 1/s), exactly.
    totals.max_b = double(max_b);
    totals.max_m = double(max_b * max_b + in.inv_s);
    for (const detail::SlopeHistogram& h : histograms) totals.histogram.merge(h);
    return totals;
}

// Resizes one output slice. A new vector's bytes are zero-filled by resize, which faults every
// page in: a new buffer is advised to use huge pages first (assign_large, docs/perf.md). Reused
// buffers are left as they are.
void size_slice(std::vector<std::uint8_t>& slice, std::size_t bytes) {
    if (slice.capacity() < bytes) {
        assign_large(slice, bytes, std::uint8_t(0));
        return;
    }
    slice.resize(bytes);
}

// Sizes the slices of the output levels (whose width and height are set); lean1, lean2 and the
// plateau layer (when the map has one; else it is emptied) by different threads, sharing the
// first touch.
void size_output(PackedLeanMap& packed, int texel_bytes, int threads) {
    const std::size_t count = packed.levels.size();
    const int slices = packed.layer_count();  // the first rows of kLeanLayers
    for (const LeanLayerInfo& row : kLeanLayers)
        if (!packed.has_layer(row.layer))
            for (PackedLevel& level : packed.levels) level.slice(row.layer) = {};
    parallel_for_rows(int(std::size_t(slices) * count), std::min(threads, slices),
                      [&](int first, int end) {
        for (int job = first; job < end; ++job) {
            const std::size_t l = std::size_t(job) % count;
            const std::size_t slice = std::size_t(job) / count;
            PackedLevel& out = packed.levels[l];
            const std::size_t bytes =
                std::size_t(out.width) * std::size_t(out.height) * std::size_t(texel_bytes);
            size_slice(out.slice(kLeanLayers[slice].layer), bytes);
        }
    });
}

// The map's own level vectors as the bake's targets, sized for `storage` (size_output).
std::vector<PackedLevelTarget> sized_targets(PackedLeanMap& packed, Storage storage, int threads) {
    size_output(packed, bytes_per_texel(storage), threads);
    std::vector<PackedLevelTarget> targets;
    for (PackedLevel& level : packed.levels) {
        PackedLevelTarget target;
        for (const LeanLayerInfo& row : kLeanLayers) {
            std::vector<std::uint8_t>& slice = level.slice(row.layer);
            target.slice(row.layer) = slice.empty() ? nullptr : slice.data();
        }
        targets.push_back(target);
    }
    return targets;
}

}  // namespace

bool set_bake_simd(bool enabled) {
    return g_simd_enabled.exchange(enabled);
}

bool bake_simd_active() {
    return avx2::supported() && g_simd_enabled.load();
}

namespace {

// Fills `packed` with the metadata and the level sizes and returns where each level goes.
using TargetProvider =
    std::function<std::vector<PackedLevelTarget>(PackedLeanMap& packed, int threads)>;

// The first channel of integer samples as floats (UnormImage::to_float's values).
Image first_channel(const UnormImage& input) {
    Image height(input.width, input.height, 1);
    const auto channels = std::size_t(input.channels);
    const float scale = float(input.max_value);
    for (std::size_t i = 0; i < height.pixels.size(); ++i)
        height.pixels[i] = float(input.samples[i * channels]) / scale;
    return height;
}

// `source`: input.read_as resolved (a height or a normal map).
void bake_repaired(PackedBakeResult& result, const BakeInput& input, BakeSource source,
                   const BakeOptions& options, Storage storage, const std::string& generator,
                   const std::string& source_name, const TargetProvider& provide_targets,
                   const NormalRepairs& repairs, const MomentRunSink& moments, float source_step) {
    result.source = source;
    result.clamped_texels = 0;
    const bool avx2 = bake_simd_active();
    if (!std::isfinite(options.plateau_epsilon) || options.plateau_epsilon < 0.0f)
        throw Error::setting("plateau_epsilon", "must be finite and >= 0 (0: no plateau layer)");

    Plan plan;
    plan.top.green_sign = options.convention == NormalConvention::DirectX ? -1.0f : 1.0f;
    plan.top.inv_s =
        options.bake_roughness_shininess > 0.0f ? 1.0f / options.bake_roughness_shininess : 0.0f;
    // Pass 0. Height maps go through the reference slope filter (Sobel in double, docs/math.md
    // §2), which also validates them; normal maps are decoded on the fly in pass 1.
    Image slopes;
    ScanTotals totals;
    const int width = input.width(), height = input.height();
    if (result.source == BakeSource::Normal) {
        detail::check_normal_map_shape(width, height, input.channels(), source_name);
        if (input.floats() != nullptr) {
            plan.top.pixels = input.floats()->pixels.data();
        } else {
            plan.top.unorm = input.integers()->samples.data();
            plan.top.unorm_max = float(input.integers()->max_value);
            plan.top.bake_id = g_next_bake_id.fetch_add(1);
        }
        plan.top.width = width;
        plan.top.channels = input.channels();
        plan.kernels = select_kernels(plan.top.channels, storage, avx2);
        plan.top.unorm_to_float = plan.kernels.unorm_to_float;
        totals = scan_input(plan.top, height, options.threads, plan.kernels.scan_row, source_name,
                            detail::kSteepNormalCause);
        result.clamped_texels = totals.clamped;
    } else {
        // Integer samples: only the first channel (the height) as floats.
        slopes =
            input.floats() != nullptr
                ? slopes_from_height(*input.floats(), options, source_name).slopes
                : slopes_from_height(first_channel(*input.integers()), options, source_name).slopes;
        plan.top.pixels = slopes.pixels.data();
        plan.top.width = slopes.width;
        plan.top.channels = 2;
        plan.kernels = select_kernels(plan.top.channels, storage, avx2);
        totals = scan_input(plan.top, slopes.height, options.threads, plan.kernels.scan_row,
                            source_name, "height steps times the strength are too large");
    }
    const detail::ScaleChoice scale =
        options.scale_excludes_outliers
            ? detail::choose_lean_scale(totals.histogram, totals.max_b, totals.max_m,
                                        plan.top.inv_s)
            : detail::ScaleChoice{detail::lean_scale(totals.max_b, totals.max_m), 0};
    result.texels_beyond_scale = scale.beyond;
    // A Signed map (float storages) is stored with its own sc, a power of two (LeanEncoding).
    const LeanEncoding encoding = default_encoding(storage);
    const float sc = encoding == LeanEncoding::Signed
                         ? signed_encoding_scale(storage, totals.max_b, totals.max_m)
                         : scale.scale;
    plan.scale.sc = sc;
    plan.scale.sc2 = sc * sc;
    plan.scale.unorm = detail::unorm_packing(storage, plan.scale.sc, plan.scale.sc2);
    plan.scale.gain = encoding == LeanEncoding::Offset ? 0.5f : 1.0f;
    plan.scale.offset = encoding == LeanEncoding::Offset ? 0.5f : 0.0f;

    const int texel_bytes = bytes_per_texel(storage);
    plan.texel_bytes = texel_bytes;
    plan.levels = plan_levels(width, height);
    plan.store_level = choose_store_level(plan.levels);
    const LevelPlan& store = plan.levels[std::size_t(plan.store_level)];
    plan.stored.resize(std::size_t(store.height) * kMoments * store.stride);

    PackedLeanMap& packed = result.packed;
    packed.storage = storage;
    packed.encoding = encoding;
    packed.scale = sc;
    packed.roughness_baked = plan.top.inv_s > 0.0f;
    packed.baked_shininess = packed.roughness_baked ? options.bake_roughness_shininess : 0.0f;
    packed.plateau_epsilon = options.plateau_epsilon;
    packed.source_convention = options.convention;
    packed.normal_repairs = repairs;
    packed.generator = generator;
    packed.levels.assign(plan.levels.size(), PackedLevel{});
    for (std::size_t l = 0; l < plan.levels.size(); ++l) {
        packed.levels[l].width = plan.levels[l].width;
        packed.levels[l].height = plan.levels[l].height;
    }
    plan.targets = provide_targets(packed, resolve_thread_count(options.threads));
    if (plan.targets.size() != plan.levels.size())
        throw std::invalid_argument("bake_packed_to: one output target per level expected");
    const auto unpacked = [](const PackedLevelTarget& t) { return t.lean1 == nullptr; };
    plan.pack = !std::all_of(plan.targets.begin(), plan.targets.end(), unpacked);
    if (plan.pack && std::any_of(plan.targets.begin(), plan.targets.end(), unpacked))
        throw std::invalid_argument("bake_packed_to: every level's target or none expected");
    if (!plan.pack && packed.has_plateau())
        throw std::invalid_argument("bake_packed_to: a plateau layer needs packed targets");
    if (packed.has_plateau())
        for (const PackedLevelTarget& target : plan.targets)
            if (target.plateau == nullptr)
                throw std::invalid_argument("bake_packed_to: a plateau target per level expected");
    plan.moments = moments ? &moments : nullptr;

    // Pass 1: the store level's rows (and everything above them), one at a time to whichever
    // thread is free. Which thread makes a row changes nothing in it.
    std::vector<std::unique_ptr<RowMaker>> makers(
        static_cast<std::size_t>(resolve_thread_count(options.threads)));
    parallel_for_dynamic(store.height, options.threads, 1, [&](int worker, int first, int end) {
        auto& maker = makers[std::size_t(worker)];
        if (!maker) maker = std::make_unique<RowMaker>(plan, false);
        for (int y = first; y < end; ++y) maker->row(plan.store_level, y, true);
    });
    // Pass 2: the small levels below, from the stored rows.
    RowMaker maker(plan, true);
    const int last = int(plan.levels.size()) - 1;
    const Planes coarsest = maker.row(last, 0, true);

    LeanMapSummary& s = result.summary;
    s = LeanMapSummary{};
    s.width = width;
    s.height = height;
    s.levels = int(plan.levels.size());
    s.scale = scale.scale;  // the map's sc (a Signed map is stored with its own)
    s.max_slope = totals.max_slope;
    s.mean_slope = float(totals.sum_slope / (double(width) * double(height)));
    detail::summarize_coarsest(s, {coarsest[kBx][0], coarsest[kBy][0]},
                               {coarsest[kMxx][0], coarsest[kMyy][0], coarsest[kMxy][0]});

    // Two-lobe LEAN's plateau layer from the packed finest level (add_plateau_layer's bytes).
    if (packed.has_plateau()) {
        const detail::PlateauOutcome plateau = detail::pack_plateau_layer_to(
            packed, plan.targets.front().lean2, plan.targets, packed.plateau_epsilon, source_step,
            options.spike_fit, options.threads);
        s.plateau_fraction = plateau.fraction;
        s.spike_window = plateau.rule.window;
        s.flat_fraction = plateau.rule.window.shape == SpikeWindowShape::None
                              ? plateau.fraction
                              : plateau.fit.plateau_fraction;
        s.spike_fit_error = plateau.fit.error;
        s.plateaus_fit_error = plateau.fit.plateaus_error;
        s.plateau_rule_epsilon = plateau.rule.epsilon;
        s.plateau_radius_x = plateau.rule.radius_x;
        s.plateau_radius_y = plateau.rule.radius_y;
    }
}

// The bake of a normal map's repaired copy where it has texels to repair (NormalRepairs), else of
// the input as it is.
void bake_samples(PackedBakeResult& result, const BakeInput& input, const BakeOptions& options,
                  Storage storage, const std::string& generator,
                  const TargetProvider& provide_targets, const MomentRunSink& moments) {
    const BakeSource resolved = input.floats() != nullptr
                                    ? resolve_bake_source(input.read_as, *input.floats())
                                    : resolve_bake_source(input.read_as, *input.integers());
    NormalRepairs repairs;
    if (resolved == BakeSource::Normal && !options.strict_normals) {
        repairs = input.floats() != nullptr ? count_normal_repairs(*input.floats())
                                            : count_normal_repairs(*input.integers());
    }
    // The quantisation step of the source's slopes (the plateau rule's, plateau.hpp).
    // Integer samples: their own precision (a 16-bit file of 8-bit data has 8-bit steps).
    const int max_code =
        input.integers() != nullptr
            ? input.integers()->effective_max_code(resolved == BakeSource::Normal ? 3 : 1)
            : options.source_max_code;
    // A strength per UV unit is per texel times the texel count (the larger side's).
    const float texel_strength =
        options.strength_unit == StrengthUnit::Uv
            ? options.strength * float(std::max(input.width(), input.height()))
            : options.strength;
    const float source_step = source_slope_step(resolved, max_code, texel_strength);
    if (!repairs.any()) {
        bake_repaired(result, input, resolved, options, storage, generator, input.name,
                      provide_targets, repairs, moments, source_step);
        return;
    }
    const Image repaired = repair_normal_map(
        input.floats() != nullptr ? *input.floats() : input.integers()->to_float());
    bake_repaired(result, BakeInput(repaired, resolved, input.name), resolved, options, storage,
                  generator, input.name, provide_targets, repairs, moments, source_step);
}

}  // namespace

const char* to_string(const StoragePolicy& policy) {
    return policy.automatic ? "auto" : to_string(policy.storage);
}

StoragePolicy parse_storage_policy(std::string_view name, const std::string& setting) {
    return {parse_bake_storage(name, setting), name == "auto"};
}

std::vector<PackedLevelTarget> PackedMapSink::open(const PackedLeanMap& layout, int threads) {
    // The map's levels, taking the buffers of the earlier ones (sized_targets keeps a buffer of
    // the right size as it is).
    PackedLeanMap map;
    map.metadata() = layout.metadata();
    map.levels.resize(layout.levels.size());
    for (std::size_t l = 0; l < layout.levels.size(); ++l) {
        map.levels[l].width = layout.levels[l].width;
        map.levels[l].height = layout.levels[l].height;
        if (l < levels_.size())
            for (const LeanLayerInfo& row : kLeanLayers)
                map.levels[l].slice(row.layer) = std::move(levels_[l].slice(row.layer));
    }
    std::vector<PackedLevelTarget> targets = sized_targets(map, map.storage, threads);
    levels_ = std::move(map.levels);
    return targets;
}

void PackedMapSink::finish(PackedBakeResult& result, bool drop_plateau) {
    result.packed.levels = std::move(levels_);
    levels_.clear();
    if (drop_plateau) remove_plateau_layer(result.packed);
}

PackedBakeResult bake(const BakeInput& input, const BakeSettings& settings, BakeSink& sink) {
    BakeOptions options = settings.options;
    StoragePolicy policy = settings.storage;
    if (!sink.takes_map()) {
        // Nothing is packed: no plateau layer, and the float moments need no storage choice.
        options.plateau_epsilon = 0.0f;
        policy = {Storage::Float32, false};
    }
    PackedBakeResult result = bake_with_auto_storage(
        policy.storage, policy.automatic, input.width(), input.height(),
        [&](Storage storage, const MomentRunSink& probe) {
            PackedBakeResult baked;
            bake_samples(
                baked, input, options, storage, settings.generator,
                [&](PackedLeanMap& packed, int threads) { return sink.open(packed, threads); },
                both_sinks(sink.moments, probe));
            return baked;
        });
    // Nothing flat: the map keeps no layer of zeros (a third of its bytes).
    const bool drop_plateau = !settings.keep_empty_plateau && result.packed.has_plateau() &&
                              result.summary.plateau_fraction == 0.0f;
    if (drop_plateau) result.packed.plateau_epsilon = 0.0f;
    sink.finish(result, drop_plateau);
    return result;
}

namespace {

BakeSettings packed_settings(const BakeOptions& options, Storage storage,
                             const std::string& generator) {
    return BakeSettings{.options = options,
                        .storage = StoragePolicy::fixed(storage),
                        .generator = generator,
                        .keep_empty_plateau = true};
}

// bake_packed_to of either kind of samples.
PackedBakeResult bake_to_targets(const PackedOutputOpener& open_output, const BakeInput& input,
                                 const BakeOptions& options, Storage storage,
                                 const std::string& generator, const MomentRunSink& moments) {
    LevelTargetsSink sink(open_output);
    sink.moments = moments;
    return bake(input, packed_settings(options, storage, generator), sink);
}

}  // namespace

void bake_packed_into(PackedBakeResult& result, const Image& input, BakeSource source,
                      const BakeOptions& options, Storage storage, const std::string& generator,
                      const std::string& source_name, const MomentRunSink& moments) {
    // Keep the buffers of a previous result: baking a map of the same size and storage again
    // allocates nothing.
    PackedMapSink sink(std::move(result.packed.levels));
    sink.moments = moments;
    result = bake(BakeInput(input, source, source_name),
                  packed_settings(options, storage, generator), sink);
}

PackedBakeResult bake_packed_to(const PackedOutputOpener& open_output, const Image& input,
                                BakeSource source, const BakeOptions& options, Storage storage,
                                const std::string& generator, const std::string& source_name,
                                const MomentRunSink& moments) {
    return bake_to_targets(open_output, BakeInput(input, source, source_name), options, storage,
                           generator, moments);
}

PackedBakeResult bake_packed_to(const PackedOutputOpener& open_output, const UnormImage& input,
                                BakeSource source, const BakeOptions& options, Storage storage,
                                const std::string& generator, const std::string& source_name,
                                const MomentRunSink& moments) {
    return bake_to_targets(open_output, BakeInput(input, source, source_name), options, storage,
                           generator, moments);
}

PackedBakeResult bake_packed(const Image& input, BakeSource source, const BakeOptions& options,
                             Storage storage, const std::string& generator,
                             const std::string& source_name, const MomentRunSink& moments) {
    PackedBakeResult result;
    bake_packed_into(result, input, source, options, storage, generator, source_name, moments);
    return result;
}

PackedBakeResult bake_packed_image(const std::variant<Image, UnormImage>& input, BakeSource source,
                                   const BakeOptions& options, StoragePolicy storage,
                                   const std::string& generator, const std::string& source_name,
                                   const MomentRunSink& moments) {
    PackedMapSink sink;
    sink.moments = moments;
    return bake(BakeInput(input, source, source_name), BakeSettings{options, storage, generator},
                sink);
}

}  // namespace leanfade