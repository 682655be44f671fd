// bake(input, settings, sink), the one bake entry (leanfade/core/lean_map.hpp): every sink gets
// the same map from the same input and settings, a file sink writes the bytes write_ktx2 writes
// of the map in memory, a map sink reuses the buffers it is given, and nothing is left behind when
// the bake throws.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "io_test_helpers.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::io {
namespace {

using test::read_bytes;
using test::scratch_folder;

// An 8-bit height map with flat ground (the built-in bumps: a plateau layer with texels in it)
// or with none (noise, the plateau rule alone: the layer is empty).
UnormImage eight_bit_heights(const std::string& set, int size) {
    const Image heights = make_builtin_height(set, size, 3);
    float low = heights.pixels.front(), high = low;
    for (float v : heights.pixels) low = std::min(low, v), high = std::max(high, v);
    UnormImage samples(size, size, 1, 255);
    for (std::size_t i = 0; i < heights.pixels.size(); ++i)
        samples.samples[i] =
            std::uint16_t(std::lround(255.0f * (heights.pixels[i] - low) / (high - low)));
    return samples;
}

BakeSettings settings_for(StoragePolicy storage, SpikeFit fit = SpikeFit::Auto) {
    BakeSettings settings;
    settings.options.strength = 4.0f;
    settings.options.spike_fit = fit;
    settings.storage = storage;
    settings.generator = "leanfade test";
    return settings;
}

// The caller's memory, as a LevelTargetsSink fills it.
struct CallerMemory {
    std::vector<PackedLevel> levels;
    LevelTargetsSink sink() {
        return LevelTargetsSink([this](const PackedLeanMap& layout) {
            levels = layout.levels;
            std::vector<PackedLevelTarget> targets(levels.size());
            const std::size_t texel = bytes_per_texel(layout.storage);
            for (std::size_t l = 0; l < levels.size(); ++l)
                for (const LeanLayerInfo& row : kLeanLayers) {
                    if (!layout.has_layer(row.layer)) continue;
                    std::vector<std::uint8_t>& slice = levels[l].slice(row.layer);
                    slice.assign(std::size_t(levels[l].width) * std::size_t(levels[l].height) *
                                     texel,
                                 0xCD);
                    targets[l].slice(row.layer) = slice.data();
                }
            return targets;
        });
    }
};

TEST(BakeSinks, EverySinkGetsTheSameMap) {
    const std::string folder = scratch_folder();
    struct Case {
        const char* set;
        StoragePolicy storage;
        SpikeFit fit;
    };
    const Case cases[] = {
        {"bumps", {Storage::Unorm16, false}, SpikeFit::Auto},
        {"bumps", {Storage::Unorm16, true}, SpikeFit::Auto},  // --bits auto
        {"bumps", {Storage::Float16, false}, SpikeFit::Auto},
        {"bumps", {Storage::Unorm8, false}, SpikeFit::Plateaus},
        {"noise", {Storage::Unorm16, false}, SpikeFit::Plateaus},  // nothing flat
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(c.set) + " " + to_string(c.storage.storage) +
                     (c.storage.automatic ? " auto" : ""));
        const UnormImage samples = eight_bit_heights(c.set, 64);
        const BakeInput input(samples, BakeSource::Height, "heights.png");
        const BakeSettings settings = settings_for(c.storage, c.fit);

        const PackedBakeResult memory = bake(input, settings);
        ASSERT_EQ(memory.packed.levels.size(), std::size_t(mip_level_count(64, 64)));
        // The flat ground keeps its layer; an empty one leaves the map.
        EXPECT_EQ(memory.packed.has_plateau(), memory.summary.plateau_fraction > 0.0f);
        EXPECT_EQ(memory.packed.has_plateau(), std::string(c.set) == "bumps");
        for (const PackedLevel& level : memory.packed.levels)
            EXPECT_EQ(level.plateau.empty(), !memory.packed.has_plateau());

        // The float samples of the same file bake the same bytes.
        BakeOptions float_options = settings.options;
        float_options.source_max_code = 255;
        const Image floats = samples.to_float();
        const PackedBakeResult from_floats =
            bake(BakeInput(floats, BakeSource::Height, "heights.png"),
                 BakeSettings{float_options, c.storage, settings.generator});
        EXPECT_EQ(write_ktx2_to_memory(from_floats.packed), write_ktx2_to_memory(memory.packed));

        // A file sink writes write_ktx2's bytes of the map in memory.
        const std::string path = folder + "/" + c.set + "_" + to_string(c.storage.storage) +
                                 (c.storage.automatic ? "_auto" : "") + ".ktx2";
        Ktx2FileSink file(path);
        const PackedBakeResult written = bake(input, settings, file);
        EXPECT_TRUE(written.packed.levels.front().lean1.empty());
        EXPECT_EQ(written.packed.storage, memory.packed.storage);
        EXPECT_EQ(written.packed.plateau_epsilon, memory.packed.plateau_epsilon);
        EXPECT_EQ(written.summary.max_slope, memory.summary.max_slope);
        EXPECT_EQ(read_bytes(path), write_ktx2_to_memory(memory.packed));

        // The caller's memory holds the same layers as memory does with the empty plateau
        // layer kept (the caller's buffers are not resized), and without it where it is dropped.
        BakeSettings keep = settings;
        keep.keep_empty_plateau = true;
        const PackedBakeResult kept = bake(input, keep);
        EXPECT_GT(kept.packed.plateau_epsilon, 0.0f);
        CallerMemory caller;
        LevelTargetsSink targets = caller.sink();
        const PackedBakeResult into = bake(input, keep, targets);
        EXPECT_EQ(into.packed.plateau_epsilon, kept.packed.plateau_epsilon);
        ASSERT_EQ(caller.levels.size(), memory.packed.levels.size());
        for (std::size_t l = 0; l < caller.levels.size(); ++l) {
            EXPECT_TRUE(caller.levels[l].lean1 == memory.packed.levels[l].lean1) << l;
            EXPECT_TRUE(caller.levels[l].lean2 == memory.packed.levels[l].lean2) << l;
            EXPECT_TRUE(caller.levels[l].plateau == kept.packed.levels[l].plateau) << l;
            if (memory.packed.has_plateau()) {
                EXPECT_TRUE(caller.levels[l].plateau == memory.packed.levels[l].plateau) << l;
            }
        }
    }
}

TEST(BakeSinks, MapSinkReusesTheBuffersItIsGiven) {
    const UnormImage samples = eight_bit_heights("bumps", 64);
    const BakeInput input(samples, BakeSource::Height);
    const BakeSettings settings = settings_for({Storage::Unorm16, false});
    PackedBakeResult first = bake(input, settings);
    const std::vector<PackedLevel> copy = first.packed.levels;
    const std::uint8_t* lean1 = first.packed.levels.front().lean1.data();
    const std::uint8_t* plateau = first.packed.levels.back().plateau.data();
    PackedMapSink again(std::move(first.packed.levels));
    const PackedBakeResult second = bake(input, settings, again);
    EXPECT_EQ(second.packed.levels.front().lean1.data(), lean1);
    EXPECT_EQ(second.packed.levels.back().plateau.data(), plateau);
    ASSERT_EQ(second.packed.levels.size(), copy.size());
    for (std::size_t l = 0; l < copy.size(); ++l) {
        EXPECT_TRUE(second.packed.levels[l].lean1 == copy[l].lean1) << l;
        EXPECT_TRUE(second.packed.levels[l].plateau == copy[l].plateau) << l;
    }
}

// The float moments of every texel of every level, once, and the map's summary, with no map.
TEST(BakeSinks, MomentsOnlySinkSeesEveryTexelAndPacksNothing) {
    const UnormImage samples = eight_bit_heights("bumps", 48);
    const BakeInput input(samples, BakeSource::Height);
    const BakeSettings settings = settings_for({Storage::Unorm16, true});
    std::atomic<std::uint64_t> texels{0};
    std::atomic<int> level0_runs{0};
    MomentsOnlySink moments([&](const MomentRun& run) {
        texels += std::uint64_t(run.count);
        if (run.level == 0) ++level0_runs;
        for (int i = 0; i < run.count; ++i) ASSERT_TRUE(std::isfinite(run.mxx[i]));
    });
    const PackedBakeResult result = bake(input, settings, moments);
    std::uint64_t expected = 0;
    for (int w = 48, h = 48;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
        expected += std::uint64_t(w) * std::uint64_t(h);
        if (w == 1 && h == 1) break;
    }
    EXPECT_EQ(texels.load(), expected);
    EXPECT_GT(level0_runs.load(), 0);
    EXPECT_FALSE(result.packed.has_plateau());
    EXPECT_TRUE(std::isnan(result.probe_unorm16_psnr));  // no storage was chosen
    const PackedBakeResult memory = bake(input, settings);
    EXPECT_FLOAT_EQ(result.summary.max_slope, memory.summary.max_slope);
    EXPECT_FLOAT_EQ(result.summary.mean_slope, memory.summary.mean_slope);
}

// Bad samples: the error names the input, and the file sink leaves nothing at its path.
TEST(BakeSinks, NothingAppearsWhenTheBakeThrows) {
    const std::string folder = scratch_folder();
    Image heights(16, 16, 1, 0.25f);
    heights.pixels[37] = std::numeric_limits<float>::quiet_NaN();
    const std::string path = folder + "/never.ktx2";
    Ktx2FileSink file(path);
    try {
        bake(BakeInput(heights, BakeSource::Height, "bad.exr"), settings_for({Storage::Unorm16}),
             file);
        FAIL() << "a NaN height was baked";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "bad.exr") << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder))
        ++entries;
    EXPECT_EQ(entries, 0u);
}

}  // namespace
}  // namespace leanfade::io
