// bake_packed (the fused fast path) against the reference pack_lean_map(bake_lean_map(...)):
// the same bytes for every storage, size, wrap mode, input kind, baked roughness, kernel set and
// thread count; the same summary within float rounding; the same errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "test_helpers.hpp"

using namespace leanfade;

namespace {

const std::vector<Storage> kStorages = {Storage::Unorm8, Storage::Unorm16, Storage::Float16,
                                        Storage::Float32};

// Sizes covering: 1x1, single rows and columns, odd (3-tap) reductions, even (box) reductions
// with and without a stored level below the top, and mixed even/odd axes.
const std::vector<std::pair<int, int>>& sizes() {
    static const std::vector<std::pair<int, int>> list = {
        {1, 1},   {1, 9},    {9, 1},    {37, 23},  {129, 5}, {2, 2},    {16, 16},
        {64, 64}, {128, 67}, {67, 128}, {131, 77}, {96, 40}, {263, 130}};
    return list;
}

Image height_map(int w, int h) {
    return test::height_from(w, h, [](double x, double y) {
        return 3 * std::sin(x * 0.37 + 0.2) + 2 * std::cos(y * 0.23 + x * 0.11) +
               0.7 * std::sin(x * y * 0.013);
    });
}

// A normal map with `channels` (3 or 4) from the slopes of height_map, with a few texels whose
// z is just below zero (raised to kMinNormalZ, counted) and a few at the edge of the range.
Image normal_map(int w, int h, int channels) {
    const Image slopes = slopes_from_height(height_map(w, h), BakeOptions{}).slopes;
    Image normals(w, h, channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float bx = slopes.at(x, y, 0), by = slopes.at(x, y, 1);
            const float inv = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
            normals.at(x, y, 0) = 0.5f * bx * inv + 0.5f;
            normals.at(x, y, 1) = 0.5f * by * inv + 0.5f;
            normals.at(x, y, 2) = 0.5f * inv + 0.5f;
            if (channels == 4) normals.at(x, y, 3) = 0.25f;
            if ((x * 7 + y * 3) % 23 == 0) {  // z slightly negative: clamped, counted
                normals.at(x, y, 0) = 0.95f;
                normals.at(x, y, 2) = 0.4995f;
            }
            if ((x + y * 5) % 31 == 0) {  // grazing: |B| near 64
                normals.at(x, y, 1) = 0.0f;
                normals.at(x, y, 2) = 0.5f + 0.5f * kMinNormalZ;
            }
        }
    return normals;
}

void expect_same_packed(const PackedLeanMap& fast, const PackedLeanMap& ref,
                        const std::string& what) {
    EXPECT_EQ(fast.storage, ref.storage) << what;
    EXPECT_EQ(fast.scale, ref.scale) << what;
    EXPECT_EQ(fast.roughness_baked, ref.roughness_baked) << what;
    EXPECT_EQ(fast.baked_shininess, ref.baked_shininess) << what;
    EXPECT_EQ(fast.source_convention, ref.source_convention) << what;
    EXPECT_EQ(fast.generator, ref.generator) << what;
    EXPECT_EQ(fast.plateau_epsilon, ref.plateau_epsilon) << what;
    ASSERT_EQ(fast.levels.size(), ref.levels.size()) << what;
    for (std::size_t l = 0; l < ref.levels.size(); ++l) {
        const PackedLevel& a = fast.levels[l];
        const PackedLevel& b = ref.levels[l];
        EXPECT_EQ(a.width, b.width) << what << " level " << l;
        EXPECT_EQ(a.height, b.height) << what << " level " << l;
        // Byte-identical: report the first differing byte rather than two huge vectors.
        for (int slice = 0; slice < 3; ++slice) {
            const auto& x = slice == 0 ? a.lean1 : slice == 1 ? a.lean2 : a.plateau;
            const auto& y = slice == 0 ? b.lean1 : slice == 1 ? b.lean2 : b.plateau;
            ASSERT_EQ(x.size(), y.size()) << what << " level " << l;
            for (std::size_t i = 0; i < x.size(); ++i)
                if (x[i] != y[i]) {
                    ADD_FAILURE() << what << ": level " << l << " slice " << slice
                                  << " differs first at byte " << i << " (" << int(x[i]) << " vs "
                                  << int(y[i]) << ")";
                    break;
                }
        }
    }
}

void expect_summary_close(const LeanMapSummary& fast, const LeanMapSummary& ref,
                          const std::string& what) {
    EXPECT_EQ(fast.width, ref.width) << what;
    EXPECT_EQ(fast.height, ref.height) << what;
    EXPECT_EQ(fast.levels, ref.levels) << what;
    EXPECT_EQ(fast.scale, ref.scale) << what;
    // |B| in float instead of hypot in double: a few float ulps at most.
    EXPECT_NEAR(fast.mean_slope, ref.mean_slope, 4e-7f * ref.mean_slope + 1e-30f) << what;
    EXPECT_NEAR(fast.max_slope, ref.max_slope, 4e-7f * ref.max_slope + 1e-30f) << what;
    // The 1x1 level's floats are the reference's exactly.
    EXPECT_EQ(fast.coarsest_covariance, ref.coarsest_covariance) << what;
    if (std::isinf(ref.coarsest_anisotropy))
        EXPECT_TRUE(std::isinf(fast.coarsest_anisotropy)) << what;
    else
        EXPECT_EQ(fast.coarsest_anisotropy, ref.coarsest_anisotropy) << what;
}

// Runs `body` with the AVX2 kernels (where the CPU has them) and with the portable ones.
template <typename Body>
void for_each_kernel_set(Body body) {
    const bool previous = set_bake_simd(true);
    body();
    if (bake_simd_active()) {
        set_bake_simd(false);
        body();
    }
    set_bake_simd(previous);
}

struct Case {
    Image input;
    BakeSource source;
    BakeOptions options;
    std::string name;
};

// The reference once, then bake_packed for each storage with both kernel sets (where the CPU
// has AVX2).
void check_case(const Case& c, const std::vector<Storage>& storages) {
    const BakeResult ref = bake_lean_map(c.input, c.source, c.options, "in");
    const LeanMapSummary ref_summary = summarize(ref.map);
    for (Storage storage : storages) {
        // The reference packing, with the plateau layer the packed bake adds (plateau.hpp).
        PackedLeanMap ref_packed = pack_lean_map(ref.map, storage, "gen");
        if (c.options.plateau_epsilon > 0.0f)
            add_plateau_layer(ref_packed, c.options.plateau_epsilon);
        for_each_kernel_set([&] {
            const std::string what = c.name + " storage " + to_string(storage) +
                                     (bake_simd_active() ? " avx2" : " scalar");
            const PackedBakeResult fast =
                bake_packed(c.input, c.source, c.options, storage, "gen", "in");
            EXPECT_EQ(fast.source, ref.source) << what;
            EXPECT_EQ(fast.clamped_texels, ref.clamped_texels) << what;
            expect_same_packed(fast.packed, ref_packed, what);
            expect_summary_close(fast.summary, ref_summary, what);
        });
    }
}

std::vector<Case> cases_for(int w, int h) {
    std::vector<Case> cases;
    const std::string size = std::to_string(w) + "x" + std::to_string(h);
    for (Wrap wrap : {Wrap::Repeat, Wrap::Clamp}) {
        for (float s : {0.0f, 300.0f}) {
            BakeOptions options;
            options.wrap = wrap;
            options.bake_roughness_shininess = s;
            options.strength = 0.8f;
            const std::string tag = size + " " + to_string(wrap) + " s=" + std::to_string(s);
            cases.push_back({height_map(w, h), BakeSource::Height, options, "height " + tag});
            cases.push_back({normal_map(w, h, 3), BakeSource::Normal, options, "rgb " + tag});
            if (wrap == Wrap::Repeat) {
                cases.push_back({normal_map(w, h, 4), BakeSource::Auto, options, "rgba " + tag});
                BakeOptions dx = options;
                dx.convention = NormalConvention::DirectX;
                cases.push_back({normal_map(w, h, 3), BakeSource::Normal, dx, "directx " + tag});
            }
        }
    }
    return cases;
}

}  // namespace

TEST(BakeFastPath, SameBytesAsReferenceForEveryStorageSizeAndInput) {
    for (auto [w, h] : sizes())
        for (const Case& c : cases_for(w, h)) check_case(c, kStorages);
}

TEST(BakeFastPath, SameBytesForBuiltinSets) {
    for (const std::string& name : builtin_bump_names())
        check_case({make_builtin_height(name, 128, 3), BakeSource::Height, BakeOptions{}, name},
                   {Storage::Unorm16, Storage::Float32});
}

TEST(BakeFastPath, ThreadCountDoesNotChangeAnything) {
    for_each_kernel_set([] {
        for (auto [w, h] : {std::pair{256, 192}, std::pair{131, 77}, std::pair{1, 9}}) {
            for (BakeSource source : {BakeSource::Height, BakeSource::Normal}) {
                const Image input =
                    source == BakeSource::Height ? height_map(w, h) : normal_map(w, h, 3);
                BakeOptions options;
                options.threads = 1;
                const PackedBakeResult one =
                    bake_packed(input, source, options, Storage::Unorm16, "gen");
                for (int threads : {2, 3}) {
                    options.threads = threads;
                    const PackedBakeResult many =
                        bake_packed(input, source, options, Storage::Unorm16, "gen");
                    const std::string what = std::to_string(w) + "x" + std::to_string(h) +
                                             " threads " + std::to_string(threads);
                    expect_same_packed(many.packed, one.packed, what);
                    EXPECT_EQ(many.summary.mean_slope, one.summary.mean_slope) << what;
                    EXPECT_EQ(many.summary.max_slope, one.summary.max_slope) << what;
                    EXPECT_EQ(many.clamped_texels, one.clamped_texels) << what;
                }
            }
        }
    });
}

// Every kernel set the CPU has gives the same summary, bit for bit, and each is close to the
// reference's (on a CPU without AVX2 only the portable kernels run, against the reference).
TEST(BakeFastPath, KernelSetsGiveTheSameSummary) {
    const Image input = normal_map(263, 130, 3);
    const LeanMapSummary ref = summarize(bake_lean_map(input, BakeSource::Normal, {}, "in").map);
    std::vector<LeanMapSummary> summaries;
    for_each_kernel_set([&] {
        summaries.push_back(
            bake_packed(input, BakeSource::Normal, {}, Storage::Unorm16, "").summary);
        expect_summary_close(summaries.back(), ref, bake_simd_active() ? "avx2" : "scalar");
    });
    ASSERT_FALSE(summaries.empty());
    for (const LeanMapSummary& s : summaries) {
        EXPECT_EQ(s.mean_slope, summaries.front().mean_slope);
        EXPECT_EQ(s.max_slope, summaries.front().max_slope);
    }
}

TEST(BakeFastPath, ReusedResultEqualsAFreshOne) {
    PackedBakeResult reused;
    for (auto [w, h, storage] :
         {std::tuple{64, 64, Storage::Unorm16}, std::tuple{37, 23, Storage::Float32},
          std::tuple{64, 64, Storage::Unorm8}}) {
        const Image input = normal_map(w, h, 3);
        bake_packed_into(reused, input, BakeSource::Normal, {}, storage, "gen");
        const PackedBakeResult fresh = bake_packed(input, BakeSource::Normal, {}, storage, "gen");
        expect_same_packed(reused.packed, fresh.packed, std::to_string(w));
    }
}

TEST(BakeFastPath, RefusesWhatTheReferenceRefusesWithTheSameMessage) {
    auto message = [](auto&& bake) -> std::string {
        try {
            bake();
        } catch (const Error& e) {
            return e.what();
        }
        return "(no error)";
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<std::pair<std::string, Image>> inputs;
    {
        Image img = normal_map(40, 30, 3);
        img.at(17, 21, 1) = nan;  // first in row-major order
        img.at(3, 25, 2) = 0.2f;  // z < 0 later
        inputs.push_back({"nan then negative z", img});
    }
    {
        Image img = normal_map(40, 30, 3);
        img.at(30, 2, 2) = 0.1f;  // z <= 0 first
        img.at(5, 28, 0) = nan;   // NaN later (another thread's rows)
        inputs.push_back({"negative z then nan", img});
    }
    {
        Image img = normal_map(40, 30, 4);
        img.at(9, 4, 0) = 1.0e9f;  // slope ~1e9: steeper than kMaxSlope
        img.at(33, 29, 2) = 0.0f;  // ... but a bad z anywhere is reported first
        inputs.push_back({"steep then bad z", img});
    }
    {
        Image img = normal_map(40, 30, 3);
        img.at(9, 4, 1) = -3.0e8f;  // steep in y
        img.at(2, 20, 0) = 5.0e8f;
        inputs.push_back({"two steep", img});
    }
    {
        // Finite components near the float maximum: 2 n - 1 overflows, n.x / n.z is inf / inf.
        Image img = normal_map(40, 30, 3);
        img.at(5, 6, 0) = 3.0e38f;
        img.at(5, 6, 2) = 3.0e38f;
        inputs.push_back({"nan slope", img});
    }
    {
        Image img = normal_map(40, 30, 3);
        img.at(0, 0, 2) = std::numeric_limits<float>::infinity();
        inputs.push_back({"inf", img});
    }
    {
        Image img = height_map(40, 30);
        img.at(12, 13) = nan;
        inputs.push_back({"nan height", img});
    }
    {
        Image img(2, 2, 2);
        inputs.push_back({"two channels as normal map", img});
    }
    for (int threads : {1, 2, 3}) {
        BakeOptions options;
        options.threads = threads;
        for (const auto& [name, img] : inputs) {
            const BakeSource source =
                name == "nan height" ? BakeSource::Height : BakeSource::Normal;
            const std::string ref = message([&] { bake_lean_map(img, source, options, "f.png"); });
            const std::string fast =
                message([&] { bake_packed(img, source, options, Storage::Unorm16, "g", "f.png"); });
            EXPECT_NE(ref, "(no error)") << name;
            EXPECT_EQ(fast, ref) << name << " threads " << threads;
        }
    }
}

namespace {

// Integer samples (as an 8- or 16-bit file holds them) of a float image in [0, 1].
UnormImage quantised(const Image& image, std::uint16_t max_value) {
    UnormImage unorm(image.width, image.height, image.channels, max_value);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        unorm.samples[i] = std::uint16_t(std::lround(
            std::clamp(image.pixels[i], 0.0f, 1.0f) * float(max_value)));
    return unorm;
}

// bake_packed_to into caller-owned buffers; the opener records the layout it was given.
template <class Input>
PackedBakeResult bake_to_buffers(const Input& input, BakeSource source, const BakeOptions& options,
                                 Storage storage, PackedLeanMap& filled,
                                 const std::string& source_name = "in") {
    PackedBakeResult result = bake_packed_to(
        [&](const PackedLeanMap& layout) {
            filled = layout;
            std::vector<PackedLevelTarget> targets;
            for (PackedLevel& level : filled.levels) {
                const std::size_t bytes = std::size_t(level.width) * std::size_t(level.height) *
                                          std::size_t(bytes_per_texel(storage));
                level.lean1.assign(bytes, 0xAB);  // not zero: every byte must be written
                level.lean2.assign(bytes, 0xCD);
                if (layout.has_plateau()) level.plateau.assign(bytes, 0xEF);
                targets.push_back({level.lean1.data(), level.lean2.data(), level.plateau.data()});
            }
            return targets;
        },
        input, source, options, storage, "gen", source_name);
    return result;
}

}  // namespace

// Baking into memory the caller provides (a mapped KTX2 file in `leanfade bake`) gives the
// bytes, metadata and summary of bake_packed, from floats and from integer samples alike.
TEST(BakeFastPath, BakeIntoCallerMemoryEqualsBakePacked) {
    for_each_kernel_set([] {
        for (auto [w, h] : {std::pair{131, 77}, std::pair{64, 64}, std::pair{1, 9}}) {
            for (int channels : {3, 4}) {
                for (std::uint16_t max_value : {std::uint16_t(255), std::uint16_t(65535)}) {
                    const UnormImage samples = quantised(normal_map(w, h, channels), max_value);
                    const Image floats = samples.to_float();
                    for (Storage storage : {Storage::Unorm16, Storage::Unorm8, Storage::Float32}) {
                        for (int threads : {1, 2}) {
                            BakeOptions options;
                            options.threads = threads;
                            options.convention = channels == 4 ? NormalConvention::DirectX
                                                               : NormalConvention::OpenGL;
                            const std::string what =
                                std::to_string(w) + "x" + std::to_string(h) + " c" +
                                std::to_string(channels) + " max " + std::to_string(max_value) +
                                " " + to_string(storage) + " threads " + std::to_string(threads) +
                                (bake_simd_active() ? " avx2" : " scalar");
                            const PackedBakeResult ref =
                                bake_packed(floats, BakeSource::Auto, options, storage, "gen");
                            for (bool from_samples : {false, true}) {
                                PackedLeanMap filled;
                                const PackedBakeResult to =
                                    from_samples ? bake_to_buffers(samples, BakeSource::Auto,
                                                                   options, storage, filled)
                                                 : bake_to_buffers(floats, BakeSource::Auto,
                                                                   options, storage, filled);
                                const std::string how = what + (from_samples ? " samples" : "");
                                expect_same_packed(filled, ref.packed, how);
                                EXPECT_TRUE(to.packed.levels.front().lean1.empty()) << how;
                                EXPECT_EQ(to.packed.scale, ref.packed.scale) << how;
                                EXPECT_EQ(to.source, ref.source) << how;
                                EXPECT_EQ(to.clamped_texels, ref.clamped_texels) << how;
                                EXPECT_EQ(to.summary.mean_slope, ref.summary.mean_slope) << how;
                                EXPECT_EQ(to.summary.max_slope, ref.summary.max_slope) << how;
                                EXPECT_EQ(to.summary.coarsest_covariance,
                                          ref.summary.coarsest_covariance)
                                    << how;
                            }
                        }
                    }
                }
            }
        }
    });
}

TEST(BakeFastPath, IntegerHeightMapsBakeAsTheirFloats) {
    const UnormImage samples = quantised(test::height_from(67, 40, [](double x, double y) {
                                             return 0.5 + 0.4 * std::sin(x * 0.3 + y * 0.17);
                                         }),
                                         65535);
    BakeOptions options;
    options.strength = 40.0f;
    const PackedBakeResult ref =
        bake_packed(samples.to_float(), BakeSource::Auto, options, Storage::Unorm16, "gen");
    PackedLeanMap filled;
    const PackedBakeResult to =
        bake_to_buffers(samples, BakeSource::Auto, options, Storage::Unorm16, filled);
    EXPECT_EQ(to.source, BakeSource::Height);
    expect_same_packed(filled, ref.packed, "height samples");
}

// Bad integer normals (z below zero, steep slopes) are refused with the float path's message,
// before the opener is called: no output is ever opened for a refused input.
TEST(BakeFastPath, IntegerInputIsRefusedLikeFloatsBeforeAnyOutputIsOpened) {
    UnormImage samples = quantised(normal_map(40, 30, 3), 65535);
    samples.samples[(std::size_t(21) * 40 + 17) * 3 + 2] = 1000;  // z = 2 * 1000/65535 - 1 < 0
    const Image floats = samples.to_float();
    BakeOptions strict;  // z < 0 is refused (else raised: BakeSource.PaddingIsFlat...)
    strict.strict_normals = true;
    std::string expected = "(no error)", got = "(no error)";
    try {
        bake_packed(floats, BakeSource::Normal, strict, Storage::Unorm16, "g", "f.png");
    } catch (const Error& e) {
        expected = e.what();
    }
    bool opened = false;
    try {
        bake_packed_to(
            [&](const PackedLeanMap&) {
                opened = true;
                return std::vector<PackedLevelTarget>{};
            },
            samples, BakeSource::Normal, strict, Storage::Unorm16, "g", "f.png");
    } catch (const Error& e) {
        got = e.what();
    }
    EXPECT_NE(expected, "(no error)");
    EXPECT_NE(expected.find("(17, 21)"), std::string::npos) << expected;
    EXPECT_EQ(got, expected);
    EXPECT_FALSE(opened);
}

// An opener that fails stops the bake with its error; a wrong number of targets is refused.
TEST(BakeFastPath, FailingOpenerStopsTheBake) {
    const Image floats = normal_map(32, 32, 3);
    EXPECT_THROW(bake_packed_to([](const PackedLeanMap&) -> std::vector<PackedLevelTarget> {
                     throw Error("out.ktx2", "cannot create");
                 },
                                floats, BakeSource::Normal, {}, Storage::Unorm16, "g"),
                 Error);
    EXPECT_THROW(bake_packed_to([](const PackedLeanMap&) { return std::vector<PackedLevelTarget>(2); },
                                floats, BakeSource::Normal, {}, Storage::Unorm16, "g"),
                 std::invalid_argument);
}

TEST(UnormImage, ToFloatDividesByTheMaximum) {
    UnormImage samples(3, 1, 1, 65535);
    samples.samples = {0, 32768, 65535};
    const Image floats = samples.to_float();
    EXPECT_EQ(floats.pixels[0], 0.0f);
    EXPECT_EQ(floats.pixels[1], 32768.0f / 65535.0f);
    EXPECT_EQ(floats.pixels[2], 1.0f);
    UnormImage bytes(1, 1, 1, 255);
    bytes.samples = {51};
    EXPECT_EQ(bytes.to_float().pixels[0], 51.0f / 255.0f);
}
