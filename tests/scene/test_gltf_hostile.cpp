// Hostile glTF files given to load_gltf (docs/robustness.md, "glTF scenes"): required
// extensions, nesting depth, object counts, images and instances within their budgets. Each file
// is made by the test.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"
#include "test_gltf_builder.hpp"

namespace leanfade::scene {
namespace {

using nlohmann::json;
using test::GltfStorage;
using test::GltfTestFile;

std::vector<std::uint8_t> flat_normal_png() {
    std::vector<float> pixels;
    for (int i = 0; i < 8 * 8; ++i)
        for (float c : {0.6f, 0.5f, 0.9f}) pixels.push_back(c);
    return test::png_bytes(8, 8, 3, pixels);
}

// One quad with a normal-mapped material.
GltfTestFile quad_file() {
    GltfTestFile file;
    file.images = {flat_normal_png()};
    file.materials = {{"m", glm::vec4(1.0f), -1, 0, 1.0f}};
    file.meshes = {{test::unit_quad(0)}};
    return file;
}

std::vector<std::uint8_t> text_bytes(const json& root) {
    const std::string text = root.dump();
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

// The cause of load_gltf_from_memory's refusal ("" when it loads).
std::string refusal(const std::vector<std::uint8_t>& bytes, const GltfLoadOptions& options = {}) {
    try {
        load_gltf_from_memory(bytes, "scene.gltf", options);
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "scene.gltf");
        return e.cause();
    }
    return {};
}

std::string refusal(const json& root, const GltfLoadOptions& options = {}) {
    return refusal(text_bytes(root), options);
}

TEST(GltfHostile, RequiredExtensionsLeanfadeDoesNotSupportAreRefusedByName) {
    for (const std::string extension : {"KHR_materials_clearcoat", "KHR_mesh_quantization",
                                        "KHR_draco_mesh_compression", "EXT_never_heard_of"}) {
        json root = test::build_gltf(quad_file(), GltfStorage::Embedded, "").json;
        root["extensionsUsed"] = {extension};
        EXPECT_EQ(refusal(root), "") << "only used: " << extension;
        root["extensionsRequired"] = {extension};
        const std::string cause = refusal(root);
        EXPECT_NE(cause.find("requires the extension '" + extension + "'"), std::string::npos)
            << cause;
        EXPECT_NE(cause.find("does not support"), std::string::npos) << cause;
    }
    // Malformed lists.
    json root = test::build_gltf(quad_file(), GltfStorage::Embedded, "").json;
    root["extensionsRequired"] = "KHR_texture_transform";
    EXPECT_NE(refusal(root).find("'extensionsRequired' is not an array"), std::string::npos);
    root["extensionsRequired"] = {1};
    EXPECT_NE(refusal(root).find("not a name"), std::string::npos);
    root["extensionsRequired"] = json::array();
    EXPECT_EQ(refusal(root), "");
    // What leanfade draws may be required (kSupportedGltfExtensions).
    root["extensionsUsed"] = {"KHR_texture_transform"};
    root["extensionsRequired"] = {"KHR_texture_transform"};
    EXPECT_EQ(refusal(root), "");
}

// `levels` arrays or objects, one inside the other, around a 1.
std::string nested(int levels, bool objects) {
    std::string deep;
    for (int i = 0; i < levels; ++i) deep += objects ? "{\"a\":" : "[";
    deep += "1";
    for (int i = 0; i < levels; ++i) deep += objects ? "}" : "]";
    return deep;
}

// The JSON text of `root` with its string value "@DEEP@" replaced by `deep`.
std::string replace_marker(const json& root, const std::string& deep) {
    std::string text = root.dump();
    const std::string marker = "\"@DEEP@\"";
    text.replace(text.find(marker), marker.size(), deep);
    return text;
}

// asset.extras (or a material's extension) nested `levels` deep.
std::vector<std::uint8_t> with_deep_value(int levels, bool objects, bool in_material) {
    json root = test::build_gltf(quad_file(), GltfStorage::Embedded, "").json;
    if (in_material)
        root["materials"][0]["extensions"]["EXT_x"] = "@DEEP@";
    else
        root["asset"]["extras"] = "@DEEP@";
    const std::string text = replace_marker(root, nested(levels, objects));
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

TEST(GltfHostile, JsonNestedDeeperThanTheLimitIsRefusedBeforeParsing) {
    // asset.extras sits at depth 2 (the root object, asset), a material's extension value at
    // depth 4 (root, materials, the material, extensions).
    for (bool objects : {false, true}) {
        EXPECT_EQ(refusal(with_deep_value(kMaxGltfJsonDepth - 2, objects, false)), "");
        EXPECT_EQ(refusal(with_deep_value(kMaxGltfJsonDepth - 4, objects, true)), "");
        for (int levels : {kMaxGltfJsonDepth - 1, 1000, 30000, 200000}) {
            for (bool in_material : {false, true}) {
                const std::string cause = refusal(with_deep_value(levels, objects, in_material));
                EXPECT_EQ(cause, "the JSON nests deeper than " + std::to_string(kMaxGltfJsonDepth) +
                                     " levels of arrays and objects")
                    << levels;
            }
        }
    }
    // Brackets inside strings (with escaped quotes) do not count.
    json root = test::build_gltf(quad_file(), GltfStorage::Embedded, "").json;
    root["asset"]["extras"] = std::string(100000, '[') + "\"\\" + std::string(100000, '{');
    EXPECT_EQ(refusal(root), "");
    // A GLB's JSON chunk is checked alike.
    const test::GltfTestOutput out = test::build_gltf(quad_file(), GltfStorage::Binary, "");
    json marked = out.json;
    marked["asset"]["extras"] = "@DEEP@";
    std::string text = replace_marker(marked, nested(30000, false));
    while (text.size() % 4 != 0) text += ' ';
    std::vector<std::uint8_t> glb;
    const auto u32 = [&](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) glb.push_back(std::uint8_t(v >> (8 * i)));
    };
    for (char c : {'g', 'l', 'T', 'F'}) glb.push_back(std::uint8_t(c));
    u32(2);
    u32(std::uint32_t(12 + 8 + text.size() + 8 + out.bin.size()));
    u32(std::uint32_t(text.size()));
    u32(0x4E4F534Au);  // JSON
    glb.insert(glb.end(), text.begin(), text.end());
    u32(std::uint32_t(out.bin.size()));
    u32(0x004E4942u);  // BIN
    glb.insert(glb.end(), out.bin.begin(), out.bin.end());
    EXPECT_NE(refusal(glb).find("nests deeper than"), std::string::npos);
}

TEST(GltfHostile, TopLevelArraysLongerThanTheirLimitsAreRefused) {
    for (const GltfArrayLimit& limit : kGltfArrayLimits) {
        json root = test::build_gltf(quad_file(), GltfStorage::Embedded, "").json;
        json& array = root[std::string(limit.key)];
        array = json::array();
        for (std::size_t i = 0; i <= limit.max_elements; ++i) array.push_back(json::object());
        // Appended piece by piece: "'" + std::string trips GCC 12's -Wrestrict false positive.
        std::string expected = "'";
        expected += limit.key;
        expected += "' has " + std::to_string(limit.max_elements + 1) +
                    " elements, more than the limit of " + std::to_string(limit.max_elements);
        EXPECT_EQ(refusal(root), expected) << limit.key;
    }
    json root = test::build_gltf(quad_file(), GltfStorage::Embedded, "").json;
    json& primitives = root["meshes"][0]["primitives"];
    while (primitives.size() <= kMaxGltfPrimitivesPerMesh) primitives.push_back(primitives[0]);
    EXPECT_NE(refusal(root).find("mesh 0 has 4097 primitives, more than the limit of 4096"),
              std::string::npos);
}

TEST(GltfHostile, OnlyImagesAMaterialUsesAreKeptWithinTheBudget) {
    // 200 images naming one buffer view of the image; only image 0 is used.
    test::GltfTestOutput out = test::build_gltf(quad_file(), GltfStorage::Binary, "");
    const json image = out.json["images"][0];
    for (int i = 0; i < 200; ++i) out.json["images"].push_back(image);
    const std::vector<std::uint8_t> glb = test::pack_glb(out.json, out.bin);
    const std::size_t image_bytes = quad_file().images[0].size();
    GltfLoadOptions options;
    options.max_image_bytes = 2 * image_bytes;  // room for the used one only
    const GltfScene scene = load_gltf_from_memory(glb, "scene.glb", options);
    ASSERT_EQ(scene.images.size(), 1u);
    EXPECT_EQ(scene.images[0].bytes, quad_file().images[0]);
    // Ten materials, each with its own texture of its own image (all the same view): the
    // budget counts each copy.
    out = test::build_gltf(quad_file(), GltfStorage::Binary, "");
    for (int i = 1; i < 10; ++i) {
        out.json["images"].push_back(image);
        out.json["textures"].push_back({{"source", i}});
        json material = out.json["materials"][0];
        material["normalTexture"]["index"] = i;
        out.json["materials"].push_back(material);
    }
    options.max_image_bytes = 5 * image_bytes;
    const std::string cause = refusal(test::pack_glb(out.json, out.bin), options);
    EXPECT_NE(cause.find("image 5: the images the materials use exceed the limit of " +
                         std::to_string(5 * image_bytes) + " bytes"),
              std::string::npos)
        << cause;
    options.max_image_bytes = 10 * image_bytes;
    EXPECT_EQ(refusal(test::pack_glb(out.json, out.bin), options), "");
}

TEST(GltfHostile, InstancesCountTheirIndicesBeforeTheyAreCopied) {
    // A 3-vertex strip of 30000 indices (29998 triangles), instanced by 100 nodes.
    GltfTestFile file = quad_file();
    test::GltfTestPrimitive strip = test::unit_quad(0);
    strip.positions.resize(3);
    strip.normals.resize(3);
    strip.uvs.resize(3);
    strip.indices.clear();
    for (int i = 0; i < 30000; ++i) strip.indices.push_back(std::uint32_t(i % 3));
    strip.mode = 5;
    file.meshes = {{strip}};
    for (int n = 0; n < 100; ++n) file.nodes.push_back({0, {}, {}, {double(n), 0, 0}, {}});
    const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    const std::vector<std::uint8_t> glb = test::pack_glb(out.json, out.bin);
    GltfLoadOptions options;
    options.max_indices = 50 * 29998 * 3;
    const std::string cause = refusal(glb, options);
    EXPECT_NE(cause.find("more than " + std::to_string(options.max_indices) +
                         " triangle indices in the scene"),
              std::string::npos)
        << cause;
    options.max_indices = 100 * 29998 * 3;
    EXPECT_EQ(refusal(glb, options), "");
}

// ---- Bakes a scene asks for, and the LEAN-map cache ------------------------------------------

TEST(GltfHostile, OneImageBakesAtMostFourScales) {
    GltfTestFile file = quad_file();
    file.materials.clear();
    file.meshes.clear();
    for (int m = 0; m < 5; ++m) {
        std::string name = "m";
        name += std::to_string(m);  // not "m" + ...: GCC 12's -Wrestrict misfires on it here
        file.materials.push_back({name, glm::vec4(1.0f), -1, 0, 1.0f - 0.1f * float(m)});
        file.meshes.push_back({test::unit_quad(m)});
    }
    const std::string cause =
        refusal(test::pack_glb(test::build_gltf(file, GltfStorage::Binary, "").json,
                               test::build_gltf(file, GltfStorage::Binary, "").bin));
    EXPECT_NE(cause.find("normal texture of 5 different scales, more than the limit of 4"),
              std::string::npos)
        << cause;
    file.materials[4].normal_scale = file.materials[0].normal_scale;  // 4 different scales
    const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    EXPECT_EQ(refusal(test::pack_glb(out.json, out.bin)), "");
}

TEST(GltfHostile, RenderSceneHoldsLeanMapsWithinItsBudget) {
    GltfTestFile file = quad_file();
    file.materials.push_back({"n", glm::vec4(1.0f), -1, 0, 0.5f});
    file.meshes.push_back({test::unit_quad(1)});
    const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    const GltfScene scene = load_gltf_from_memory(test::pack_glb(out.json, out.bin), "s.glb");
    GltfBakeSettings settings;
    const Scene whole = make_render_scene(scene, settings);
    std::uint64_t one = 0;
    for (const PackedLevel& level : whole.lean_maps[0].levels)
        one += level.lean1.size() + level.lean2.size();
    settings.max_lean_map_bytes = 2 * one;
    EXPECT_NO_THROW(make_render_scene(scene, settings));
    settings.max_lean_map_bytes = 2 * one - 1;
    try {
        make_render_scene(scene, settings);
        ADD_FAILURE() << "the budget was not applied";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("LEAN maps of its normal textures exceed"),
                  std::string::npos)
            << e.what();
    }
}

// Entries of a cache folder, by file name.
std::vector<std::string> cache_files(const std::filesystem::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
        names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

TEST(LeanMapCacheBounds, EntriesAreVerifiedAgainstTheirKey) {
    namespace fs = std::filesystem;
    const fs::path folder = test::fresh_test_folder("gltf_hostile", "cache_verify");
    const test::GltfTestOutput out = test::build_gltf(quad_file(), GltfStorage::Binary, "");
    const GltfScene scene = load_gltf_from_memory(test::pack_glb(out.json, out.bin), "s.glb");
    GltfBakeSettings settings;
    settings.cache_folder = folder.string();
    bool cached = true;
    const PackedLeanMap baked = bake_normal_texture(scene, 0, 1.0f, settings, &cached);
    EXPECT_FALSE(cached);
    ASSERT_EQ(cache_files(folder).size(), 1u);
    const std::string key = fs::path(cache_files(folder)[0]).stem().string();
    const LeanMapCache cache(folder.string());
    // The entry as stored: the map baked, its writer string as the bake's.
    std::optional<PackedLeanMap> found = cache.find(key, baked.storage);
    ASSERT_TRUE(found.has_value());
    EXPECT_EQ(found->generator, baked.generator);
    EXPECT_EQ(found->levels[0].lean1, baked.levels[0].lean1);
    EXPECT_FALSE(cache.find(key, Storage::Float32).has_value()) << "another storage";
    // An entry under another key's name (copied, renamed, or written by something else) is not
    // used, and is baked again over.
    const std::string other = lean_cache_key(scene.images[0].bytes, "something else");
    fs::copy_file(cache.entry_path(key), cache.entry_path(other));
    EXPECT_FALSE(cache.find(other).has_value());
    // A plain write_ktx2 of the map (no key recorded) is not used either.
    io::write_ktx2(cache.entry_path(other), baked);
    EXPECT_FALSE(cache.find(other).has_value());
    // A corrupt entry is baked again.
    { std::ofstream(cache.entry_path(key), std::ios::binary | std::ios::trunc) << "KTX"; }
    EXPECT_EQ(bake_normal_texture(scene, 0, 1.0f, settings, &cached).levels[0].lean1,
              baked.levels[0].lean1);
    EXPECT_FALSE(cached);
    bake_normal_texture(scene, 0, 1.0f, settings, &cached);
    EXPECT_TRUE(cached);
}

TEST(LeanMapCacheBounds, FileEntriesAreCopiedOnlyWhenWholeAndOfTheirSize) {
    namespace fs = std::filesystem;
    const fs::path folder = test::fresh_test_folder("gltf_hostile", "cache_copy");
    const LeanMapCache cache((folder / "cache").string());
    const std::string source = (folder / "made.bin").string();
    const std::string text = "the bytes of an output";
    { std::ofstream(source, std::ios::binary) << text; }
    const std::string key = lean_cache_key({1, 2, 3}, "copy test");
    EXPECT_EQ(cache.store_file_copy(key, ".out.bin", source, text.size()), "");
    const auto copy_to = [&](const std::string& suffix, std::uint64_t size) {
        const std::string out = (folder / "copy.bin").string();
        fs::remove(out);
        io::AtomicFile file(out);
        if (!cache.copy_file_to(key, suffix, size, file)) return std::optional<std::string>{};
        file.commit();
        std::ifstream in(out, std::ios::binary);
        return std::optional<std::string>(std::string(std::istreambuf_iterator<char>(in), {}));
    };
    EXPECT_EQ(copy_to(".out.bin", text.size()), text);
    EXPECT_EQ(cache.find_file(key, ".out.bin"), std::vector<std::uint8_t>(text.begin(), text.end()));
    // Another size than the caller expects (cut short, or another entry's), missing, an unsafe
    // suffix: not copied, and the output is left as it was.
    EXPECT_FALSE(copy_to(".out.bin", text.size() + 1).has_value());
    EXPECT_FALSE(copy_to(".other.bin", text.size()).has_value());
    EXPECT_FALSE(copy_to("/../x", text.size()).has_value());
    EXPECT_NE(cache.store_file_copy(key, "/../x", source, text.size()), "");
    // A source of another size than said is not stored.
    EXPECT_NE(cache.store_file_copy(key, ".short.bin", source, text.size() + 5), "");
    EXPECT_FALSE(copy_to(".short.bin", text.size() + 5).has_value());
    // A symbolic link in the cache is not followed.
    fs::create_symlink(source, folder / "cache" / (key + ".link.bin"));
    EXPECT_FALSE(copy_to(".link.bin", text.size()).has_value());
    // A disabled cache copies and stores nothing.
    const LeanMapCache disabled("");
    io::AtomicFile file((folder / "never.bin").string());
    EXPECT_FALSE(disabled.copy_file_to(key, ".out.bin", text.size(), file));
    EXPECT_EQ(disabled.store_file_copy(key, ".out.bin", source, text.size()), "");
}

TEST(LeanMapCacheBounds, LinkedEntriesAreServedOnlyWithTheirHash) {
    namespace fs = std::filesystem;
    const fs::path folder = test::fresh_test_folder("gltf_hostile", "cache_link");
    const LeanMapCache cache((folder / "cache").string());
    const std::string source = (folder / "made.bin").string();
    const std::string text = "the bytes of a batch output";
    { std::ofstream(source, std::ios::binary) << text; }
    const std::string sha = sha256_file_hex(source);
    const std::string key = lean_cache_key({4, 5, 6}, "link test");
    EXPECT_EQ(cache.store_file_link(key, ".out.bin", source, text.size()), "");
    const fs::path entry = folder / "cache" / (key + ".out.bin");
    // The same file system: a hard link, no copy.
    EXPECT_TRUE(fs::equivalent(entry, source));
    const std::string out = (folder / "served.bin").string();
    const auto read = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_TRUE(cache.serve_file_to(key, ".out.bin", text.size(), sha, out));
    EXPECT_EQ(read(out), text);
    // Another hash or size than recorded, missing, an unsafe suffix: not served, the output
    // left as it was.
    // (A new file: `out` is the entry's hard link, and writing it in place would change both.)
    fs::remove(out);
    { std::ofstream(out, std::ios::binary) << "old"; }
    EXPECT_FALSE(cache.serve_file_to(key, ".out.bin", text.size(), std::string(64, '0'), out));
    EXPECT_FALSE(cache.serve_file_to(key, ".out.bin", text.size() + 1, sha, out));
    EXPECT_FALSE(cache.serve_file_to(key, ".none.bin", text.size(), sha, out));
    EXPECT_FALSE(cache.serve_file_to(key, "/../x", text.size(), sha, out));
    EXPECT_EQ(read(out), "old");
    // An entry damaged where it lies is not served.
    { std::ofstream(entry, std::ios::binary | std::ios::in | std::ios::out) << "X"; }
    EXPECT_FALSE(cache.serve_file_to(key, ".out.bin", text.size(), sha, out));
    EXPECT_EQ(read(out), "old");
    // No temporary is left beside the output or in the cache.
    for (const fs::path& dir : {folder, folder / "cache"})
        for (const auto& file : fs::directory_iterator(dir))
            EXPECT_EQ(file.path().filename().string().find(".tmp-"), std::string::npos)
                << file.path();
    // A source of another size than said is not stored.
    EXPECT_NE(cache.store_file_link(key, ".short.bin", source, text.size() + 5), "");
    const LeanMapCache disabled("");
    EXPECT_EQ(disabled.store_file_link(key, ".out.bin", source, text.size()), "");
    EXPECT_FALSE(disabled.serve_file_to(key, ".out.bin", text.size(), sha, out));
}

TEST(LeanMapCacheBounds, EntriesKeepTheMapsMetadata) {
    // Every field of the metadata comes back from an entry as stored, none at its default.
    namespace fs = std::filesystem;
    const fs::path folder = test::fresh_test_folder("gltf_hostile", "cache_metadata");
    PackedLeanMap map;
    map.storage = Storage::Unorm8;
    map.scale = 3.5f;
    map.roughness_baked = true;
    map.baked_shininess = 40.0f;
    map.source_convention = NormalConvention::DirectX;
    map.normal_repairs = {3, 5};
    map.source_looks_flipped = true;
    map.generator = "leanfade test";
    for (const int size : {2, 1}) {
        const auto bytes = std::size_t(size * size * bytes_per_texel(map.storage));
        map.levels.push_back({size, size, std::vector<std::uint8_t>(bytes, 0x40),
                              std::vector<std::uint8_t>(bytes, 0x80), {}});
    }
    const LeanMapCache cache(folder.string());
    const std::string key = lean_cache_key({1, 2, 3}, "metadata");
    ASSERT_EQ(cache.store(key, map), "");
    const std::optional<PackedLeanMap> found = cache.find(key, map.storage);
    ASSERT_TRUE(found.has_value());
    const PackedLeanMapMetadata& m = found->metadata();
    EXPECT_EQ(m.storage, map.storage);
    EXPECT_EQ(m.scale, map.scale);
    EXPECT_EQ(m.roughness_baked, map.roughness_baked);
    EXPECT_EQ(m.baked_shininess, map.baked_shininess);
    EXPECT_EQ(m.source_convention, map.source_convention);
    EXPECT_EQ(m.normal_repairs.padding_texels, 3u);
    EXPECT_EQ(m.normal_repairs.raised_texels, 5u);
    EXPECT_EQ(m.source_looks_flipped, map.source_looks_flipped);
    EXPECT_EQ(m.generator, map.generator);
    ASSERT_EQ(found->levels.size(), map.levels.size());
    for (std::size_t l = 0; l < map.levels.size(); ++l) {
        EXPECT_EQ(found->levels[l].lean1, map.levels[l].lean1) << l;
        EXPECT_EQ(found->levels[l].lean2, map.levels[l].lean2) << l;
    }
}

TEST(LeanMapCacheBounds, TheFolderIsBoundedOldestFirstAndStaleTemporariesGo) {
    namespace fs = std::filesystem;
    const fs::path folder = test::fresh_test_folder("gltf_hostile", "cache_bound");
    const test::GltfTestOutput out = test::build_gltf(quad_file(), GltfStorage::Binary, "");
    const GltfScene scene = load_gltf_from_memory(test::pack_glb(out.json, out.bin), "s.glb");
    GltfBakeSettings settings;
    settings.cache_folder = folder.string();
    bake_normal_texture(scene, 0, 1.0f, settings);
    const std::uintmax_t entry = fs::file_size(folder / cache_files(folder)[0]);
    settings.max_cache_bytes = 3 * entry;  // room for three entries (all of one size)
    // Five bakes, each entry made older than the next: the oldest go first, the newest stays.
    std::vector<std::string> order = {cache_files(folder)[0]};
    const auto start = fs::file_time_type::clock::now() - std::chrono::hours(10);
    fs::last_write_time(folder / order[0], start);
    for (int i = 1; i < 5; ++i) {
        const std::vector<std::string> before = cache_files(folder);
        bake_normal_texture(scene, 0, 1.0f - 0.1f * float(i), settings);
        for (const std::string& name : cache_files(folder))
            if (std::find(before.begin(), before.end(), name) == before.end()) {
                order.push_back(name);
                fs::last_write_time(folder / name, start + std::chrono::hours(i));
            }
        std::uintmax_t total = 0;
        for (const std::string& name : cache_files(folder)) total += fs::file_size(folder / name);
        EXPECT_LE(total, settings.max_cache_bytes) << i;
    }
    ASSERT_EQ(order.size(), 5u);
    std::vector<std::string> newest(order.begin() + 2, order.end());
    std::sort(newest.begin(), newest.end());
    EXPECT_EQ(cache_files(folder), newest);
    // Temporaries: of a dead process (removed), a day old (removed), this process's fresh one
    // (kept); the first use of the cache cleans.
    const std::string base = (folder / newest[0]).string();
    const std::string id = "-" + io::temporary_run_id();
    const std::string dead = base + ".tmp-999999999-0" + id;
    const std::string old = base + ".tmp-" + std::to_string(::getpid()) + "-90" + id;
    const std::string fresh = base + ".tmp-" + std::to_string(::getpid()) + "-91" + id;
    for (const std::string& name : {dead, old, fresh}) std::ofstream(name) << "x";
    fs::last_write_time(old, fs::file_time_type::clock::now() - std::chrono::hours(25));
    const LeanMapCache cache(folder.string(), settings.max_cache_bytes);
    EXPECT_FALSE(cache.find("0000").has_value());
    EXPECT_FALSE(fs::exists(dead));
    EXPECT_FALSE(fs::exists(old));
    EXPECT_TRUE(fs::exists(fresh));
}

}  // namespace
}  // namespace leanfade::scene
