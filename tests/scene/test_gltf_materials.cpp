// glTF materials as the renderer draws them (OpenGL; llvmpipe here, never skipped), against the
// shared header on the CPU (leanfade/core/shading.hpp: lf_surface, lf_shade_surface,
// lf_surface_color), and the header's material formulas against the glTF specification's.
//
// The acceptance scene, in the style of the Khronos sample models: four quads side by side, one
// material each, written as a .glb and read back as a user's file is:
//   "brushed metal"  base colour texture with KHR_texture_transform, metallic-roughness texture
//                    (metalness in B, roughness in G), KHR_materials_anisotropy with a texture
//                    (listed in extensionsRequired);
//   "painted stone"  a tilted normal texture, a metallic factor of 0.5 times the texture, an
//                    occlusion texture (strength 0.7) and its own texture transforms;
//   "lamp"           an emissive texture (sRGB) times an emissive factor;
//   "glass"          alphaMode BLEND over the background, with an emissive factor alone.
// A second scene (two_set_file) puts each map on the texture coordinate set its reference names.
// Every texture is 8 x 8 texels of 2 x 2 blocks, magnified (level 0 only): a pixel is compared
// where every map's bilinear footprint (and a margin of 0.05 texel around it, for the
// rasteriser's interpolation of uv) lies on equal texels, so that the filter returns that texel
// exactly; the others are skipped and counted.
//
// Tolerance, as in tests/gl/test_cpu_reference.cpp: |gpu - cpu| <= 2e-3 |cpu| + 2e-4 per
// channel; the CPU rounds the half-float textures' texels (base colour, emissive, anisotropy) as
// the GPU stores them. Both sides run the same float formulas; what differs is the GPU's exp and
// pow, the interpolation of the light and view vectors, the order of operations and the
// rounding of texels to half floats (measured on llvmpipe: at most 5e-4). A dropped or doubled term
// (the emission, the occlusion, the metalness, a texture transform, the anisotropy) changes pixels
// by percents.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>

#include "gl_test_helpers.hpp"
#include "gltf_render_scene.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/scene/gltf.hpp"
#include "test_gltf_builder.hpp"

using namespace leanfade;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class GltfMaterials : public test::GlTest, public ::testing::WithParamInterface<Brdf> {};

// An 8 x 8 image of 2 x 2 blocks: block b = (x >= 4) + 2 (y >= 4) (rows top first) has
// blocks[b], `channels` of it.
std::vector<std::uint8_t> block_png(int channels, const std::array<glm::vec4, 4>& blocks) {
    std::vector<float> pixels;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < channels; ++c) pixels.push_back(blocks[(x >= 4) + 2 * (y >= 4)][c]);
    return scene::test::png_bytes(8, 8, channels, pixels);
}

enum TestImage { kBaseColor, kMetallicRoughness, kOcclusion, kEmissive, kAnisotropy, kNormal };

scene::test::GltfTestFile acceptance_file() {
    scene::test::GltfTestFile file;
    file.images.resize(6);
    file.images[kBaseColor] = block_png(4, {{{0.9f, 0.2f, 0.1f, 1.0f},
                                             {0.2f, 0.8f, 0.3f, 1.0f},
                                             {0.3f, 0.3f, 0.9f, 0.6f},
                                             {0.95f, 0.85f, 0.4f, 0.8f}}});
    // G: roughness, B: metalness.
    file.images[kMetallicRoughness] = block_png(3, {{{0.0f, 0.3f, 1.0f, 1.0f},
                                                     {0.0f, 0.6f, 0.0f, 1.0f},
                                                     {0.0f, 0.45f, 0.5f, 1.0f},
                                                     {0.0f, 0.8f, 0.8f, 1.0f}}});
    file.images[kOcclusion] = block_png(3, {{{1.0f, 1.0f, 1.0f, 1.0f},
                                             {0.2f, 0.2f, 0.2f, 1.0f},
                                             {0.6f, 0.6f, 0.6f, 1.0f},
                                             {0.0f, 0.0f, 0.0f, 1.0f}}});
    file.images[kEmissive] = block_png(3, {{{1.0f, 0.5f, 0.1f, 1.0f},
                                            {0.0f, 0.0f, 0.0f, 1.0f},
                                            {0.2f, 0.6f, 1.0f, 1.0f},
                                            {1.0f, 1.0f, 1.0f, 1.0f}}});
    // RG: the direction (2 RG - 1): +u, +v, the diagonal, -u; B: the strength.
    file.images[kAnisotropy] = block_png(3, {{{1.0f, 0.5f, 1.0f, 1.0f},
                                              {0.5f, 1.0f, 0.5f, 1.0f},
                                              {0.85f, 0.85f, 0.8f, 1.0f},
                                              {0.0f, 0.5f, 0.3f, 1.0f}}});
    const glm::vec3 tilted = glm::normalize(glm::vec3(0.25f, -0.15f, 1.0f));
    const glm::vec4 normal_texel(0.5f * tilted + 0.5f, 1.0f);
    file.images[kNormal] = block_png(3, {{normal_texel, normal_texel, normal_texel, normal_texel}});

    const auto transform = [](json value) { return json{{"KHR_texture_transform", value}}; };
    file.materials.resize(4);
    scene::test::GltfTestMaterial& metal = file.materials[0];
    metal.name = "brushed metal";
    metal.base_color = {0.9f, 0.9f, 0.95f, 1.0f};
    metal.base_color_image = kBaseColor;
    metal.base_color_transform = {{"offset", {0.25, 0.0}}, {"scale", {1.5, 1.0}}};
    metal.metallic = 1.0f;
    metal.roughness = 0.9f;
    metal.metallic_roughness_image = kMetallicRoughness;
    metal.patch = {
        {"extensions",
         {{"KHR_materials_anisotropy",
           {{"anisotropyStrength", 0.7},
            {"anisotropyRotation", 0.4},
            {"anisotropyTexture",
             {{"index", kAnisotropy}, {"extensions", transform({{"rotation", 0.3}})}}}}}}}};

    scene::test::GltfTestMaterial& stone = file.materials[1];
    stone.name = "painted stone";
    stone.base_color = {0.7f, 0.65f, 0.6f, 1.0f};
    stone.base_color_image = kBaseColor;
    stone.base_color_transform = {{"rotation", 1.5707963}, {"offset", {0.0, 1.0}}};
    stone.normal_image = kNormal;
    stone.metallic = 0.5f;
    stone.roughness = 0.7f;
    stone.metallic_roughness_image = kMetallicRoughness;
    stone.patch = {
        {"pbrMetallicRoughness",
         {{"metallicRoughnessTexture",
           {{"index", kMetallicRoughness}, {"extensions", transform({{"offset", {0.5, 0.25}}})}}}}},
        {"occlusionTexture",
         {{"index", kOcclusion},
          {"strength", 0.7},
          {"extensions", transform({{"scale", {2.0, 2.0}}})}}}};

    scene::test::GltfTestMaterial& lamp = file.materials[2];
    lamp.name = "lamp";
    lamp.base_color = {0.2f, 0.2f, 0.2f, 1.0f};
    lamp.metallic = 0.0f;
    lamp.roughness = 0.5f;
    lamp.patch = {{"emissiveFactor", {0.8, 0.6, 0.4}},
                  {"emissiveTexture",
                   {{"index", kEmissive}, {"extensions", transform({{"offset", {0.5, 0.5}}})}}}};

    scene::test::GltfTestMaterial& glass = file.materials[3];
    glass.name = "glass";
    glass.base_color = {0.3f, 0.6f, 0.9f, 0.45f};
    glass.metallic = 0.0f;
    glass.roughness = 0.2f;
    glass.alpha_mode = "BLEND";
    glass.patch = {{"emissiveFactor", {0.05, 0.04, 0.03}}};

    for (int m = 0; m < 4; ++m) file.meshes.push_back({scene::test::unit_quad(m)});
    file.nodes = {{0, {}, {}, {-1.0, -1.0, 0.0}, {}},
                  {1, {}, {}, {0.0, -1.0, 0.0}, {}},
                  {2, {}, {}, {-1.0, 0.0, 0.0}, {}},
                  {3, {}, {}, {0.0, 0.0, 0.0}, {}}};
    file.patch = {{"extensionsUsed", {"KHR_texture_transform", "KHR_materials_anisotropy"}},
                  {"extensionsRequired", {"KHR_materials_anisotropy"}}};
    return file;
}

// The scene written as a .glb and loaded. The file's name carries the process id: ctest runs the
// parameters of one test (each BRDF) as processes side by side, which must not write one file.
scene::Scene material_scene(const scene::test::GltfTestFile& file, const std::string& name) {
    return scene::test::render_scene_of(file, "gltf_materials",
                                        name + "." + std::to_string(::getpid()));
}

glm::vec2 transformed(const scene::UvTransform& t, glm::vec2 uv) {
    return {glm::dot(glm::vec2(t.row0), uv) + t.row0.z, glm::dot(glm::vec2(t.row1), uv) + t.row1.z};
}

float as_half(float v) {
    return glm::unpackHalf1x16(glm::packHalf1x16(v));
}

// Texel (x, y) of `image` as GL reads it: rows uploaded flipped (y = 0 the bottom row),
// repeating; one channel reads (r, 0, 0, 1), three (r, g, b, 1).
glm::vec4 gl_texel(const Image& image, int x, int y, bool half) {
    x = ((x % image.width) + image.width) % image.width;
    y = ((y % image.height) + image.height) % image.height;
    glm::vec4 t(0.0f, 0.0f, 0.0f, 1.0f);
    for (int c = 0; c < image.channels; ++c) {
        const float v = image.at(x, image.height - 1 - y, c);
        t[c] = half ? as_half(v) : v;
    }
    return t;
}

// The bilinear read of level 0 at uv when every texel it (or a read 0.05 texel away) weighs is
// the same: that texel; else none.
std::optional<glm::vec4> uniform_read(const Image& image, glm::vec2 uv, bool half) {
    const glm::vec2 p = uv * glm::vec2(image.width, image.height) - 0.5f;
    const glm::ivec2 lo(glm::floor(p - 0.05f)), hi(glm::floor(p + 0.05f) + 1.0f);
    const glm::vec4 first = gl_texel(image, lo.x, lo.y, half);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
            if (gl_texel(image, x, y, half) != first) return std::nullopt;
    return first;
}

std::optional<glm::vec4> uniform_lean_read(const PackedLeanMap& map, int slice, glm::vec2 uv) {
    const int w = map.levels[0].width, h = map.levels[0].height;
    const glm::vec2 p = uv * glm::vec2(w, h) - 0.5f;
    const glm::ivec2 lo(glm::floor(p - 0.05f)), hi(glm::floor(p + 0.05f) + 1.0f);
    const auto texel = [&](int x, int y) {
        x = ((x % w) + w) % w;
        y = ((y % h) + h) % h;
        return fetch_packed_texel(map, 0, slice, x, h - 1 - y);
    };
    const glm::vec4 first = texel(lo.x, lo.y);
    for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x)
            if (texel(x, y) != first) return std::nullopt;
    return first;
}

// How a test quad maps onto its textures and its tangent frame, for the CPU side: leanfade's uv
// is the quad's (x, y) (unit_quad); uv1 is either a copy of it (no TEXCOORD_1) or the turned set
// (y, 1 - x) of two_set_quad; the tangent frame is the world axes (T = +x, B = +y) or, for tangents
// of the turned set, T = +y (along +u1), B = -x (along +v1). The quads are translated and
// uniformly scaled only, so object and world directions agree.
struct QuadMapping {
    bool turned_uv1 = false;
    bool frame_of_uv1 = false;
};

// A quad with TEXCOORD_1 = its TEXCOORD_0 turned by 90 degrees: leanfade's uv1 = (y, 1 - x),
// glTF's (y, x); orientation preserving (the tangents of set 1 keep w = +1).
scene::test::GltfTestPrimitive two_set_quad(int material) {
    scene::test::GltfTestPrimitive p = scene::test::unit_quad(material);
    for (const glm::vec3& q : p.positions) p.uvs1.push_back(glm::vec2(q.y, q.x));
    return p;
}

// Where a map with transform `t` samples at a point of texture coordinates uv and uv1.
glm::vec2 sampled_at(const scene::UvTransform& t, glm::vec2 uv, glm::vec2 uv1) {
    return transformed(t, t.set == 1 ? uv1 : uv);
}

// The pixels of each object of a comparison, those skipped on texel edges, and the worst error.
struct Comparison {
    std::vector<int> compared;
    int skipped = 0;
    double worst = 0.0;
};

// Draws `scene` (quads in the world's z = 0 plane, `mappings` one per object) with the lean
// technique and compares every pixel whose maps' reads are each one texel with the shared header
// on the CPU (the tolerance of the file's comment).
void compare_with_cpu(gl::Context& context, const scene::Scene& scene, Brdf brdf,
                      const std::vector<QuadMapping>& mappings, Comparison& out) {
    ASSERT_EQ(mappings.size(), scene.objects.size());
    out.compared.assign(scene.objects.size(), 0);
    gl::Renderer renderer(context);
    renderer.set_scene(scene);
    gl::RenderRequest request;
    request.technique = Technique::Lean;
    request.width = 144;
    request.height = 128;
    request.view = gl::view_at_distance(2.4f, 40.0f, {0.2f, -0.15f, 1.0f});
    ShadingSettings& s = request.settings;
    s.light_direction = {-0.4f, 0.5f, 0.8f};
    s.light_color = {1.0f, 0.95f, 0.9f};
    s.ambient = {0.3f, 0.28f, 0.25f};  // large enough that the occlusion shows
    s.brdf = brdf;
    s.shininess = 40.0f;
    s.tiling = 1.0f;
    s.geometric_aa = GeometricAa::Off;  // the CPU passes no footprint
    request.background = glm::vec3(0.1f, 0.2f, 0.3f);
    const Image gpu = renderer.render(request);

    const scene::Bounds bounds = scene::scene_bounds(scene);
    const glm::mat4 model = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / bounds.radius())) *
                            glm::translate(glm::mat4(1.0f), -bounds.center());
    const glm::mat4 view = request.view.view_matrix();
    const glm::mat4 inverse = glm::inverse(
        request.view.projection_matrix(float(request.width) / float(request.height)) * view);
    const glm::vec3 light_world = glm::normalize(s.light_direction);
    for (int y = 0; y < gpu.height; ++y) {
        for (int x = 0; x < gpu.width; ++x) {
            // The pixel centre's ray on the quads' plane (world z = 0).
            const glm::vec2 ndc((x + 0.5f) / gpu.width * 2.0f - 1.0f,
                                (gpu.height - 1 - y + 0.5f) / gpu.height * 2.0f - 1.0f);
            const glm::vec4 a = inverse * glm::vec4(ndc, -1.0f, 1.0f);
            const glm::vec4 b = inverse * glm::vec4(ndc, 1.0f, 1.0f);
            const glm::vec3 p0 = glm::vec3(a) / a.w, p1 = glm::vec3(b) / b.w;
            const glm::vec3 p = p0 + (p0.z / (p0.z - p1.z)) * (p1 - p0);
            int object = -1;
            glm::vec2 uv(0.0f);
            for (std::size_t o = 0; o < scene.objects.size(); ++o) {
                const glm::vec4 local =
                    glm::inverse(model * scene.objects[o].transform) * glm::vec4(p, 1.0f);
                if (local.x > 0.02f && local.x < 0.98f && local.y > 0.02f && local.y < 0.98f) {
                    object = int(o);
                    uv = glm::vec2(local);  // unit_quad: leanfade's uv = (x, y)
                }
            }
            if (object < 0) continue;
            const QuadMapping& mapping = mappings[std::size_t(object)];
            const glm::vec2 uv1 = mapping.turned_uv1 ? glm::vec2(uv.y, 1.0f - uv.x) : uv;
            const scene::Material& m =
                scene.materials[std::size_t(scene.objects[std::size_t(object)].material)];
            const PackedLeanMap& lean = scene.lean_maps[std::size_t(m.lean_map)];
            const std::optional<glm::vec4> lean1 =
                uniform_lean_read(lean, 0, sampled_at(m.lean_uv, uv, uv1));
            const std::optional<glm::vec4> lean2 =
                uniform_lean_read(lean, 1, sampled_at(m.lean_uv, uv, uv1));
            // Each surface map's texel: the map's where the material has it (and the BRDF reads
            // it), else the shader's value without it.
            bool uniform = lean1 && lean2;
            std::array<glm::vec4, scene::kMapKindCount> texels;
            std::array<bool, scene::kMapKindCount> read{};
            for (const scene::MapKindInfo& kind : scene::kMapKinds) {
                const int slot = m.map(kind.kind);
                read[std::size_t(kind.kind)] =
                    slot >= 0 && (!kind.cook_torrance_only || brdf == Brdf::CookTorrance);
                glm::vec4& t = texels[std::size_t(kind.kind)];
                t = kind.kind == scene::MapKind::Anisotropy ? glm::vec4(1.0f, 0.5f, 1.0f, 1.0f)
                                                            : glm::vec4(1.0f);
                if (!read[std::size_t(kind.kind)]) continue;
                const std::optional<glm::vec4> got =
                    uniform_read(scene.maps_of(kind.kind)[std::size_t(slot)][0],
                                 sampled_at(m.map_uv[std::size_t(kind.kind)], uv, uv1),
                                 kind.format == scene::MapFormat::Rgba16f);
                if (!got)
                    uniform = false;
                else
                    t = *got;
            }
            if (!uniform) {
                ++out.skipped;
                continue;
            }
            const auto texel = [&](scene::MapKind kind) { return texels[std::size_t(kind)]; };
            // The renderer's settings for the material, then the shared header's pipeline.
            ShadingSettings ms = s;
            if (m.diffuse) ms.kd = *m.diffuse;
            if (m.metallic) ms.metallic = 0.0f;
            const shading::LfParams params = to_lf_params(ms, lean.roughness_baked);
            shading::LfMaterialFactors factors;
            factors.emissive = m.emissive;
            factors.metallic = m.metallic.value_or(0.0f);
            factors.anisotropy_rotation =
                glm::vec2(std::cos(m.anisotropy_rotation), std::sin(m.anisotropy_rotation));
            factors.anisotropy_strength = m.anisotropy_strength;
            factors.occlusion_strength =
                m.map(scene::MapKind::Occlusion) >= 0 ? m.occlusion_strength : 0.0f;
            const shading::LfSurface surface = shading::lf_surface(
                texel(scene::MapKind::BaseColor), read[std::size_t(scene::MapKind::BaseRoughness)],
                texel(scene::MapKind::BaseRoughness).x, texel(scene::MapKind::Metallic).x,
                texel(scene::MapKind::Occlusion).x, texel(scene::MapKind::Emissive),
                texel(scene::MapKind::Anisotropy), factors);
            const shading::LfMoments moments = shading::lf_map_moments(
                *lean1, *lean2, lean.scale, lean_offset(lean.encoding), glm::vec4(0.0f));
            // The light and the eye in the quad's tangent frame (docs/math.md §1).
            const glm::mat3 frame =
                mapping.frame_of_uv1
                    ? glm::mat3(glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1))
                    : glm::mat3(1.0f);  // columns T, B, N
            const glm::mat3 to_tangent = glm::transpose(frame);
            const glm::vec3 light = to_tangent * light_world;
            const glm::vec3 view_t = to_tangent * (request.view.eye - p);
            const shading::LfShade shade = shading::lf_shade_surface(
                info(Technique::Lean).shader_technique, moments, surface, light, view_t, params);
            glm::vec3 expected = shading::lf_surface_color(shade, surface);
            if (m.blend) {  // straight alpha over the background
                const float alpha = texel(scene::MapKind::BaseColor).w * m.base_alpha;
                expected = alpha * expected + (1.0f - alpha) * request.background;
            }
            for (int ch = 0; ch < 3; ++ch) {
                const double want = expected[ch], got = gpu.at(x, y, ch);
                const double error = std::abs(got - want);
                out.worst = std::max(out.worst, error / (std::abs(want) + 1e-3));
                ASSERT_LE(error, 2e-3 * std::abs(want) + 2e-4)
                    << m.name << " pixel " << x << "," << y << " channel " << ch << ": gpu " << got
                    << " cpu " << want;
            }
            ++out.compared[std::size_t(object)];
        }
    }
}

TEST_P(GltfMaterials, AcceptanceSceneMatchesTheSharedHeaderPixelByPixel) {
    const Brdf brdf = GetParam();
    const scene::Scene scene = material_scene(acceptance_file(), "acceptance");
    ASSERT_EQ(scene.objects.size(), 4u);
    ASSERT_EQ(scene.materials.size(), 4u);
    // What the loader made of the file: the maps each material names.
    const scene::Material& metal = scene.materials[0];
    const scene::Material& stone = scene.materials[1];
    const scene::Material& lamp = scene.materials[2];
    EXPECT_GE(metal.map(scene::MapKind::Metallic), 0);
    EXPECT_GE(metal.map(scene::MapKind::Anisotropy), 0);
    EXPECT_FLOAT_EQ(metal.anisotropy_strength, 0.7f);
    EXPECT_GE(stone.map(scene::MapKind::Occlusion), 0);
    EXPECT_FLOAT_EQ(stone.occlusion_strength, 0.7f);
    EXPECT_FLOAT_EQ(*stone.metallic, 0.5f);
    EXPECT_GE(lamp.map(scene::MapKind::Emissive), 0);
    EXPECT_EQ(scene.materials[3].map(scene::MapKind::Emissive), -1);
    EXPECT_TRUE(scene.materials[3].blend);

    Comparison result;
    compare_with_cpu(context(), scene, brdf, std::vector<QuadMapping>(4), result);
    if (HasFatalFailure()) return;
    for (int o = 0; o < 4; ++o)
        EXPECT_GT(result.compared[std::size_t(o)], 400)
            << scene.materials[std::size_t(o)].name << ": pixels compared";
    RecordProperty("worst_relative_error", std::to_string(result.worst));
    std::printf(
        "%s: %d + %d + %d + %d pixels compared, %d on texel edges skipped, worst relative "
        "error %.3g\n",
        to_string(brdf), result.compared[0], result.compared[1], result.compared[2],
        result.compared[3], result.skipped, result.worst);
}

// Two quads whose TEXCOORD_1 is their TEXCOORD_0 turned by 90 degrees (two_set_quad), each map
// on the set its reference names:
//   "base colour on set 1"  base colour and metallic-roughness textures on TEXCOORD_1, a normal
//                           texture of four tilts and an occlusion texture on TEXCOORD_0, an
//                           emissive texture whose KHR_texture_transform overrides its texCoord 0
//                           with 1;
//   "normal on set 1"       the normal texture (so the LEAN map and the generated tangents) and
//                           an anisotropy texture on TEXCOORD_1, base colour on TEXCOORD_0.
// The CPU samples each map at the set the loader gave it and shades in the frame of the normal
// texture's set (T = +y, B = -x for the second quad): a shader that ignored the set, or
// tangents generated from TEXCOORD_0, differ by percents.
scene::test::GltfTestFile two_set_file() {
    scene::test::GltfTestFile file = acceptance_file();  // its images
    const glm::vec3 tilts[4] = {
        {0.25f, -0.15f, 1.0f}, {-0.3f, 0.1f, 1.0f}, {0.05f, 0.35f, 1.0f}, {-0.2f, -0.25f, 1.0f}};
    std::array<glm::vec4, 4> normal_blocks;
    for (int b = 0; b < 4; ++b)
        normal_blocks[b] = glm::vec4(0.5f * glm::normalize(tilts[b]) + 0.5f, 1.0f);
    file.images[kNormal] = block_png(3, normal_blocks);
    const auto transform = [](json value) { return json{{"KHR_texture_transform", value}}; };
    file.materials.assign(2, {});
    scene::test::GltfTestMaterial& first = file.materials[0];
    first.name = "base colour on set 1";
    first.base_color = {0.9f, 0.85f, 0.8f, 1.0f};
    first.base_color_image = kBaseColor;
    first.normal_image = kNormal;
    first.metallic = 0.6f;
    first.roughness = 0.8f;
    first.metallic_roughness_image = kMetallicRoughness;
    first.patch = {{"pbrMetallicRoughness",
                    {{"baseColorTexture", {{"texCoord", 1}}},
                     {"metallicRoughnessTexture", {{"texCoord", 1}}}}},
                   {"occlusionTexture", {{"index", kOcclusion}, {"strength", 0.8}}},
                   {"emissiveFactor", {0.5, 0.4, 0.3}},
                   {"emissiveTexture",
                    {{"index", kEmissive},
                     {"texCoord", 0},
                     {"extensions", transform({{"offset", {0.25, 0.0}}, {"texCoord", 1}})}}}};
    scene::test::GltfTestMaterial& second = file.materials[1];
    second.name = "normal on set 1";
    second.base_color = {0.8f, 0.8f, 0.85f, 1.0f};
    second.base_color_image = kBaseColor;
    second.normal_image = kNormal;
    second.metallic = 0.3f;
    second.roughness = 0.6f;
    second.patch = {{"normalTexture", {{"texCoord", 1}}},
                    {"extensions",
                     {{"KHR_materials_anisotropy",
                       {{"anisotropyStrength", 0.6},
                        {"anisotropyTexture", {{"index", kAnisotropy}, {"texCoord", 1}}}}}}}};
    file.meshes = {{two_set_quad(0)}, {two_set_quad(1)}};
    file.nodes = {{0, {}, {}, {-1.0, -0.5, 0.0}, {}}, {1, {}, {}, {0.0, -0.5, 0.0}, {}}};
    file.patch = {{"extensionsUsed", {"KHR_texture_transform", "KHR_materials_anisotropy"}}};
    return file;
}

TEST_P(GltfMaterials, EachMapSamplesTheTextureCoordinateSetItsReferenceNames) {
    const Brdf brdf = GetParam();
    const scene::Scene scene = material_scene(two_set_file(), "two_sets");
    ASSERT_EQ(scene.objects.size(), 2u);
    ASSERT_EQ(scene.materials.size(), 2u);
    // The sets as the file names them (the loader's test checks them one by one).
    const scene::Material& first = scene.materials[0];
    const scene::Material& second = scene.materials[1];
    const auto set = [](const scene::Material& m, scene::MapKind kind) {
        return m.map_uv[std::size_t(kind)].set;
    };
    EXPECT_EQ(set(first, scene::MapKind::BaseColor), 1);
    EXPECT_EQ(set(first, scene::MapKind::Metallic), 1);
    EXPECT_EQ(set(first, scene::MapKind::Occlusion), 0);
    EXPECT_EQ(set(first, scene::MapKind::Emissive), 1);
    EXPECT_EQ(first.lean_uv.set, 0);
    EXPECT_EQ(second.lean_uv.set, 1);
    EXPECT_EQ(set(second, scene::MapKind::BaseColor), 0);
    EXPECT_EQ(set(second, scene::MapKind::Anisotropy), 1);
    EXPECT_GE(second.map(scene::MapKind::Anisotropy), 0);
    const std::vector<QuadMapping> mappings = {{true, false}, {true, true}};
    Comparison result;
    compare_with_cpu(context(), scene, brdf, mappings, result);
    if (HasFatalFailure()) return;
    for (int o = 0; o < 2; ++o)
        EXPECT_GT(result.compared[std::size_t(o)], 1000)
            << scene.materials[std::size_t(o)].name << ": pixels compared";
    RecordProperty("worst_relative_error", std::to_string(result.worst));
    std::printf(
        "%s: %d + %d pixels compared, %d on texel edges skipped, worst relative error "
        "%.3g\n",
        to_string(brdf), result.compared[0], result.compared[1], result.skipped, result.worst);
}

INSTANTIATE_TEST_SUITE_P(Brdfs, GltfMaterials,
                         ::testing::Values(Brdf::CookTorrance, Brdf::BlinnPhong),
                         [](const ::testing::TestParamInfo<Brdf>& info) {
                             return info.param == Brdf::CookTorrance ? std::string("CookTorrance")
                                                                     : std::string("BlinnPhong");
                         });

// The header's material terms against the glTF specification's formulas, written out here.
shading::LfMaterialFactors no_factors() {
    shading::LfMaterialFactors f;
    f.emissive = glm::vec3(0.0f);
    f.metallic = 0.0f;
    f.anisotropy_rotation = glm::vec2(1.0f, 0.0f);
    f.anisotropy_strength = 0.0f;
    f.occlusion_strength = 0.0f;
    return f;
}

const glm::vec4 kWhite(1.0f);
const glm::vec4 kNoAnisotropyTexture(1.0f, 0.5f, 1.0f, 1.0f);

TEST(GltfSurface, MetalnessFollowsTheMetalRoughnessModel) {
    ShadingSettings s;
    s.kd = {0.8f, 0.5f, 0.2f};  // the base colour factor
    const glm::vec4 texture(0.5f, 0.9f, 0.4f, 1.0f);
    const glm::vec3 base = s.kd * glm::vec3(texture);
    for (const float metallic_texel : {0.0f, 0.25f, 1.0f}) {
        shading::LfMaterialFactors f = no_factors();
        f.metallic = 0.8f;
        const float m = 0.8f * metallic_texel;  // glTF 2.0 §3.9.2: factor x B
        // Cook-Torrance, glTF 2.0 Appendix B: c_diff = lerp(base, 0, m), F0 = lerp(0.04, base, m).
        s.brdf = Brdf::CookTorrance;
        const shading::LfSurface surface = shading::lf_surface(
            texture, false, 0.0f, metallic_texel, 1.0f, kWhite, kNoAnisotropyTexture, f);
        EXPECT_FLOAT_EQ(surface.metallic, m);
        const shading::LfParams ct = shading::lf_surface_params(to_lf_params(s, false), surface);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(ct.kd[c], base[c] * (1.0f - m), 1e-6f);
            EXPECT_NEAR(ct.f0[c], 0.04f + (base[c] - 0.04f) * m, 1e-6f);
        }
        // Blinn-Phong: the same rule on Ks.
        s.brdf = Brdf::BlinnPhong;
        s.ks = glm::vec3(0.6f);
        const shading::LfParams bp = shading::lf_surface_params(to_lf_params(s, false), surface);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(bp.kd[c], base[c] * (1.0f - m), 1e-6f);
            EXPECT_NEAR(bp.ks[c], 0.6f + (base[c] - 0.6f) * m, 1e-6f);
        }
    }
}

TEST(GltfSurface, OcclusionWeighsTheAmbientTermByItsStrength) {
    ShadingSettings s;
    s.ambient = {0.2f, 0.3f, 0.4f};
    for (const float strength : {0.0f, 0.5f, 1.0f})
        for (const float occlusion : {0.0f, 0.3f, 1.0f}) {
            shading::LfMaterialFactors f = no_factors();
            f.occlusion_strength = strength;
            const shading::LfSurface surface = shading::lf_surface(
                kWhite, false, 0.0f, 1.0f, occlusion, kWhite, kNoAnisotropyTexture, f);
            const shading::LfParams p = shading::lf_surface_params(to_lf_params(s, false), surface);
            // glTF 2.0 §3.9.4: lerp(color, color x occlusion, strength).
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(p.ambient[c],
                            s.ambient[c] + strength * (s.ambient[c] * occlusion - s.ambient[c]),
                            1e-6f);
        }
}

TEST(GltfSurface, EmissionIsTheFactorTimesTheTextureAddedToTheColour) {
    shading::LfMaterialFactors f = no_factors();
    f.emissive = {0.8f, 0.6f, 0.4f};
    const glm::vec4 texture(0.5f, 0.25f, 1.0f, 1.0f);
    const shading::LfSurface surface =
        shading::lf_surface(kWhite, false, 0.0f, 1.0f, 1.0f, texture, kNoAnisotropyTexture, f);
    shading::LfShade shade;
    shade.diffuse = glm::vec3(0.1f, 0.2f, 0.3f);
    shade.specular = glm::vec3(0.05f);
    const glm::vec3 color = shading::lf_surface_color(shade, surface);
    for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(color[c],
                        shade.diffuse[c] + shade.specular[c] + f.emissive[c] * texture[c]);
}

// KHR_materials_anisotropy: direction = R(rotation) (2 rg - 1), strength = b x anisotropyStrength,
// alpha_t = mix(alpha, 1, strength^2) along the direction, alpha_b = alpha across it; as slope
// covariances (alpha^2 / 2 per axis) the base's Sigma0 = R diag(alpha_t^2, alpha^2) R^T / 2.
TEST(GltfSurface, AnisotropyStretchesTheBaseRoughnessAlongItsDirection) {
    const float rotation = 0.6f;
    shading::LfMaterialFactors f = no_factors();
    f.anisotropy_rotation = {std::cos(rotation), std::sin(rotation)};
    f.anisotropy_strength = 0.8f;
    // The texture's direction +v at strength 0.5: +v rotated by 0.6 rad counter-clockwise.
    const glm::vec4 texture(0.5f, 1.0f, 0.5f, 1.0f);
    const shading::LfSurface surface =
        shading::lf_surface(kWhite, true, 0.09f, 1.0f, 1.0f, kWhite, texture, f);
    const float phi = 1.5707963f + rotation;
    EXPECT_NEAR(surface.anisotropy_direction.x, std::cos(phi), 1e-6f);
    EXPECT_NEAR(surface.anisotropy_direction.y, std::sin(phi), 1e-6f);
    EXPECT_FLOAT_EQ(surface.anisotropy, 0.4f);
    const float alpha = 0.3f;  // alpha^2 = 0.09
    const float alpha_t = alpha + (1.0f - alpha) * 0.4f * 0.4f;
    const glm::vec3 extra =
        shading::lf_anisotropy_covariance(surface.anisotropy_direction, surface.anisotropy, 0.09f);
    const glm::mat2 r(std::cos(phi), std::sin(phi), -std::sin(phi), std::cos(phi));
    const glm::mat2 sigma0 = r *
                             glm::mat2(0.5f * alpha_t * alpha_t, 0.0f, 0.0f, 0.5f * alpha * alpha) *
                             glm::transpose(r);
    EXPECT_NEAR(0.5f * alpha * alpha + extra.x, sigma0[0][0], 1e-6f);
    EXPECT_NEAR(0.5f * alpha * alpha + extra.y, sigma0[1][1], 1e-6f);
    EXPECT_NEAR(extra.z, sigma0[0][1], 1e-6f);
    // Without strength, nothing changes, bit for bit; with Blinn-Phong, the shade ignores it.
    EXPECT_EQ(shading::lf_anisotropy_covariance(surface.anisotropy_direction, 0.0f, 0.09f),
              glm::vec3(0.0f));
    ShadingSettings s;
    const shading::LfMoments flat =
        shading::lf_map_moments(glm::vec4(0.5f, 0.5f, 1.0f, 0.5f),
                                glm::vec4(0.5f, 0.5f, 0.0f, 0.0f), 1.0f, 1.0f, glm::vec4(0.0f));
    const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.1f, 1.0f));
    const glm::vec3 eye(-0.4f, 0.2f, 2.0f);
    const shading::LfSurface plain = shading::lf_surface(kWhite, true, 0.09f, 1.0f, 1.0f, kWhite,
                                                         kNoAnisotropyTexture, no_factors());
    s.brdf = Brdf::BlinnPhong;
    const auto specular = [&](const shading::LfSurface& surf) {
        return shading::lf_shade_surface(shading::LF_TECHNIQUE_LEAN, flat, surf, light, eye,
                                         to_lf_params(s, false))
            .specular;
    };
    EXPECT_EQ(specular(surface), specular(plain));
    s.brdf = Brdf::CookTorrance;
    EXPECT_NE(specular(surface), specular(plain));
}

// A highlight off the normal along the stretch is brighter than one as far off across it: the
// lobe is wider along the direction (Cook-Torrance with the anisotropic base roughness).
TEST(GltfSurface, AnisotropicHighlightsSpreadAlongTheDirection) {
    ShadingSettings s;
    s.brdf = Brdf::CookTorrance;
    s.roughness = 0.3f;
    shading::LfMaterialFactors f = no_factors();
    f.anisotropy_strength = 0.9f;
    const shading::LfSurface along_u =
        shading::lf_surface(kWhite, false, 0.0f, 1.0f, 1.0f, kWhite, kNoAnisotropyTexture, f);
    const shading::LfMoments flat =
        shading::lf_map_moments(glm::vec4(0.5f, 0.5f, 1.0f, 0.5f),
                                glm::vec4(0.5f, 0.5f, 0.0f, 0.0f), 1.0f, 1.0f, glm::vec4(0.0f));
    const glm::vec3 eye(0.0f, 0.0f, 3.0f);
    const auto specular = [&](glm::vec3 light) {
        return shading::lf_shade_surface(shading::LF_TECHNIQUE_LEAN, flat, along_u,
                                         glm::normalize(light), eye, to_lf_params(s, false))
            .specular.x;
    };
    const float toward_u = specular({0.6f, 0.0f, 1.0f});
    const float toward_v = specular({0.0f, 0.6f, 1.0f});
    EXPECT_GT(toward_u, 3.0f * toward_v) << toward_u << " vs " << toward_v;
}

}  // namespace
