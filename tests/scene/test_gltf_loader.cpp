// glTF loading (leanfade/scene/gltf.hpp) on small files written by the test: several materials,
// with and without tangents, external and embedded buffers, GLB; and broken or hostile files.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/gltf.hpp"
#include "mesh_checks.hpp"
#include "test_gltf_builder.hpp"

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;
using test::GltfStorage;
using test::GltfTestFile;

fs::path loader_folder(const std::string& name) { return test::fresh_test_folder("gltf", name); }

// Two meshes, three materials (one without textures), two PNG images (a base colour and a
// normal map), the second mesh with tangents from the file.
GltfTestFile two_material_file() {
    GltfTestFile file;
    file.images.push_back(test::png_bytes(2, 2, 3, std::vector<float>(12, 0.75f)));
    std::vector<float> normal(4 * 4 * 3);
    for (std::size_t i = 0; i < normal.size(); i += 3) {
        normal[i] = 0.7f;
        normal[i + 1] = 0.5f;
        normal[i + 2] = 0.9f;
    }
    file.images.push_back(test::png_bytes(4, 4, 3, normal));
    file.materials.push_back({"painted", {0.5f, 0.25f, 1.0f, 1.0f}, 0, -1, 1.0f});
    file.materials.push_back({"bumpy", {1.0f, 1.0f, 1.0f, 1.0f}, -1, 1, 0.5f});
    file.materials.push_back({"plain", {0.2f, 0.3f, 0.4f, 1.0f}, -1, -1, 1.0f});
    test::GltfTestPrimitive a = test::unit_quad(0);
    test::GltfTestPrimitive b = test::unit_quad(1);
    b.tangents.assign(4, glm::vec4(1, 0, 0, 1));
    test::GltfTestPrimitive c = test::unit_quad(2);
    file.meshes = {{a}, {b, c}};
    return file;
}

void expect_same_meshes(const GltfScene& x, const GltfScene& y) {
    ASSERT_EQ(x.objects.size(), y.objects.size());
    for (std::size_t o = 0; o < x.objects.size(); ++o) {
        const Mesh& a = x.objects[o].mesh;
        const Mesh& b = y.objects[o].mesh;
        ASSERT_EQ(a.vertices.size(), b.vertices.size());
        EXPECT_EQ(a.indices, b.indices);
        for (std::size_t i = 0; i < a.vertices.size(); ++i) {
            EXPECT_EQ(a.vertices[i].position, b.vertices[i].position);
            EXPECT_EQ(a.vertices[i].uv, b.vertices[i].uv);
            EXPECT_EQ(a.vertices[i].uv1, b.vertices[i].uv1);
            EXPECT_EQ(a.vertices[i].tangent, b.vertices[i].tangent);
        }
        EXPECT_EQ(x.objects[o].material, y.objects[o].material);
    }
    ASSERT_EQ(x.images.size(), y.images.size());
    for (std::size_t i = 0; i < x.images.size(); ++i)
        EXPECT_EQ(x.images[i].bytes, y.images[i].bytes);
}

TEST(GltfLoader, ReadsMeshesMaterialsAndImagesOfExternalFiles) {
    const fs::path dir = loader_folder("external");
    const GltfTestFile file = two_material_file();
    const std::string path = (dir / "scene.gltf").string();
    test::write_gltf(file, path, GltfStorage::External);
    const GltfScene scene = load_gltf(path);
    ASSERT_EQ(scene.objects.size(), 3u);
    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_EQ(scene.materials[0].name, "painted");
    EXPECT_EQ(scene.materials[0].base_color_factor, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
    ASSERT_GE(scene.materials[0].base_color_image, 0);
    EXPECT_EQ(scene.images[std::size_t(scene.materials[0].base_color_image)].bytes,
              file.images[0]);
    EXPECT_EQ(scene.materials[0].normal_image, -1);
    ASSERT_GE(scene.materials[1].normal_image, 0);
    EXPECT_EQ(scene.images[std::size_t(scene.materials[1].normal_image)].bytes, file.images[1]);
    EXPECT_FLOAT_EQ(scene.materials[1].normal_scale, 0.5f);
    EXPECT_EQ(scene.materials[2].base_color_image, -1);
    EXPECT_EQ(scene.materials[2].normal_image, -1);
    EXPECT_EQ(scene.objects[0].material, 0);
    EXPECT_EQ(scene.objects[1].material, 1);
    EXPECT_EQ(scene.objects[2].material, 2);
    EXPECT_EQ(scene.primitives_with_tangents, 1u);
    EXPECT_EQ(scene.primitives_generated_tangents, 2u);

    // uv flipped to v up: the quad's corner (x, y) has leanfade uv (x, y).
    for (const GltfObject& object : scene.objects) {
        ASSERT_EQ(object.mesh.vertices.size(), 4u);
        for (const Vertex& v : object.mesh.vertices) {
            EXPECT_FLOAT_EQ(v.uv.x, v.position.x);
            EXPECT_FLOAT_EQ(v.uv.y, v.position.y);
            // T along +u = +x, bitangent w cross(N, T) along +v = +y.
            EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
            EXPECT_NEAR(std::abs(v.tangent.y) + std::abs(v.tangent.z), 0.0f, 1e-6f);
            EXPECT_EQ(v.tangent.w, 1.0f);
        }
        const test::UvFrameStats uv = test::uv_frame_stats(object.mesh);
        EXPECT_GT(uv.min_cos_tangent, 0.9999f);
        EXPECT_GT(uv.min_cos_bitangent, 0.9999f);
    }
}

TEST(GltfLoader, EmbeddedAndBinaryFilesGiveTheSameScene) {
    const fs::path dir = loader_folder("storages");
    const GltfTestFile file = two_material_file();
    const std::string external = (dir / "a.gltf").string();
    const std::string embedded = (dir / "b.gltf").string();
    const std::string binary = (dir / "c.glb").string();
    test::write_gltf(file, external, GltfStorage::External);
    test::write_gltf(file, embedded, GltfStorage::Embedded);
    test::write_gltf(file, binary, GltfStorage::Binary);
    const GltfScene a = load_gltf(external);
    expect_same_meshes(a, load_gltf(embedded));
    expect_same_meshes(a, load_gltf(binary));
    // Embedded data needs no other file: the same bytes load from memory.
    expect_same_meshes(a, load_gltf_from_memory(test::read_bytes(binary), "memory.glb"));
    expect_same_meshes(a, load_gltf_from_memory(test::read_bytes(embedded), "memory.gltf"));
}

TEST(GltfLoader, FileTangentsAreKeptAndOrthonormalised) {
    GltfTestFile file;
    test::GltfTestPrimitive quad = test::unit_quad();
    // Not unit, not orthogonal to N = +z, mirrored (w = -1).
    quad.tangents.assign(4, glm::vec4(2.0f, 0.0f, 1.0f, -1.0f));
    file.meshes = {{quad}};
    const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    const GltfScene scene = load_gltf_from_memory(test::pack_glb(out.json, out.bin), "t.glb");
    ASSERT_EQ(scene.objects.size(), 1u);
    EXPECT_EQ(scene.primitives_with_tangents, 1u);
    for (const Vertex& v : scene.objects[0].mesh.vertices) {
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
        EXPECT_NEAR(v.tangent.z, 0.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, -1.0f);
    }
    ASSERT_EQ(scene.materials.size(), 1u);  // the default material
    EXPECT_EQ(scene.materials[0].name, "default");
    EXPECT_EQ(scene.materials[0].base_color_factor, glm::vec4(1.0f));
}

TEST(GltfLoader, NodeTransformsAreComposedAndMirrorsKeepTheFrame) {
    GltfTestFile file;
    file.meshes = {{test::unit_quad()}};
    // Node 0 translates and holds node 1 (scaled, mirrored in x) and node 2 (a plain instance).
    file.nodes.resize(3);
    file.nodes[0].translation = {1.0, 2.0, 3.0};
    file.nodes[0].children = {1, 2};
    file.nodes[1].mesh = 0;
    file.nodes[1].scale = {-2.0, 1.0, 1.0};
    file.nodes[2].mesh = 0;
    const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    const GltfScene scene = load_gltf_from_memory(test::pack_glb(out.json, out.bin), "n.glb");
    ASSERT_EQ(scene.objects.size(), 2u);
    const GltfObject& mirrored = scene.objects[0];
    const GltfObject& plain = scene.objects[1];
    EXPECT_EQ(mirrored.transform * glm::vec4(1, 1, 0, 1), glm::vec4(-1.0f, 3.0f, 3.0f, 1.0f));
    EXPECT_EQ(plain.transform * glm::vec4(1, 1, 0, 1), glm::vec4(2.0f, 3.0f, 3.0f, 1.0f));
    // Mirrored: winding reversed and w negated, so that after the transform the triangles are
    // still counter-clockwise seen from the side the (transformed) normals point to, and the
    // bitangent w cross(N', T') still points along the transformed +v.
    for (std::size_t t = 0; t < plain.mesh.indices.size(); t += 3) {
        EXPECT_EQ(mirrored.mesh.indices[t], plain.mesh.indices[t]);
        EXPECT_EQ(mirrored.mesh.indices[t + 1], plain.mesh.indices[t + 2]);
    }
    const glm::mat3 m(mirrored.transform);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(m));
    for (const Vertex& v : mirrored.mesh.vertices) {
        EXPECT_EQ(v.tangent.w, -1.0f);
        const glm::vec3 n = glm::normalize(normal_matrix * v.normal);
        const glm::vec3 t = glm::normalize(m * glm::vec3(v.tangent));
        const glm::vec3 bitangent = v.tangent.w * glm::cross(n, t);
        const glm::vec3 dp_dv = m * glm::vec3(0, 1, 0);  // v = y on the quad
        EXPECT_GT(glm::dot(bitangent, glm::normalize(dp_dv)), 0.999f);
    }
    for (std::size_t t = 0; t < mirrored.mesh.indices.size(); t += 3) {
        const glm::vec3 p[3] = {
            glm::vec3(mirrored.transform *
                      glm::vec4(mirrored.mesh.vertices[mirrored.mesh.indices[t]].position, 1)),
            glm::vec3(mirrored.transform *
                      glm::vec4(mirrored.mesh.vertices[mirrored.mesh.indices[t + 1]].position, 1)),
            glm::vec3(mirrored.transform *
                      glm::vec4(mirrored.mesh.vertices[mirrored.mesh.indices[t + 2]].position, 1))};
        const glm::vec3 face = glm::cross(p[1] - p[0], p[2] - p[0]);
        const glm::vec3 n = normal_matrix * mirrored.mesh.vertices[mirrored.mesh.indices[t]].normal;
        EXPECT_GT(glm::dot(face, n), 0.0f);
    }
}

TEST(GltfLoader, StripsFansAndMissingNormals) {
    GltfTestFile file;
    test::GltfTestPrimitive strip = test::unit_quad();
    strip.indices = {0, 1, 3, 2};  // strip: (0 1 3), (3 1 2) after the odd-triangle swap
    strip.mode = 5;
    test::GltfTestPrimitive fan = test::unit_quad();
    fan.indices = {0, 1, 2, 3};  // fan: (0 1 2), (0 2 3)
    fan.mode = 6;
    fan.normals.clear();  // flat normals, computed
    file.meshes = {{strip, fan}};
    const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    const GltfScene scene = load_gltf_from_memory(test::pack_glb(out.json, out.bin), "s.glb");
    ASSERT_EQ(scene.objects.size(), 2u);
    for (const GltfObject& o : scene.objects) {
        EXPECT_EQ(o.mesh.triangle_count(), 2u);
        const test::WindingStats w = test::winding_stats(o.mesh);
        EXPECT_EQ(w.disagreeing, 0u);
        EXPECT_EQ(w.degenerate, 0u);
        for (const Vertex& v : o.mesh.vertices) EXPECT_NEAR(v.normal.z, 1.0f, 1e-6f);
    }
    EXPECT_EQ(scene.objects[1].mesh.vertices.size(), 6u);  // flat: three vertices per triangle
}

// ---------------------------------------------------------------------------------------------
// Broken and hostile files: one line naming the file and the cause.

void expect_load_error(const std::string& path, const std::string& cause) {
    try {
        (void)load_gltf(path);
        ADD_FAILURE() << path << ": no error thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), path);
        EXPECT_NE(e.cause().find(cause), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

void expect_memory_error(const std::vector<std::uint8_t>& bytes, const std::string& cause) {
    try {
        (void)load_gltf_from_memory(bytes, "bad.glb");
        ADD_FAILURE() << cause << ": no error thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "bad.glb");
        EXPECT_NE(e.cause().find(cause), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

std::vector<std::uint8_t> glb_of(const GltfTestFile& file,
                                 void (*edit)(nlohmann::json&, std::vector<std::uint8_t>&)) {
    test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    edit(out.json, out.bin);
    return test::pack_glb(out.json, out.bin);
}

GltfTestFile one_quad() {
    GltfTestFile file;
    file.meshes = {{test::unit_quad()}};
    return file;
}

// A quad whose TEXCOORD_1 is its TEXCOORD_0 turned by 90 degrees: leanfade uv = (x, y), uv1 =
// (y, 1 - x) (glTF's (y, x)), so +u1 runs along +y and +v1 along -x (orientation kept).
test::GltfTestPrimitive two_set_quad(int material) {
    test::GltfTestPrimitive p = test::unit_quad(material);
    for (const glm::vec3& q : p.positions) p.uvs1.push_back(glm::vec2(q.y, q.x));
    return p;
}

bool any_warning_has(const GltfScene& scene, const std::string& a, const std::string& b) {
    for (const std::string& w : scene.warnings)
        if (w.find(a) != std::string::npos && w.find(b) != std::string::npos) return true;
    return false;
}

TEST(GltfLoader, EachTextureSamplesTheSetItsReferenceNames) {
    GltfTestFile file;
    file.images.push_back(test::png_bytes(2, 2, 3, std::vector<float>(12, 0.75f)));
    std::vector<float> normal;
    for (int i = 0; i < 16; ++i) normal.insert(normal.end(), {0.6f, 0.45f, 0.9f});
    file.images.push_back(test::png_bytes(4, 4, 3, normal));
    const auto transform = [](nlohmann::json value) {
        return nlohmann::json{{"KHR_texture_transform", value}};
    };
    // "mixed": base colour on set 1, normal on set 0; the emissive texture's transform overrides
    // its texCoord 0 with 1, the occlusion texture's its texCoord 1 with 0; the
    // metallic-roughness texture names set 3, which leanfade does not read.
    test::GltfTestMaterial mixed{"mixed", glm::vec4(1.0f), 0, 1, 1.0f};
    mixed.metallic_roughness_image = 0;
    mixed.patch = {{"pbrMetallicRoughness",
                    {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}},
                     {"metallicRoughnessTexture", {{"index", 0}, {"texCoord", 3}}}}},
                   {"emissiveTexture",
                    {{"index", 0}, {"texCoord", 0}, {"extensions", transform({{"texCoord", 1}})}}},
                   {"occlusionTexture",
                    {{"index", 0},
                     {"texCoord", 1},
                     {"extensions", transform({{"offset", {0.5, 0.0}}, {"texCoord", 0}})}}}};
    // "second set": the normal texture on set 1 (and the base colour on set 0).
    test::GltfTestMaterial second{"second set", glm::vec4(1.0f), 0, 1, 1.0f};
    second.patch = {{"normalTexture", {{"texCoord", 1}}}};
    // "missing": the base colour on set 1 of a primitive without TEXCOORD_1.
    test::GltfTestMaterial missing{"missing", glm::vec4(1.0f), 0, -1, 1.0f};
    missing.patch = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"texCoord", 1}}}}}};
    file.materials = {mixed, second, missing};
    file.meshes = {{two_set_quad(0)}, {two_set_quad(1)}, {test::unit_quad(2)}};
    file.patch = {{"extensionsUsed", {"KHR_texture_transform"}}};
    const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
    const GltfScene scene = load_gltf_from_memory(test::pack_glb(out.json, out.bin), "sets.glb");
    ASSERT_EQ(scene.objects.size(), 3u);
    ASSERT_EQ(scene.materials.size(), 3u);

    // The sets each reference samples, overrides applied, set 3 read as 0.
    const GltfMaterial& m0 = scene.materials[0];
    EXPECT_EQ(m0.base_color_transform.tex_coord, 1);
    EXPECT_EQ(m0.normal_transform.tex_coord, 0);
    EXPECT_EQ(m0.emissive_transform.tex_coord, 1);
    EXPECT_EQ(m0.occlusion_transform.tex_coord, 0);
    EXPECT_FLOAT_EQ(m0.occlusion_transform.offset.x, 0.5f);
    EXPECT_EQ(m0.metallic_roughness_transform.tex_coord, 0);
    EXPECT_EQ(scene.materials[1].normal_transform.tex_coord, 1);
    EXPECT_EQ(scene.materials[1].base_color_transform.tex_coord, 0);
    EXPECT_EQ(scene.materials[2].base_color_transform.tex_coord, 1);
    // Warnings: set 3, and set 1 on the primitive without it; nothing else names a set.
    EXPECT_TRUE(any_warning_has(scene, "metallicRoughnessTexture", "TEXCOORD_3"));
    EXPECT_TRUE(any_warning_has(scene, "'missing'", "TEXCOORD_1, which the primitive lacks"));
    int set_warnings = 0;
    for (const std::string& w : scene.warnings)
        if (w.find("TEXCOORD") != std::string::npos) ++set_warnings;
    EXPECT_EQ(set_warnings, 2) << ::testing::PrintToString(scene.warnings);

    // uv1 holds TEXCOORD_1 flipped to v up, or a copy of uv without it; the tangents follow the
    // normal texture's set: +x (along +u) for "mixed", +y (along +u1) for "second set", w = +1.
    for (std::size_t o = 0; o < 3; ++o) {
        ASSERT_EQ(scene.objects[o].mesh.vertices.size(), 4u) << o;
        for (const Vertex& v : scene.objects[o].mesh.vertices) {
            EXPECT_EQ(v.uv, glm::vec2(v.position.x, v.position.y));
            const glm::vec2 uv1 = o < 2 ? glm::vec2(v.position.y, 1.0f - v.position.x) : v.uv;
            EXPECT_EQ(v.uv1, uv1) << o;
            const glm::vec3 along = o == 1 ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
            EXPECT_NEAR(glm::length(glm::vec3(v.tangent) - along), 0.0f, 1e-6f) << o;
            EXPECT_EQ(v.tangent.w, 1.0f) << o;
        }
    }

    // The render scene's materials carry the sets into their UvTransforms (the renderer's
    // uv_transforms row 0 w).
    const Scene render = make_render_scene(scene, GltfBakeSettings{});
    ASSERT_EQ(render.materials.size(), 3u);
    const Material& r0 = render.materials[0];
    EXPECT_EQ(r0.map_uv[std::size_t(MapKind::BaseColor)].set, 1);
    EXPECT_EQ(r0.lean_uv.set, 0);
    EXPECT_EQ(r0.map_uv[std::size_t(MapKind::Emissive)].set, 1);
    EXPECT_EQ(r0.map_uv[std::size_t(MapKind::Occlusion)].set, 0);
    EXPECT_EQ(r0.map_uv[std::size_t(MapKind::Occlusion)].row0.z, 0.5f);
    EXPECT_EQ(r0.map_uv[std::size_t(MapKind::Metallic)].set, 0);
    EXPECT_EQ(r0.map_uv[std::size_t(MapKind::BaseRoughness)].set, 0);
    EXPECT_EQ(render.materials[1].lean_uv.set, 1);
    EXPECT_EQ(render.materials[1].map_uv[std::size_t(MapKind::BaseColor)].set, 0);
    // A set the meshes do not have is refused by the scene's validation.
    Scene broken = render;
    broken.materials[0].map_uv[std::size_t(MapKind::Emissive)].set = 2;
    try {
        validate(broken);
        ADD_FAILURE() << "set 2 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("texture coordinate set 2"), std::string::npos)
            << e.what();
    }
}

TEST(GltfLoaderErrors, MissingUnreadableAndNotGltf) {
    const fs::path dir = loader_folder("errors");
    expect_load_error((dir / "missing.gltf").string(), "No such file");
    expect_load_error(dir.string(), "folder");
    test::write_bytes((dir / "text.gltf").string(), {'h', 'e', 'l', 'l', 'o'});
    expect_load_error((dir / "text.gltf").string(), "not valid glTF JSON");
    test::write_bytes((dir / "empty.glb").string(), {});
    expect_load_error((dir / "empty.glb").string(), "not valid glTF JSON");
}

TEST(GltfLoaderErrors, TruncatedAndCorruptContainers) {
    const test::GltfTestOutput out = test::build_gltf(one_quad(), GltfStorage::Binary, "");
    const std::vector<std::uint8_t> glb = test::pack_glb(out.json, out.bin);
    // Every truncation is an error, never a crash.
    for (std::size_t size : {std::size_t(4), std::size_t(19), std::size_t(20), glb.size() / 2,
                             glb.size() - 8, glb.size() - 1}) {
        std::vector<std::uint8_t> cut(glb.begin(), glb.begin() + std::ptrdiff_t(size));
        EXPECT_THROW((void)load_gltf_from_memory(cut, "cut.glb"), Error) << size;
    }
    std::vector<std::uint8_t> bad = glb;
    bad[4] = 1;  // version 1
    expect_memory_error(bad, "GLB version");
    // A BIN chunk claiming 8 more bytes than the file has (tinygltf 2.7 would read past the end).
    bad = glb;
    const std::size_t json_length = std::size_t(bad[12]) | std::size_t(bad[13]) << 8;
    const std::size_t bin_at = 20 + json_length;
    bad[bin_at] = std::uint8_t(bad[bin_at] + 8);
    expect_memory_error(bad, "BIN chunk");
}

TEST(GltfLoaderErrors, IndicesAndAccessorsOutOfRange) {
    GltfTestFile file = one_quad();
    file.meshes[0][0].indices = {0, 1, 2, 0, 2, 4};
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        expect_memory_error(test::pack_glb(out.json, out.bin), "index 4 out of range (4 vertices)");
    }
    expect_memory_error(glb_of(one_quad(), [](nlohmann::json& j, std::vector<std::uint8_t>&) {
                            j["accessors"][0]["count"] = 1000000;
                        }),
                        "do not fit in buffer view");
    expect_memory_error(glb_of(one_quad(), [](nlohmann::json& j, std::vector<std::uint8_t>&) {
                            j["bufferViews"][0]["byteOffset"] = 1u << 30;
                        }),
                        "outside");
    expect_memory_error(glb_of(one_quad(), [](nlohmann::json& j, std::vector<std::uint8_t>&) {
                            j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99;
                        }),
                        "does not exist");
    expect_memory_error(glb_of(one_quad(), [](nlohmann::json& j, std::vector<std::uint8_t>&) {
                            j["meshes"][0]["primitives"][0]["material"] = 3;
                        }),
                        "material 3 does not exist");
}

TEST(GltfLoaderErrors, TextureCoordinateSetsThatAreNotSets) {
    GltfTestFile file = one_quad();
    file.images.push_back(test::png_bytes(2, 2, 3, std::vector<float>(12, 0.75f)));
    file.materials.push_back({"m", glm::vec4(1.0f), 0, -1, 1.0f});
    file.meshes[0][0].material = 0;
    file.materials[0].base_color_transform = {{"texCoord", -1}};
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        expect_memory_error(test::pack_glb(out.json, out.bin),
                            "baseColorTexture: KHR_texture_transform texCoord is not a texture "
                            "coordinate set");
    }
    file.materials[0].base_color_transform = {{"texCoord", 0.5}};
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        expect_memory_error(test::pack_glb(out.json, out.bin), "texCoord is not a texture");
    }
    file = one_quad();
    file.meshes[0][0].uvs1 = file.meshes[0][0].uvs;
    file.meshes[0][0].uvs1[2].y = NAN;
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        expect_memory_error(test::pack_glb(out.json, out.bin), "TEXCOORD_1 2 is not finite");
    }
    file.meshes[0][0].uvs1.pop_back();
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        expect_memory_error(test::pack_glb(out.json, out.bin),
                            "TEXCOORD_1 has 3 elements for 4 positions");
    }
}

TEST(GltfLoaderErrors, NonFiniteValues) {
    GltfTestFile file = one_quad();
    file.meshes[0][0].positions[2].y = INFINITY;
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        expect_memory_error(test::pack_glb(out.json, out.bin), "POSITION 2 is not finite");
    }
    file = one_quad();
    file.meshes[0][0].uvs[1].x = NAN;
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        expect_memory_error(test::pack_glb(out.json, out.bin), "TEXCOORD_0 1 is not finite");
    }
    // Positions so large that the bounding radius leaves the renderer's float range.
    file = one_quad();
    file.meshes[0][0].positions[2] = glm::vec3(3e38f, 3e38f, 0.0f);
    {
        const test::GltfTestOutput out = test::build_gltf(file, GltfStorage::Binary, "");
        EXPECT_THROW((void)load_gltf_from_memory(test::pack_glb(out.json, out.bin), "b.glb"),
                     Error);
    }
}

TEST(GltfLoaderErrors, NodeCyclesAndSharedChildren) {
    expect_memory_error(glb_of(one_quad(), [](nlohmann::json& j, std::vector<std::uint8_t>&) {
                            j["nodes"][0]["children"] = {0};
                        }),
                        "reached twice");
    expect_memory_error(glb_of(one_quad(), [](nlohmann::json& j, std::vector<std::uint8_t>&) {
                            j["nodes"].push_back({{"children", {0}}});
                            j["scenes"][0]["nodes"] = {0, 1};
                        }),
                        "reached twice");
    expect_memory_error(glb_of(one_quad(), [](nlohmann::json& j, std::vector<std::uint8_t>&) {
                            j["nodes"][0]["matrix"] = {1e300, 0, 0, 0, 0, 1, 0, 0,
                                                       0,     0, 1, 0, 0, 0, 0, 1};
                        }),
                        "world matrix is not finite");
}

TEST(GltfLoaderErrors, UrisOutsideTheFolderAreRefused) {
    const fs::path dir = loader_folder("uris");
    fs::create_directories(dir / "inner");
    GltfTestFile file = one_quad();
    const std::string path = (dir / "inner" / "scene.gltf").string();
    test::write_gltf(file, path, GltfStorage::External);
    // The buffer exists one folder up: still refused.
    fs::copy_file(dir / "inner" / "scene.bin", dir / "scene.bin");
    const std::vector<std::uint8_t> original = test::read_bytes(path);
    const std::string text(original.begin(), original.end());
    auto with_uri = [&](const std::string& uri) {
        nlohmann::json j = nlohmann::json::parse(text);
        j["buffers"][0]["uri"] = uri;
        const std::string edited = j.dump();
        test::write_bytes(path, std::vector<std::uint8_t>(edited.begin(), edited.end()));
    };
    with_uri("../scene.bin");
    expect_load_error(path, "leaves the glTF's folder");
    with_uri("%2E%2E/scene.bin");
    expect_load_error(path, "leaves the glTF's folder");
    with_uri((dir / "scene.bin").string());
    expect_load_error(path, "absolute path");
    with_uri("file:///etc/passwd");
    expect_load_error(path, "scheme");
    with_uri("missing.bin");
    expect_load_error(path, "missing.bin");
    with_uri("scene.bin");
    EXPECT_NO_THROW((void)load_gltf(path));
    // From memory, no external file is read at all.
    try {
        (void)load_gltf_from_memory(test::read_bytes(path), "memory.gltf");
        ADD_FAILURE() << "external buffer read from memory";
    } catch (const Error& e) {
        EXPECT_NE(e.cause().find("external file"), std::string::npos) << e.what();
    }
}

TEST(GltfLoaderErrors, MissingImageFile) {
    const fs::path dir = loader_folder("missing_image");
    GltfTestFile file = one_quad();
    file.images.push_back(test::png_bytes(1, 1, 3, {0.5f, 0.5f, 1.0f}));
    file.materials.push_back({"m", glm::vec4(1.0f), -1, 0, 1.0f});
    file.meshes[0][0].material = 0;
    const std::string path = (dir / "scene.gltf").string();
    test::write_gltf(file, path, GltfStorage::External);
    fs::remove(dir / "scene_image0.png");
    expect_load_error(path, "image 0 (scene_image0.png)");
}

}  // namespace
}  // namespace leanfade::scene
