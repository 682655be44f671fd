// glTF scenes for the renderer (make_render_scene, bake_normal_texture; leanfade/scene/gltf.hpp)
// and the LEAN-map cache (leanfade/scene/detail/lean_map_cache.hpp).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <span>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"
#include "test_gltf_builder.hpp"

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;
using test::GltfStorage;
using test::GltfTestFile;

fs::path gltf_scene_folder(const std::string& name) { return test::fresh_test_folder("gltf_scene", name); }

// A uniform normal map of the unit normal n (encoded 0.5 n + 0.5), 8x8 texels, 8-bit RGB.
std::vector<std::uint8_t> uniform_normal_png(glm::vec3 n) {
    n = glm::normalize(n);
    std::vector<float> pixels;
    for (int i = 0; i < 64; ++i)
        for (int c = 0; c < 3; ++c) pixels.push_back(0.5f * n[c] + 0.5f);
    return test::png_bytes(8, 8, 3, pixels);
}

// The quad of test_gltf_builder (uv = (x, 1 - y) in glTF's convention: the image's top row lies
// at y = 1) with a normal texture, a second quad with a base colour texture.
GltfTestFile textured_file(glm::vec3 normal, float scale = 1.0f) {
    GltfTestFile file;
    file.images.push_back(uniform_normal_png(normal));
    // sRGB 0.5 -> linear 0.214; a gray + alpha PNG would do too, RGB here.
    file.images.push_back(test::png_bytes(2, 1, 3, {0.5f, 0.5f, 0.5f, 1.0f, 0.0f, 0.0f}));
    file.materials.push_back({"bumpy", glm::vec4(1.0f), -1, 0, scale});
    file.materials.push_back({"painted", glm::vec4(0.5f, 1.0f, 1.0f, 1.0f), 1, -1, 1.0f});
    file.meshes = {{test::unit_quad(0)}, {test::unit_quad(1)}};
    return file;
}

GltfScene load_textured(const fs::path& dir, glm::vec3 normal, float scale = 1.0f) {
    const std::string path = (dir / "scene.glb").string();
    test::write_gltf(textured_file(normal, scale), path, GltfStorage::Binary);
    return load_gltf(path);
}

// The world-space direction of the filtered bump normal at the quad's centre: T B.x + Bt B.y +
// N with the mean slope B of the coarsest level (the whole map).
glm::vec3 shading_normal(const Scene& scene, int object) {
    const Object& o = scene.objects[std::size_t(object)];
    const LeanMap map = unpack_lean_map(scene.lean_maps[std::size_t(
        scene.materials[std::size_t(o.material)].lean_map)]);
    const glm::vec2 b = map.levels.back().mean[0];
    const Vertex& v = o.mesh.vertices[0];
    const glm::vec3 t(v.tangent);
    const glm::vec3 bitangent = v.tangent.w * glm::cross(v.normal, t);
    return glm::normalize(t * b.x + bitangent * b.y + v.normal);
}

TEST(GltfScene, NormalTextureTiltsTowardItsImageDirections) {
    const fs::path dir = gltf_scene_folder("tilt");
    GltfBakeSettings settings;  // no cache
    // Tilted toward +X of the image (red up): toward +u, the quad's +x.
    {
        const Scene scene = make_render_scene(load_textured(dir, {0.6f, 0.0f, 0.8f}), settings);
        const glm::vec3 n = shading_normal(scene, 0);
        EXPECT_NEAR(n.x, 0.6f, 0.01f);
        EXPECT_NEAR(n.y, 0.0f, 0.01f);
        // A light at +x (object space) sees more of it than a light at -x.
        EXPECT_GT(glm::dot(n, glm::normalize(glm::vec3(1, 0, 1))),
                  glm::dot(n, glm::normalize(glm::vec3(-1, 0, 1))) + 0.5f);
    }
    // Tilted toward +Y (green up: OpenGL's convention, the image's top): the quad's +y, where
    // the image's top row lies (glTF uv (x, 0) at y = 1).
    {
        const Scene scene = make_render_scene(load_textured(dir, {0.0f, 0.6f, 0.8f}), settings);
        const glm::vec3 n = shading_normal(scene, 0);
        EXPECT_NEAR(n.x, 0.0f, 0.01f);
        EXPECT_NEAR(n.y, 0.6f, 0.01f);
    }
}

TEST(GltfScene, NormalScaleMultipliesTheSlopes) {
    const fs::path dir = gltf_scene_folder("scale");
    GltfBakeSettings settings;
    const glm::vec3 n(0.3f, -0.2f, 0.9f);
    const Scene one = make_render_scene(load_textured(dir, n, 1.0f), settings);
    const Scene two = make_render_scene(load_textured(dir, n, 2.0f), settings);
    const glm::vec2 b1 = unpack_lean_map(one.lean_maps[0]).levels.back().mean[0];
    const glm::vec2 b2 = unpack_lean_map(two.lean_maps[0]).levels.back().mean[0];
    EXPECT_NEAR(b1.x, 0.3f / 0.9f, 0.01f);
    EXPECT_NEAR(b1.y, -0.2f / 0.9f, 0.01f);
    EXPECT_NEAR(b2.x, 2.0f * b1.x, 0.01f);
    EXPECT_NEAR(b2.y, 2.0f * b1.y, 0.01f);
}

TEST(GltfScene, MaterialsGetBaseColourFactorAndLinearTexture) {
    const fs::path dir = gltf_scene_folder("colour");
    const Scene scene = make_render_scene(load_textured(dir, {0, 0, 1}), GltfBakeSettings{});
    ASSERT_EQ(scene.materials.size(), 2u);
    ASSERT_EQ(scene.objects.size(), 2u);
    EXPECT_EQ(scene.materials[0].map(MapKind::BaseColor), -1);
    EXPECT_EQ(*scene.materials[1].diffuse, glm::vec3(0.5f, 1.0f, 1.0f));
    ASSERT_EQ(scene.materials[1].map(MapKind::BaseColor), 0);
    ASSERT_EQ(scene.maps_of(MapKind::BaseColor)[0].size(), 1u);  // level 0: the GPU makes MIPs
    const Image& texture = scene.maps_of(MapKind::BaseColor)[0][0];
    ASSERT_EQ(texture.channels, 4);
    ASSERT_EQ(texture.width, 2);
    // 8-bit 128/255 = 0.50196 sRGB -> 0.21586 linear; 255 -> 1; alpha 1 (RGB file).
    EXPECT_NEAR(texture.at(0, 0, 0), 0.21586f, 1e-4f);
    EXPECT_NEAR(texture.at(1, 0, 0), 1.0f, 1e-6f);
    EXPECT_NEAR(texture.at(1, 0, 1), 0.0f, 1e-6f);
    EXPECT_EQ(texture.at(0, 0, 3), 1.0f);
    // The material without a normal texture has a flat map: B = 0.
    const LeanMap flat = unpack_lean_map(scene.lean_maps[std::size_t(scene.materials[1].lean_map)]);
    EXPECT_NEAR(glm::length(flat.levels[0].mean[0]), 0.0f, 1e-6f);
}

// The metallic-roughness part: Cook-Torrance's base roughness map per material, α0² = r⁴ with r
// the roughnessFactor times the texture's G (filtered as the moments), or the factor alone.
TEST(GltfScene, RoughnessFactorAndTextureBecomeTheBaseRoughnessMap) {
    const fs::path dir = gltf_scene_folder("roughness");
    test::GltfTestFile file;
    std::vector<float> mr;
    for (int t = 0; t < 4; ++t) mr.insert(mr.end(), {1.0f, t < 2 ? 0.2f : 0.6f, 0.5f});
    file.images = {test::png_bytes(2, 2, 3, mr)};
    file.materials = {{"factor", glm::vec4(1.0f), -1, -1, 1.0f, 0.5f},
                      {"texture", glm::vec4(1.0f), -1, -1, 1.0f, 0.5f, std::nullopt, 0},
                      {"default", glm::vec4(1.0f), -1, -1, 1.0f}};
    for (int m = 0; m < 3; ++m) file.meshes.push_back({test::unit_quad(m)});
    const std::string path = (dir / "r.glb").string();
    test::write_gltf(file, path, GltfStorage::Binary);
    const Scene scene = make_render_scene(load_gltf(path), GltfBakeSettings{});
    ASSERT_EQ(scene.materials.size(), 3u);
    const auto& maps = scene.maps_of(MapKind::BaseRoughness);
    const auto level0 = [&](int material) -> const Image& {
        const int slot = scene.materials[std::size_t(material)].map(MapKind::BaseRoughness);
        EXPECT_GE(slot, 0);
        return maps[std::size_t(slot)].front();
    };
    EXPECT_NEAR(level0(0).pixels[0], std::pow(0.5f, 4.0f), 1e-6f);
    // Texture: r = 0.5 x G (8-bit 0.2 and 0.6), rows top first.
    const Image& t = level0(1);
    ASSERT_EQ(t.width, 2);
    const float g_top = std::round(0.2f * 255.0f) / 255.0f, g_bottom = std::round(0.6f * 255.0f) / 255.0f;
    EXPECT_NEAR(t.at(0, 0), std::pow(0.5f * g_top, 4.0f), 1e-6f);
    EXPECT_NEAR(t.at(1, 1), std::pow(0.5f * g_bottom, 4.0f), 1e-6f);
    // No factor in the file: glTF's default roughness, 1.
    EXPECT_NEAR(level0(2).pixels[0], 1.0f, 1e-6f);
}

// The other glTF material terms: metalness (factor, texture B), occlusion (texture R, strength),
// emission (factor, texture sRGB decoded) and KHR_materials_anisotropy (strength, rotation,
// texture kept linear), each a map of its kind with its own texture transform.
TEST(GltfScene, MetalnessOcclusionEmissionAndAnisotropyBecomeMapsOfTheirKinds) {
    const fs::path dir = gltf_scene_folder("material_maps");
    test::GltfTestFile file;
    // One 2 x 1 RGB image for every texture: (0.2, 0.4, 0.6) and (1, 0.5, 0).
    file.images = {test::png_bytes(2, 1, 3, {0.2f, 0.4f, 0.6f, 1.0f, 0.5f, 0.0f})};
    file.materials = {{"all", glm::vec4(1.0f), -1, -1, 1.0f, 0.5f, 0.25f, 0},
                      {"factors", glm::vec4(1.0f), -1, -1, 1.0f}};
    const nlohmann::json offset = {{"KHR_texture_transform", {{"offset", {0.5, 0.0}}}}};
    file.materials[0].patch = {
        {"occlusionTexture", {{"index", 0}, {"strength", 0.6}, {"extensions", offset}}},
        {"emissiveTexture", {{"index", 0}}},
        {"emissiveFactor", {1.0, 0.5, 0.25}},
        {"extensions",
         {{"KHR_materials_anisotropy",
           {{"anisotropyStrength", 0.3},
            {"anisotropyRotation", -0.5},
            {"anisotropyTexture", {{"index", 0}}}}}}}};
    file.materials[1].patch = {{"emissiveFactor", {0.1, 0.2, 0.3}}};
    file.meshes = {{test::unit_quad(0)}, {test::unit_quad(1)}};
    file.patch = {{"extensionsUsed", {"KHR_materials_anisotropy", "KHR_texture_transform"}},
                  {"extensionsRequired", {"KHR_materials_anisotropy"}}};
    const std::string path = (dir / "m.glb").string();
    test::write_gltf(file, path, GltfStorage::Binary);
    const GltfScene gltf = load_gltf(path);
    ASSERT_EQ(gltf.materials.size(), 2u);
    const GltfMaterial& g = gltf.materials[0];
    EXPECT_FLOAT_EQ(g.occlusion_strength, 0.6f);
    EXPECT_EQ(g.emissive_factor, glm::vec3(1.0f, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(g.anisotropy_strength, 0.3f);
    EXPECT_FLOAT_EQ(g.anisotropy_rotation, -0.5f);
    EXPECT_GE(g.anisotropy_image, 0);
    EXPECT_EQ(g.occlusion_transform.offset, glm::vec2(0.5f, 0.0f));
    EXPECT_TRUE(gltf.warnings.empty()) << gltf.warnings.front();

    const Scene scene = make_render_scene(gltf, GltfBakeSettings{});
    const Material& all = scene.materials[0];
    const Material& factors = scene.materials[1];
    const auto level0 = [&](const Material& m, MapKind kind) -> const Image& {
        return scene.maps_of(kind)[std::size_t(m.map(kind))].front();
    };
    const float b8 = std::round(0.6f * 255.0f) / 255.0f, r8 = std::round(0.2f * 255.0f) / 255.0f;
    EXPECT_FLOAT_EQ(*all.metallic, 0.25f);
    ASSERT_GE(all.map(MapKind::Metallic), 0);
    EXPECT_EQ(level0(all, MapKind::Metallic).channels, 1);
    EXPECT_NEAR(level0(all, MapKind::Metallic).at(0, 0), b8, 1e-6f);  // B
    EXPECT_NEAR(level0(all, MapKind::Metallic).at(1, 0), 0.0f, 1e-6f);
    ASSERT_GE(all.map(MapKind::Occlusion), 0);
    EXPECT_NEAR(level0(all, MapKind::Occlusion).at(0, 0), r8, 1e-6f);  // R
    EXPECT_NEAR(level0(all, MapKind::Occlusion).at(1, 0), 1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(all.occlusion_strength, 0.6f);
    EXPECT_EQ(all.map_uv[std::size_t(MapKind::Occlusion)].row0.z, 0.5f);  // u + 0.5
    ASSERT_GE(all.map(MapKind::Emissive), 0);
    const Image& emissive = level0(all, MapKind::Emissive);
    EXPECT_EQ(emissive.channels, 4);
    // sRGB decoded (IEC 61966-2-1): 0.2 -> 0.0331 (8-bit 51/255).
    const float c = 51.0f / 255.0f;
    EXPECT_NEAR(emissive.at(0, 0, 0), std::pow((c + 0.055f) / 1.055f, 2.4f), 1e-5f);
    EXPECT_NEAR(emissive.at(1, 0, 1), std::pow((128.0f / 255.0f + 0.055f) / 1.055f, 2.4f), 1e-5f);
    EXPECT_EQ(all.emissive, glm::vec3(1.0f, 0.5f, 0.25f));
    ASSERT_GE(all.map(MapKind::Anisotropy), 0);
    const Image& anisotropy = level0(all, MapKind::Anisotropy);
    EXPECT_NEAR(anisotropy.at(0, 0, 0), r8, 1e-6f);  // linear: as stored
    EXPECT_NEAR(anisotropy.at(0, 0, 2), b8, 1e-6f);
    EXPECT_EQ(anisotropy.at(0, 0, 3), 1.0f);
    EXPECT_FLOAT_EQ(all.anisotropy_strength, 0.3f);
    EXPECT_FLOAT_EQ(all.anisotropy_rotation, -0.5f);
    // The factors alone: no maps, glTF's default metalness 1.
    for (const MapKind kind :
         {MapKind::Metallic, MapKind::Occlusion, MapKind::Emissive, MapKind::Anisotropy})
        EXPECT_EQ(factors.map(kind), -1);
    EXPECT_FLOAT_EQ(*factors.metallic, 1.0f);
    EXPECT_EQ(factors.emissive, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_FLOAT_EQ(factors.anisotropy_strength, 0.0f);
}

// Values outside the specification's ranges are errors naming the material and the value.
TEST(GltfScene, MaterialFactorsOutsideTheirRangesAreRefused) {
    const fs::path dir = gltf_scene_folder("material_ranges");
    const struct {
        nlohmann::json patch;
        const char* named;
    } cases[] = {
        {{{"occlusionTexture", {{"index", 0}, {"strength", 1.5}}}}, "strength"},
        {{{"emissiveFactor", {1.0, -0.5, 0.0}}}, "emissiveFactor"},
        {{{"extensions", {{"KHR_materials_anisotropy", {{"anisotropyStrength", 2.0}}}}}},
         "anisotropyStrength"},
        {{{"extensions", {{"KHR_materials_anisotropy", {{"anisotropyRotation", "up"}}}}}},
         "anisotropyRotation"},
        {{{"extensions", {{"KHR_materials_anisotropy", {{"anisotropyTexture", {{"index", 7}}}}}}}},
         "texture 7"},
    };
    for (const auto& c : cases) {
        test::GltfTestFile file;
        file.images = {test::png_bytes(1, 1, 3, {0.5f, 0.5f, 0.5f})};
        file.materials = {{"m", glm::vec4(1.0f), -1, -1, 1.0f}};
        file.materials[0].patch = c.patch;
        file.meshes = {{test::unit_quad(0)}};
        const std::string path = (dir / "bad.glb").string();
        test::write_gltf(file, path, GltfStorage::Binary);
        try {
            (void)load_gltf(path);
            ADD_FAILURE() << c.patch.dump() << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), path);
            EXPECT_NE(e.cause().find(c.named), std::string::npos) << e.what();
            EXPECT_NE(e.cause().find("material 'm'"), std::string::npos) << e.what();
        }
    }
}

bool same_map(const PackedLeanMap& a, const PackedLeanMap& b) {
    if (a.levels.size() != b.levels.size() || a.scale != b.scale || a.storage != b.storage)
        return false;
    for (std::size_t i = 0; i < a.levels.size(); ++i)
        if (a.levels[i].lean1 != b.levels[i].lean1 || a.levels[i].lean2 != b.levels[i].lean2)
            return false;
    return true;
}

TEST(GltfScene, SecondLoadReadsTheCacheAndCorruptEntriesAreRebaked) {
    const fs::path dir = gltf_scene_folder("cache");
    GltfBakeSettings settings;
    settings.cache_folder = (dir / "cache").string();
    const GltfScene gltf = load_textured(dir, {0.2f, 0.1f, 0.95f});

    GltfBakeReport first;
    const Scene a = make_render_scene(gltf, settings, &first);
    EXPECT_EQ(first.baked, 1u);
    EXPECT_EQ(first.from_cache, 0u);
    EXPECT_TRUE(first.warnings.empty());
    std::vector<fs::path> entries;
    for (const auto& e : fs::directory_iterator(settings.cache_folder)) entries.push_back(e.path());
    ASSERT_EQ(entries.size(), 1u);
    EXPECT_EQ(entries[0].extension(), ".ktx2");
    const auto written = fs::last_write_time(entries[0]);

    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    GltfBakeReport second;
    const Scene b = make_render_scene(gltf, settings, &second);
    EXPECT_EQ(second.baked, 0u);
    EXPECT_EQ(second.from_cache, 1u);
    EXPECT_EQ(fs::last_write_time(entries[0]), written);  // not written again
    ASSERT_EQ(a.lean_maps.size(), b.lean_maps.size());
    for (std::size_t i = 0; i < a.lean_maps.size(); ++i)
        EXPECT_TRUE(same_map(a.lean_maps[i], b.lean_maps[i])) << i;

    // Another scale is another bake (another key).
    GltfBakeReport scaled;
    (void)make_render_scene(load_textured(dir, {0.2f, 0.1f, 0.95f}, 0.5f), settings, &scaled);
    EXPECT_EQ(scaled.baked, 1u);

    // A truncated entry is ignored, rebaked and replaced; the result is the same map.
    fs::resize_file(entries[0], fs::file_size(entries[0]) / 2);
    GltfBakeReport third;
    const Scene c = make_render_scene(gltf, settings, &third);
    EXPECT_EQ(third.baked, 1u);
    EXPECT_EQ(third.from_cache, 0u);
    for (std::size_t i = 0; i < a.lean_maps.size(); ++i)
        EXPECT_TRUE(same_map(a.lean_maps[i], c.lean_maps[i])) << i;
    GltfBakeReport fourth;
    (void)make_render_scene(gltf, settings, &fourth);
    EXPECT_EQ(fourth.from_cache, 1u);

    // An unwritable cache is a warning, not a failure.
    GltfBakeSettings unwritable = settings;
    unwritable.cache_folder = (dir / "scene.glb" / "cache").string();  // under a file
    GltfBakeReport fifth;
    EXPECT_NO_THROW((void)make_render_scene(gltf, unwritable, &fifth));
    EXPECT_EQ(fifth.baked, 1u);
    EXPECT_EQ(fifth.warnings.size(), 1u);
}

TEST(GltfScene, BrokenImagesAreOneLineErrors) {
    const fs::path dir = gltf_scene_folder("broken");
    GltfTestFile file = textured_file({0, 0, 1});
    file.images[0].resize(file.images[0].size() / 2);  // truncated PNG
    const std::string path = (dir / "broken.glb").string();
    test::write_gltf(file, path, GltfStorage::Binary);
    const GltfScene gltf = load_gltf(path);
    try {
        (void)make_render_scene(gltf, GltfBakeSettings{});
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), path);
        EXPECT_NE(e.cause().find("image 0"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
    // A gray normal texture is refused.
    file = textured_file({0, 0, 1});
    file.images[0] = test::png_bytes(2, 2, 1, {0.5f, 0.5f, 0.5f, 0.5f});
    test::write_gltf(file, path, GltfStorage::Binary);
    try {
        (void)make_render_scene(load_gltf(path), GltfBakeSettings{});
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(e.cause().find("3 channels"), std::string::npos) << e.what();
    }
}

TEST(LeanMapCache, Sha256MatchesTheStandardsTestVectors) {
    // FIPS 180-4 examples: "abc", the empty message and the two-block message.
    EXPECT_EQ(sha256_hex("abc", 3),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256_hex("", 0),
              "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    const std::string two = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    EXPECT_EQ(sha256_hex(two.data(), two.size()),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    // A message of many blocks: the FIPS 180-4 example of a million 'a'.
    const std::string million(1000000, 'a');
    EXPECT_EQ(sha256_hex(million.data(), million.size()),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    // Keys differ with the settings and the bytes.
    EXPECT_NE(lean_cache_key({1, 2, 3}, "a"), lean_cache_key({1, 2, 3}, "b"));
    EXPECT_NE(lean_cache_key({1, 2, 3}, "a"), lean_cache_key({1, 2, 4}, "a"));
    EXPECT_EQ(lean_cache_key({1, 2, 3}, "a"), lean_cache_key({1, 2, 3}, "a"));
    // Several sources: one gives the key of one; the split between them counts.
    const std::vector<std::uint8_t> abc{1, 2, 3}, ab{1, 2}, c{3}, none;
    const std::span<const std::uint8_t> one[] = {abc};
    const std::span<const std::uint8_t> split[] = {ab, c};
    const std::span<const std::uint8_t> joined[] = {abc, none};
    EXPECT_EQ(lean_cache_key(one, "a"), lean_cache_key(abc, "a"));
    EXPECT_NE(lean_cache_key(split, "a"), lean_cache_key(joined, "a"));
    EXPECT_NE(lean_cache_key(joined, "a"), lean_cache_key(one, "a"));
}

TEST(LeanMapCache, DefaultFolderFollowsXdg) {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const std::string saved = xdg != nullptr ? xdg : "";
    const char* home = std::getenv("HOME");
    const std::string saved_home = home != nullptr ? home : "";
    ::setenv("XDG_CACHE_HOME", "/somewhere/cache", 1);
    EXPECT_EQ(default_lean_cache_folder(), "/somewhere/cache/leanfade");
    ::setenv("XDG_CACHE_HOME", "relative", 1);  // not absolute: ignored
    ::setenv("HOME", "/home/someone", 1);
    EXPECT_EQ(default_lean_cache_folder(), "/home/someone/.cache/leanfade");
    if (xdg != nullptr) ::setenv("XDG_CACHE_HOME", saved.c_str(), 1);
    else ::unsetenv("XDG_CACHE_HOME");
    if (home != nullptr) ::setenv("HOME", saved_home.c_str(), 1);
    else ::unsetenv("HOME");
}

}  // namespace
}  // namespace leanfade::scene
