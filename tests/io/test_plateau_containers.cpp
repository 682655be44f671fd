// The plateau layer of two-lobe LEAN in the LEAN map containers (docs/ktx2.md): a third KTX2
// array layer, a third PNG of the pair; maps written without it (older versions) load without it.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>

#include "io_test_helpers.hpp"
#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/png_io.hpp"

namespace leanfade::io {
namespace {

using test::expect_error;
using test::read_bytes;
using test::scratch_folder;
using test::u32_le;
using test::write_bytes;

constexpr std::size_t kLayerCountOffset = 32;

PackedLeanMap bumps_map(Storage storage, int size = 32) {
    BakeOptions options;
    options.strength = 4.0f;
    return bake_packed(make_builtin_height("bumps", size, 2), BakeSource::Height, options, storage,
                       "leanfade test")
        .packed;
}

void expect_same_layers(const PackedLeanMap& a, const PackedLeanMap& b) {
    ASSERT_EQ(a.levels.size(), b.levels.size());
    EXPECT_EQ(a.plateau_epsilon, b.plateau_epsilon);
    for (std::size_t l = 0; l < a.levels.size(); ++l) {
        EXPECT_TRUE(a.levels[l].lean1 == b.levels[l].lean1) << "level " << l;
        EXPECT_TRUE(a.levels[l].lean2 == b.levels[l].lean2) << "level " << l;
        EXPECT_TRUE(a.levels[l].plateau == b.levels[l].plateau) << "level " << l;
    }
}

TEST(PlateauContainers, Ktx2HoldsTheLayerAsAThirdArrayLayerBitForBit) {
    const std::string folder = scratch_folder();
    for (Storage storage : {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
        const PackedLeanMap map = bumps_map(storage);
        ASSERT_TRUE(map.has_plateau());
        const std::string path = folder + "/map.ktx2";
        write_ktx2(path, map);
        const std::vector<std::uint8_t> bytes = read_bytes(path);
        EXPECT_EQ(u32_le(bytes, kLayerCountOffset), 3u);
        const Ktx2Info info = inspect_ktx2(path);
        ASSERT_NE(info.find(kLayoutKey), nullptr);
        // Float maps store signed values: layout version 2 (docs/ktx2.md).
        EXPECT_EQ(*info.find(kLayoutKey), storage == Storage::Float16 || storage == Storage::Float32
                                              ? kLeanSignedPlateauLayoutName
                                              : kLeanPlateauLayoutName);
        ASSERT_NE(info.find(kPlateauEpsilonKey), nullptr);
        const PackedLeanMap read = read_ktx2(path);
        expect_same_layers(read, map);
        EXPECT_TRUE(write_ktx2_to_memory(map) == bytes) << "in memory and on disk alike";
        expect_same_layers(read_ktx2_from_memory(bytes, "memory"), map);
    }
}

// The layer table (kLeanLayers) orders the containers: the KTX2 file's array layers of each level
// are the map's slices in the table's order, the first layer_count() rows, and a PNG pair's
// files are named and tagged by the rows' names.
TEST(PlateauContainers, LayersFollowTheLayerTable) {
    const std::string folder = scratch_folder();
    PackedLeanMap map = bumps_map(Storage::Unorm16);
    ASSERT_TRUE(map.has_plateau());
    EXPECT_EQ(map.layer_count(), int(kLeanLayerCount));
    for (const LeanLayerInfo& row : kLeanLayers) EXPECT_TRUE(map.has_layer(row.layer));
    const std::string path = folder + "/table.ktx2";
    write_ktx2(path, map);  // no supercompression: the layers lie in the file as they are
    const std::vector<std::uint8_t> bytes = read_bytes(path);
    const Ktx2Info info = inspect_ktx2(path);
    ASSERT_EQ(info.levels.size(), map.levels.size());
    for (std::size_t l = 0; l < map.levels.size(); ++l) {
        const std::size_t layer_bytes = map.levels[l].lean1.size();
        for (std::size_t i = 0; i < kLeanLayerCount; ++i) {
            const std::vector<std::uint8_t>& slice = map.levels[l].slice(kLeanLayers[i].layer);
            ASSERT_EQ(slice.size(), layer_bytes);
            const auto first = bytes.begin() + std::ptrdiff_t(info.levels[l].byte_offset +
                                                              i * layer_bytes);
            EXPECT_TRUE(std::equal(slice.begin(), slice.end(), first))
                << "level " << l << ", " << kLeanLayers[i].name;
        }
    }
    remove_plateau_layer(map);
    EXPECT_EQ(map.layer_count(), 2);
    EXPECT_FALSE(map.has_layer(LeanLayer::Plateau));
    EXPECT_TRUE(map.has_layer(LeanLayer::Lean1) && map.has_layer(LeanLayer::Lean2));
}

TEST(PlateauContainers, MapsWithoutTheLayerStayTwoLayerFilesAndLoadWithoutIt) {
    const std::string folder = scratch_folder();
    PackedLeanMap map = bumps_map(Storage::Unorm16);
    remove_plateau_layer(map);
    const std::string path = folder + "/old.ktx2";
    write_ktx2(path, map);
    const std::vector<std::uint8_t> bytes = read_bytes(path);
    EXPECT_EQ(u32_le(bytes, kLayerCountOffset), 2u);
    EXPECT_EQ(*inspect_ktx2(path).find(kLayoutKey), kLeanLayoutName);
    EXPECT_EQ(inspect_ktx2(path).find(kPlateauEpsilonKey), nullptr);
    const PackedLeanMap read = read_ktx2(path);
    EXPECT_FALSE(read.has_plateau());
    EXPECT_TRUE(unpack_plateau_layer(read).empty());
    for (const PackedLevel& level : read.levels) EXPECT_TRUE(level.plateau.empty());
}

TEST(PlateauContainers, Ktx2LayerCountMustMatchTheLayout) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/bad.ktx2";
    PackedLeanMap two = bumps_map(Storage::Unorm16, 8);
    remove_plateau_layer(two);
    std::vector<std::uint8_t> bytes = write_ktx2_to_memory(two);
    // A two-layer file that says it has three layers: the level lengths no longer match.
    std::vector<std::uint8_t> patched = bytes;
    patched[kLayerCountOffset] = 3;
    write_bytes(path, patched);
    expect_error([&] { read_ktx2(path); }, path, "byteLength");
    // A three-layer file whose layout is renamed to the two-layer one.
    const PackedLeanMap three = bumps_map(Storage::Unorm16, 8);
    patched = write_ktx2_to_memory(three);
    const std::string from = kLeanPlateauLayoutName;
    const auto at = std::search(patched.begin(), patched.end(), from.begin(), from.end());
    ASSERT_NE(at, patched.end());
    // "lean1,lean2,plateau v1" -> "lean1,lean2 v1" padded with NULs is not valid text; instead
    // change one character so the layout is unknown.
    *(at + 12) = 'X';
    write_bytes(path, patched);
    expect_error([&] { read_ktx2(path); }, path, "LEANFADElayout");
    // A missing or bad epsilon key.
    PackedLeanMap bad = three;
    bad.plateau_epsilon = -1.0f;
    expect_error([&] { write_ktx2(folder + "/never.ktx2", bad); }, folder + "/never.ktx2",
                 "plateau epsilon");
    bad = three;
    bad.levels[0].plateau.pop_back();
    expect_error([&] { write_ktx2(folder + "/never.ktx2", bad); }, folder + "/never.ktx2",
                 "plateau layer");
}

TEST(PlateauContainers, PngPairWritesAThirdFileAndLoadsTheLayerBack) {
    const std::string folder = scratch_folder();
    for (Storage storage : {Storage::Unorm8, Storage::Unorm16}) {
        const PackedLeanMap map = bumps_map(storage);
        const std::string base = folder + "/map";
        write_lean_png_pair(base + ".lean1.png", base + ".lean2.png", map, {},
                            base + ".plateau.png");
        for (const char* name : {".lean1.png", ".lean2.png", ".plateau.png"}) {
            const PackedLeanMap read = read_lean_png_pair(base + name);
            ASSERT_TRUE(read.has_plateau());
            EXPECT_EQ(read.plateau_epsilon, map.plateau_epsilon);
            // The finest level as written; the chain rebuilt by filtering the stored values.
            EXPECT_TRUE(read.levels[0].plateau == map.levels[0].plateau);
            const std::vector<Image> want = unpack_plateau_layer(map);
            const std::vector<Image> got = unpack_plateau_layer(read);
            ASSERT_EQ(got.size(), want.size());
            const float q = storage == Storage::Unorm8 ? 255.0f : 65535.0f;
            const float sc = map.scale;
            const float step[4] = {1.0f / q, 2.0f * sc / q, 2.0f * sc / q, 2.0f * sc * sc / q};
            for (std::size_t l = 0; l < got.size(); ++l)
                for (std::size_t i = 0; i < got[l].pixels.size(); ++i)
                    ASSERT_NEAR(got[l].pixels[i], want[l].pixels[i], 1.01f * step[i % 4])
                        << to_string(storage) << " level " << l;
        }
        // Without the layer's file the pair is refused (its layout names the layer) ...
        std::filesystem::remove(base + ".plateau.png");
        expect_error([&] { read_lean_png_pair(base + ".lean1.png"); }, base + ".plateau.png", "");
        // ... and a pair written without the layer loads without it.
        PackedLeanMap old = map;
        remove_plateau_layer(old);
        write_lean_png_pair(base + ".lean1.png", base + ".lean2.png", old);
        EXPECT_FALSE(read_lean_png_pair(base + ".lean1.png").has_plateau());
        // A map with the layer needs the third path.
        expect_error([&] { write_lean_png_pair(base + ".a.png", base + ".b.png", map); },
                     base + ".a.png", "plateau");
    }
}

}  // namespace
}  // namespace leanfade::io
