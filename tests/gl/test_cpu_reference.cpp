// The GPU output equals the CPU evaluation of the shared header (leanfade/core/shading.hpp) pixel
// by pixel: a flat quad with a constant LEAN map, rendered to a float target.
//
// The CPU runs the shared header's fragment pipeline (lf_map_moments, lf_shade_material) on the
// texels it fetches, as scene.frag does on its filtered reads.
//
// Tolerance: |gpu - cpu| <= 2e-3 |cpu| + 2e-4 per channel (radiance values here are 0.01-5).
// Both sides run the same float formulas; the differences come from (a) the GPU's exp2/log2
// approximations in exp() and pow() (relative error about 1e-6 before the exponent amplifies it:
// pow(x, s) multiplies the error of log2(x) by s = 64, and e <= ~40 in exp(-e/2)), (b) the
// rasteriser's perspective-correct interpolation of Vt and of the light vector versus the CPU's
// exact ray-plane intersection at the pixel centre (about 1e-6 of the eye distance), (c) the float
// order of operations. Measured on llvmpipe the largest relative error is near 1e-5; the bound
// leaves two orders of magnitude for other drivers while catching any formula change (a wrong
// constant, sc, 1/s or a missing term changes values by percents).
//
// With a base roughness map (Cook-Torrance, docs/math.md §9) the quad's map has r = 0.2 on its
// left half (u < 0.5) and r = 0.6 on its right half, 8 x 8 texels magnified (level 0 only): the
// CPU takes α0² of the texel under the pixel and compares the pixels whose bilinear footprint lies
// in one half (the others blend the halves by the rasteriser's filter weights).
#include <cmath>
#include <ostream>

#include <glm/gtc/matrix_transform.hpp>

#include "gl_test_helpers.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/scene/material.hpp"

namespace leanfade::test {
namespace {

struct Case {
    const char* name;
    gl::Technique technique;
    FadeDistance fade_distance = FadeDistance::TangentZ;
    FogMode fog = FogMode::None;
    float fade_exponent = 2.0f;  // 2: the LF_FADE_EXPONENT_2 variant; other values: pow
    Brdf brdf = Brdf::BlinnPhong;
    bool roughness_map = false;  // the half-and-half base roughness map (Cook-Torrance)
    // Two-lobe LEAN's plateau layer (docs/math.md §10), constant over the quad: f = 0.4 of its
    // texels on a plateau of slope (0.1, -0.05) with a little spread; false: none (f = 0).
    bool plateau = false;
};

// The plateau texel (f, f Bs, f |Bs|^2) of Case::plateau.
const glm::vec4 kPlateauTexel(0.4f, 0.04f, -0.02f, 0.4f * (0.0125f + 0.0002f));

constexpr int kMapSize = 8;  // texels per side of the LEAN and roughness maps with a map

// Perceptual roughness of the map's column x: 0.2 on the left half, 0.6 on the right (repeating).
float map_roughness(int x) {
    x = ((x % kMapSize) + kMapSize) % kMapSize;
    return x < kMapSize / 2 ? 0.2f : 0.6f;
}

// Test names show the case's name instead of its bytes.
void PrintTo(const Case& c, std::ostream* os) {
    *os << c.name;
}

class GpuMatchesCpu : public GlTest, public ::testing::WithParamInterface<Case> {};

TEST_P(GpuMatchesCpu, PixelByPixel) {
    const Case& c = GetParam();
    const PackedLeanMap map =
        make_constant_lean_map({0.12f, -0.07f}, {0.010f, 0.018f, 0.004f}, 0.97f, Storage::Float32,
                               c.roughness_map ? kMapSize : 4);
    Image roughness(kMapSize, kMapSize, 1);
    for (int y = 0; y < kMapSize; ++y)
        for (int x = 0; x < kMapSize; ++x) roughness.at(x, y) = map_roughness(x);
    const std::vector<Image> alpha0_squared = base_alpha_squared_mips(roughness);

    gl::Renderer renderer(context());
    const scene::Mesh quad = make_test_quad();
    if (c.roughness_map || c.plateau) {
        scene::Scene scene;
        scene.objects.push_back(scene::Object{quad, 0, glm::mat4(1.0f)});
        scene::Material material;
        if (c.roughness_map)
            material.map(scene::MapKind::BaseRoughness) =
                scene.add_map(scene::MapKind::BaseRoughness, alpha0_squared);
        if (c.plateau) {
            Image plateau(4, 4, 4);
            for (int i = 0; i < 16; ++i)
                for (int ch = 0; ch < 4; ++ch) plateau.pixels[std::size_t(i * 4 + ch)] = kPlateauTexel[ch];
            material.map(scene::MapKind::Plateau) =
                scene.add_map(scene::MapKind::Plateau, build_mip_chain(plateau));
        }
        scene.materials.push_back(material);
        scene.lean_maps.push_back(map);
        renderer.set_scene(scene);
    } else {
        renderer.set_mesh(quad);
        renderer.set_lean_map(map);
    }

    gl::RenderRequest request;
    request.technique = c.technique;
    request.width = 72;
    request.height = 56;
    request.view = gl::view_at_distance(2.2f, 40.0f, {0.35f, -0.25f, 1.0f});
    ShadingSettings& s = request.settings;
    s.light_direction = {-0.4f, 0.5f, 0.8f};
    s.light_color = {1.0f, 0.95f, 0.9f};
    s.shininess = 64.0f;
    s.fade = 0.6f;  // sf = 1 + (d Fade)^2 between ~1.8 and Pmax over the quad
    s.pmax = 6.0f;
    s.fade_distance = c.fade_distance;
    s.fade_exponent = c.fade_exponent;
    s.fog = c.fog;
    s.fog_color = {0.3f, 0.4f, 0.5f};
    s.fog_density = 0.3f;
    s.brdf = c.brdf;
    s.roughness = 0.45f;
    s.metallic = 0.3f;
    // The CPU passes no footprint: geometric antialiasing (docs/math.md §11) stays off here.
    s.geometric_aa = GeometricAa::Off;
    request.background = glm::vec3(-1.0f);  // marks uncovered pixels
    const Image gpu = renderer.render(request);

    // CPU: cast a ray through each pixel centre, intersect the quad's plane (world z = 0; the
    // model matrix only scales it by 1/sqrt(2)), shade with the shared header.
    const shading::LfParams params = to_lf_params(s, map.roughness_baked);
    const glm::vec4 lean1 = fetch_packed_texel(map, 0, 0, 0, 0);
    const glm::vec4 lean2 = fetch_packed_texel(map, 0, 1, 0, 0);
    if (c.roughness_map && c.technique == gl::Technique::Roughness) {
        // The engine texel the shader builds from the map's α0² is the one `leanfade bake
        // --roughness-out --roughness-map` writes, within its 8-bit rounding.
        RoughnessOptions options;
        options.roughness_map = &roughness;
        const RoughnessTextures baked =
            roughness_textures(roughness_mips(unpack_lean_map(map), options), nullptr);
        for (int x : {0, kMapSize - 1}) {
            const glm::vec4 texel = shading::lf_roughness_mip_texel(
                lean1, lean2, map.scale, lean_offset(map.encoding), alpha0_squared[0].at(x, 0));
            const float r = baked.metallic_roughness[0].at(x, 0, 1);
            EXPECT_NEAR(texel.w, std::round(r * 255.0f) / 255.0f, 1.0f / 255.0f + 1e-6f);
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(texel[ch], std::round(baked.normal[0].at(x, 0, ch) * 255.0f) / 255.0f,
                            1.0f / 255.0f + 1e-6f);
        }
    }
    const glm::mat4 view = request.view.view_matrix();
    const glm::mat4 inverse = glm::inverse(
        request.view.projection_matrix(float(request.width) / float(request.height)) * view);
    const float half = 1.0f / std::sqrt(2.0f);
    const glm::vec3 light = glm::normalize(s.light_direction);
    int compared = 0, blended = 0;
    int compared_per_half[2] = {0, 0};
    double worst = 0.0;
    for (int y = 0; y < gpu.height; ++y) {
        for (int x = 0; x < gpu.width; ++x) {
            const glm::vec2 ndc((x + 0.5f) / gpu.width * 2.0f - 1.0f,
                                (gpu.height - 1 - y + 0.5f) / gpu.height * 2.0f - 1.0f);
            glm::vec4 a = inverse * glm::vec4(ndc, -1.0f, 1.0f);
            glm::vec4 b = inverse * glm::vec4(ndc, 1.0f, 1.0f);
            const glm::vec3 p0 = glm::vec3(a) / a.w, p1 = glm::vec3(b) / b.w;
            const float t = p0.z / (p0.z - p1.z);
            const glm::vec3 p = p0 + t * (p1 - p0);
            const bool inside = std::abs(p.x) < half * 0.97f && std::abs(p.y) < half * 0.97f;
            if (gpu.at(x, y, 0) == -1.0f) {
                EXPECT_FALSE(std::abs(p.x) < half * 0.97f && std::abs(p.y) < half * 0.97f)
                    << "uncovered pixel inside the quad at " << x << "," << y;
                continue;
            }
            if (!inside) continue;
            // Tangent frame = world axes (T = +x, Bt = +y, N = +z).
            const glm::vec3 view_t = request.view.eye - p;
            float base = 2.0f * params.inv_s_shading;  // α0² of the uniform roughness
            if (c.roughness_map) {
                // The map's texel columns under the bilinear footprint at u (level 0).
                const float u = p.x / (2.0f * half) + 0.5f;
                const int left = int(std::floor(u * kMapSize - 0.5f));
                if (map_roughness(left) != map_roughness(left + 1)) {
                    ++blended;
                    continue;
                }
                base = base_alpha_squared(map_roughness(left));
                ++compared_per_half[map_roughness(left) < 0.5f ? 0 : 1];
            }
            // scene.frag's pipeline on the texels: the moments of the LEAN map and the plateau
            // layer, then the material (no base colour texture: white; the map's α0²) and the
            // shade.
            shading::LfMoments moments =
                shading::lf_map_moments(lean1, lean2, map.scale, lean_offset(map.encoding),
                                        c.plateau ? kPlateauTexel : glm::vec4(0.0f));
            // Roughness MIPs: the engine texel of the (constant) map, which any filtering keeps.
            if (c.technique == gl::Technique::Roughness)
                moments = shading::lf_roughness_mips_moments(shading::lf_roughness_mip_texel(
                    lean1, lean2, map.scale, lean_offset(map.encoding), base));
            const shading::LfShade shade = shading::lf_shade_material(
                info(c.technique).shader_technique, moments, glm::vec4(1.0f),
                c.roughness_map && s.brdf == Brdf::CookTorrance, base, light, view_t, params);
            glm::vec3 expected = shade.diffuse + shade.specular;
            const float depth = -(view * glm::vec4(p, 1.0f)).z;
            const float f = shading::lf_fog_factor(depth, to_shader_constant(s.fog), s.fog_start,
                                                   s.fog_end, s.fog_density);
            expected = shading::lf_apply_fog(expected, s.fog_color, f);
            for (int ch = 0; ch < 3; ++ch) {
                const double want = expected[ch], got = gpu.at(x, y, ch);
                const double error = std::abs(got - want);
                worst = std::max(worst, error / (std::abs(want) + 1e-3));
                ASSERT_LE(error, 2e-3 * std::abs(want) + 2e-4)
                    << c.name << " pixel " << x << "," << y << " channel " << ch << ": gpu " << got
                    << " cpu " << want;
            }
            ++compared;
        }
    }
    EXPECT_GT(compared, gpu.width * gpu.height / (c.roughness_map ? 6 : 4))
        << "the quad must cover much of the image";
    if (c.roughness_map) {
        EXPECT_GT(compared_per_half[0], 200) << "pixels of r = 0.2";
        EXPECT_GT(compared_per_half[1], 200) << "pixels of r = 0.6";
        std::printf("%s: %d + %d pixels of r = 0.2 and 0.6, %d blending them skipped\n", c.name,
                    compared_per_half[0], compared_per_half[1], blended);
    }
    RecordProperty("worst_relative_error", std::to_string(worst));
    std::printf("%s: %d pixels, worst relative error %.3g\n", c.name, compared, worst);
}

INSTANTIATE_TEST_SUITE_P(
    Shading, GpuMatchesCpu,
    ::testing::Values(
        Case{"bump", gl::Technique::Bump}, Case{"lean", gl::Technique::Lean},
        Case{"toksvig", gl::Technique::Toksvig}, Case{"clean", gl::Technique::Clean},
        Case{"fade_tangent_z", gl::Technique::Fade},
        Case{"fade_eye", gl::Technique::Fade, FadeDistance::Eye},
        Case{"fade_power_1_7", gl::Technique::Fade, FadeDistance::TangentZ, FogMode::None, 1.7f},
        Case{"fade_exp_fog", gl::Technique::Fade, FadeDistance::Eye, FogMode::Exp},
        Case{"lean_exp_fog", gl::Technique::Lean, FadeDistance::TangentZ, FogMode::Exp},
        // The Cook-Torrance lobe stage of every technique (docs/math.md §9).
        Case{"bump_ct", gl::Technique::Bump, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance},
        Case{"toksvig_ct", gl::Technique::Toksvig, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance},
        Case{"clean_ct", gl::Technique::Clean, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance},
        Case{"lean_ct", gl::Technique::Lean, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance},
        Case{"fade_ct", gl::Technique::Fade, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance},
        Case{"fade_eye_ct_fog", gl::Technique::Fade, FadeDistance::Eye, FogMode::Exp, 1.7f,
             Brdf::CookTorrance},
        // Roughness MIPs (docs/roughness.md) in both BRDFs.
        // Two-lobe LEAN (docs/math.md §10) with and without a plateau layer, both BRDFs.
        Case{"two_lobe", gl::Technique::TwoLobe, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::BlinnPhong, false, true},
        Case{"two_lobe_no_plateau", gl::Technique::TwoLobe},
        Case{"two_lobe_ct", gl::Technique::TwoLobe, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance, false, true},
        Case{"two_lobe_ct_map", gl::Technique::TwoLobe, FadeDistance::TangentZ, FogMode::None,
             2.0f, Brdf::CookTorrance, true, true},
                Case{"roughness", gl::Technique::Roughness},
        Case{"roughness_ct", gl::Technique::Roughness, FadeDistance::TangentZ, FogMode::None,
             2.0f, Brdf::CookTorrance},
        // A base roughness map (docs/math.md §9): α0² per texel in every Cook-Torrance stage.
        Case{"bump_ct_map", gl::Technique::Bump, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance, true},
        Case{"toksvig_ct_map", gl::Technique::Toksvig, FadeDistance::TangentZ, FogMode::None,
             2.0f, Brdf::CookTorrance, true},
        Case{"clean_ct_map", gl::Technique::Clean, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance, true},
        Case{"lean_ct_map", gl::Technique::Lean, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance, true},
        Case{"fade_ct_map", gl::Technique::Fade, FadeDistance::TangentZ, FogMode::None, 2.0f,
             Brdf::CookTorrance, true},
        Case{"fade_eye_ct_fog_map", gl::Technique::Fade, FadeDistance::Eye, FogMode::Exp, 1.7f,
             Brdf::CookTorrance, true},
        Case{"roughness_ct_map", gl::Technique::Roughness, FadeDistance::TangentZ, FogMode::None,
             2.0f, Brdf::CookTorrance, true}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

// Core images are stored top row first; the upload flips them so that the top row lies at v = 1
// (+v up, docs/math.md §1). A 2 x 2 map whose top row tilts toward +x and bottom row toward -x, on
// the camera-facing quad (v up the screen) lit from +x: the upper half must be the brighter one.
class TextureOrientation : public GlTest {};

TEST_F(TextureOrientation, TopImageRowIsPlusV) {
    LeanMap map;
    MomentLevel top;
    top.width = 2;
    top.height = 2;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
            const glm::vec2 b(y == 0 ? 0.4f : -0.4f, 0.0f);  // row 0 = top of the image
            top.mean.push_back(b);
            top.second.push_back(glm::vec3(b.x * b.x, 0.0f, 0.0f));
            top.normal.push_back(glm::normalize(glm::vec3(b, 1.0f)));
        }
    MomentLevel coarse;
    coarse.width = coarse.height = 1;
    coarse.mean = {glm::vec2(0.0f)};
    coarse.second = {glm::vec3(0.16f, 0.0f, 0.0f)};
    coarse.normal = {glm::vec3(0.0f, 0.0f, 0.93f)};
    map.levels = {top, coarse};
    map.scale = 0.4f;
    gl::Renderer renderer(context());
    renderer.set_mesh(make_test_quad());
    renderer.set_lean_map(pack_lean_map(map, Storage::Float32, "leanfade tests"));
    gl::RenderRequest request;
    request.technique = gl::Technique::Bump;
    request.width = request.height = 64;
    request.view = gl::view_at_distance(2.0f, 40.0f, {0.0f, 0.0f, 1.0f});
    request.settings.light_direction = {1.0f, 0.0f, 0.6f};
    request.output = gl::OutputMode::Diffuse;
    const Image image = renderer.render(request);
    const float upper = image.at(32, 20, 0), lower = image.at(32, 44, 0);
    EXPECT_GT(upper, 1.2f * lower) << "upper " << upper << " lower " << lower;
}

}  // namespace
}  // namespace leanfade::test
