// glTF scenes drawn by the renderer (OpenGL; llvmpipe here, never skipped): a normal texture
// tilted toward +u shades the quad brighter under a light at +u (object space +x) than under the
// mirror light, as the uv flip and the tangents promise, and the base colour texture multiplies
// Kd (a red texture leaves the diffuse term red).
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "gl_test_helpers.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/scene/gltf.hpp"
#include "gltf_render_scene.hpp"
#include "test_gltf_builder.hpp"

using namespace leanfade;

namespace {

namespace fs = std::filesystem;

class GltfRender : public test::GlTest {};

std::vector<std::uint8_t> uniform_png(glm::vec3 rgb) {
    std::vector<float> pixels;
    for (int i = 0; i < 16; ++i)
        for (int c = 0; c < 3; ++c) pixels.push_back(rgb[c]);
    return scene::test::png_bytes(4, 4, 3, pixels);
}

// The renderer's scene of `file`, written as NAME.glb and read back as a user's file is.
scene::Scene scene_of(const scene::test::GltfTestFile& file, const std::string& name) {
    return scene::test::render_scene_of(file, "gltf_render", name);
}

// The quad (object xy plane, facing +z; the image's top row at y = 1) with one material.
scene::Scene quad_scene(const std::string& name, int normal_image, int base_color_image,
                        const std::vector<std::vector<std::uint8_t>>& images) {
    scene::test::GltfTestFile file;
    file.images = images;
    file.materials = {{"m", glm::vec4(1.0f), base_color_image, normal_image, 1.0f}};
    file.materials[0].metallic = 0.0f;  // a dielectric: glTF's default metalness is 1
    file.meshes = {{scene::test::unit_quad(0)}};
    return scene_of(file, name);
}

Image render(gl::Renderer& renderer, glm::vec3 light, gl::OutputMode output) {
    gl::RenderRequest r;
    r.technique = Technique::Lean;
    r.width = r.height = 64;
    r.view = gl::view_at_distance(2.5f, gl::kDefaultFovYDegrees, glm::vec3(0, 0, 1));
    r.settings.light_direction = light;
    r.output = output;
    return renderer.render(r);
}

glm::dvec3 channel_sums(const Image& image) {
    glm::dvec3 sum(0.0);
    for (std::size_t i = 0; i < image.texel_count(); ++i)
        for (int c = 0; c < 3; ++c)
            sum[c] += image.pixels[i * std::size_t(image.channels) + std::size_t(c)];
    return sum;
}

TEST_F(GltfRender, NormalTextureTiltedTowardPlusUFacesALightAtPlusX) {
    gl::Renderer renderer(context());
    // Normal (0.5, 0, 0.866) in the image's +X: toward +u, the quad's object +x.
    renderer.set_scene(quad_scene("tilted", 0, -1, {uniform_png({0.75f, 0.5f, 0.933f})}));
    const double toward = channel_sums(render(renderer, {1, 0, 1}, gl::OutputMode::Diffuse)).x;
    const double away = channel_sums(render(renderer, {-1, 0, 1}, gl::OutputMode::Diffuse)).x;
    // Lambert with the tilted normal: cos(15 deg) against cos(75 deg) (plus the ambient term).
    EXPECT_GT(toward, 2.5 * away) << toward << " vs " << away;
    // Tilted toward the image's top (+Y, OpenGL convention): the quad's +y.
    renderer.set_scene(quad_scene("up", 0, -1, {uniform_png({0.5f, 0.75f, 0.933f})}));
    const double up = channel_sums(render(renderer, {0, 1, 1}, gl::OutputMode::Diffuse)).x;
    const double down = channel_sums(render(renderer, {0, -1, 1}, gl::OutputMode::Diffuse)).x;
    EXPECT_GT(up, 2.5 * down) << up << " vs " << down;
    // A flat texture: both lights alike.
    renderer.set_scene(quad_scene("flat", 0, -1, {uniform_png({0.5f, 0.5f, 1.0f})}));
    const double left = channel_sums(render(renderer, {1, 0, 1}, gl::OutputMode::Diffuse)).x;
    const double right = channel_sums(render(renderer, {-1, 0, 1}, gl::OutputMode::Diffuse)).x;
    EXPECT_NEAR(left / right, 1.0, 0.02);
}

TEST_F(GltfRender, BaseColourTextureMultipliesKd) {
    gl::Renderer renderer(context());
    renderer.set_scene(quad_scene("white", -1, -1, {}));
    const glm::dvec3 white = channel_sums(render(renderer, {0, 0, 1}, gl::OutputMode::Diffuse));
    renderer.set_scene(quad_scene("red", -1, 0, {uniform_png({1.0f, 0.0f, 0.0f})}));
    const glm::dvec3 red = channel_sums(render(renderer, {0, 0, 1}, gl::OutputMode::Diffuse));
    EXPECT_NEAR(red.x / white.x, 1.0, 0.01);
    // Green and blue keep only the ambient term: far below white's.
    EXPECT_LT(red.y, 0.1 * white.y);
    EXPECT_LT(red.z, 0.1 * white.z);
}

// alphaMode MASK: texels whose base colour alpha (texture times factor) is below alphaCutoff are
// cut out; the same quad OPAQUE covers them.
TEST_F(GltfRender, AlphaMaskCutsOutTexelsBelowTheCutoff) {
    // A 4 x 4 RGBA base colour: the left half (u < 0.5) alpha 0.2, the right half 0.9.
    std::vector<float> rgba;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) rgba.insert(rgba.end(), {1.0f, 1.0f, 1.0f, x < 2 ? 0.2f : 0.9f});
    const std::vector<std::uint8_t> texture = scene::test::png_bytes(4, 4, 4, rgba);
    const auto covered = [&](const std::string& name, const std::string& mode, float factor_alpha) {
        scene::test::GltfTestFile file;
        file.images = {texture};
        file.materials = {{"m", glm::vec4(1.0f, 1.0f, 1.0f, factor_alpha), 0, -1, 1.0f}};
        file.materials[0].alpha_mode = mode;
        file.materials[0].metallic = 0.0f;
        file.meshes = {{scene::test::unit_quad(0)}};
        gl::Renderer renderer(context());
        renderer.set_scene(scene_of(file, name));
        const Image image = render(renderer, {0, 0, 1}, gl::OutputMode::Diffuse);
        // Lit pixels in the middle of each half (away from where the texture's filtering blends
        // the halves, and from the repeat's seam): {right, left}.
        std::size_t lit_right = 0, lit_left = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                if (!(image.at(x, y, 0) > 0.0f)) continue;
                const int eighth = 8 * x / image.width;
                lit_left += eighth >= 1 && eighth <= 2;
                lit_right += eighth >= 5 && eighth <= 6;
            }
        return std::pair{lit_right, lit_left};
    };
    const auto [opaque_right, opaque_left] = covered("opaque", "", 1.0f);
    const auto [mask_right, mask_left] = covered("mask", "MASK", 1.0f);
    const auto [faint_right, faint_left] = covered("mask_faint", "MASK", 0.5f);
    ASSERT_GT(opaque_left, 200u);
    ASSERT_EQ(opaque_right, opaque_left);
    // MASK at 0.5: the left half (alpha 0.2) goes, the right (0.9) stays.
    EXPECT_EQ(mask_left, 0u);
    EXPECT_EQ(mask_right, opaque_right);
    // The factor's alpha multiplies: 0.9 x 0.5 < 0.5, nothing is left.
    EXPECT_EQ(faint_right, 0u);
    EXPECT_EQ(faint_left, 0u);
}

// alphaMode BLEND: drawn after the opaque objects whatever their order in the file, over them:
// with alpha a the pixel is a times the front's colour plus 1 - a times what is behind (straight
// alpha, linear radiance), here measured against the same scene with the front quad opaque and
// with it fully transparent.
TEST_F(GltfRender, AlphaBlendIsDrawnOverTheOpaqueObjectsBehind) {
    const auto render_scene = [&](const std::string& name, const std::string& mode, float alpha) {
        scene::test::GltfTestFile file;
        // The front quad first in the file: the renderer must still draw it last.
        file.materials = {{"front", glm::vec4(1.0f, 0.1f, 0.1f, alpha), -1, -1, 1.0f},
                          {"back", glm::vec4(0.1f, 0.1f, 1.0f, 1.0f), -1, -1, 1.0f}};
        file.materials[0].alpha_mode = mode;
        for (auto& material : file.materials) material.metallic = 0.0f;
        file.meshes = {{scene::test::unit_quad(0)}, {scene::test::unit_quad(1)}};
        file.nodes = {{0, {}, {}, {-0.25, -0.25, 0.5}, {}}, {1, {}, {}, {-0.5, -0.5, 0.0}, {}}};
        gl::Renderer renderer(context());
        renderer.set_scene(scene_of(file, name));
        return render(renderer, {0, 0, 1}, gl::OutputMode::Diffuse);
    };
    const Image half = render_scene("blend_half", "BLEND", 0.5f);
    const Image opaque = render_scene("blend_opaque", "", 1.0f);
    const Image clear = render_scene("blend_clear", "BLEND", 0.0f);
    ASSERT_EQ(half.width, opaque.width);
    double worst = 0.0;
    std::size_t front = 0;
    for (int y = 0; y < half.height; ++y)
        for (int x = 0; x < half.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const double expected = 0.5 * opaque.at(x, y, c) + 0.5 * clear.at(x, y, c);
                worst = std::max(worst, std::abs(double(half.at(x, y, c)) - expected));
            }
            // Where the front quad is: red in the opaque render, blue behind it.
            front += opaque.at(x, y, 0) > 2.0f * opaque.at(x, y, 2);
        }
    EXPECT_GT(front, 200u) << "the front quad covers part of the view";
    EXPECT_LT(worst, 2e-3) << "0.5 front + 0.5 behind, per pixel and channel";
    // Fully transparent: no trace of the front quad, and the back quad shows through it.
    std::size_t red = 0, blue_behind = 0;
    for (int y = 0; y < clear.height; ++y)
        for (int x = 0; x < clear.width; ++x) {
            red += clear.at(x, y, 0) > 2.0f * clear.at(x, y, 2);
            blue_behind += opaque.at(x, y, 0) > 2.0f * opaque.at(x, y, 2) &&
                           clear.at(x, y, 2) > 2.0f * clear.at(x, y, 0);
        }
    EXPECT_EQ(red, 0u);
    EXPECT_GT(blue_behind, 100u);
}

// doubleSided: a single-sided material's back faces are culled; a double-sided one's are drawn and
// shaded with the reversed frame: from behind, lit from behind, the quad looks as it does from the
// front lit from the front.
TEST_F(GltfRender, DoubleSidedShadesBackFacesAndSingleSidedCullsThem) {
    const auto render_quad = [&](const std::string& name, bool double_sided, float side) {
        scene::test::GltfTestFile file;
        file.materials = {{"m", glm::vec4(1.0f), -1, -1, 1.0f}};
        file.materials[0].double_sided = double_sided;
        file.materials[0].metallic = 0.0f;
        file.meshes = {{scene::test::unit_quad(0)}};
        gl::Renderer renderer(context());
        renderer.set_scene(scene_of(file, name));
        gl::RenderRequest r;
        r.technique = Technique::Lean;
        r.width = r.height = 64;
        r.view = gl::view_at_distance(2.5f, gl::kDefaultFovYDegrees, glm::vec3(0.2f, 0.1f, side));
        r.settings.light_direction = glm::vec3(0.3f, 0.2f, side);
        r.output = gl::OutputMode::Color;
        return channel_sums(renderer.render(r));
    };
    const glm::dvec3 front = render_quad("single_front", false, 1.0f);
    const glm::dvec3 back_culled = render_quad("single_back", false, -1.0f);
    const glm::dvec3 back_double = render_quad("double_back", true, -1.0f);
    const glm::dvec3 front_double = render_quad("double_front", true, 1.0f);
    EXPECT_GT(front.x, 100.0);
    EXPECT_EQ(back_culled.x, 0.0) << "culled: the background only";
    EXPECT_NEAR(front_double.x / front.x, 1.0, 1e-6);
    // The mirror view of a flat quad: the same picture mirrored, the same sums.
    EXPECT_NEAR(back_double.x / front.x, 1.0, 0.02);
    EXPECT_NEAR(back_double.z / front.z, 1.0, 0.02);
}

// KHR_texture_transform in leanfade's uv: the glTF matrix T R S conjugated by the v flip, checked
// on points against the extension's formula in glTF's uv.
TEST(GltfTextureTransform, ConjugatesTheExtensionsMatrixByTheVFlip) {
    scene::GltfTextureTransform t;
    t.offset = {0.25f, 0.5f};
    t.rotation = 0.7f;
    t.scale = {2.0f, 0.5f};
    const scene::UvTransform m = scene::leanfade_uv_transform(t);
    for (const glm::vec2 g : {glm::vec2(0.0f), glm::vec2(0.3f, 0.8f), glm::vec2(-1.0f, 2.0f)}) {
        // glTF: uv' = T R S uv, R = [cos sin; -sin cos].
        const glm::vec2 s = g * t.scale;
        const float c = std::cos(t.rotation), n = std::sin(t.rotation);
        const glm::vec2 expected_g = glm::vec2(c * s.x + n * s.y, -n * s.x + c * s.y) + t.offset;
        const glm::vec2 l(g.x, 1.0f - g.y);  // the same point in leanfade's uv
        const glm::vec2 got(glm::dot(glm::vec2(m.row0), l) + m.row0.z,
                            glm::dot(glm::vec2(m.row1), l) + m.row1.z);
        EXPECT_NEAR(got.x, expected_g.x, 1e-5f);
        EXPECT_NEAR(got.y, 1.0f - expected_g.y, 1e-5f);
    }
}

// A base colour texture's KHR_texture_transform moves what the quad shows: red on the left, blue
// on the right; offset by half a texture in u, the two swap.
TEST_F(GltfRender, TextureTransformMovesTheBaseColourTexture) {
    std::vector<float> rgb;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            rgb.insert(rgb.end(), {x < 4 ? 1.0f : 0.0f, 0.0f, x < 4 ? 0.0f : 1.0f});
    const std::vector<std::uint8_t> texture = scene::test::png_bytes(8, 8, 3, rgb);
    const auto red_on_the_left = [&](const std::string& name, const nlohmann::json& transform) -> int {
        scene::test::GltfTestFile file;
        file.images = {texture};
        file.materials = {{"m", glm::vec4(1.0f), 0, -1, 1.0f}};
        file.materials[0].base_color_transform = transform;
        file.materials[0].metallic = 0.0f;
        file.meshes = {{scene::test::unit_quad(0)}};
        gl::Renderer renderer(context());
        renderer.set_scene(scene_of(file, name));
        const Image image = render(renderer, {0, 0, 1}, gl::OutputMode::Diffuse);
        double left_red = 0, left_blue = 0, right_red = 0, right_blue = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const int eighth = 8 * x / image.width;
                if (eighth == 2) {
                    left_red += image.at(x, y, 0);
                    left_blue += image.at(x, y, 2);
                } else if (eighth == 5) {
                    right_red += image.at(x, y, 0);
                    right_blue += image.at(x, y, 2);
                }
            }
        // +1: red left and blue right; -1: swapped; 0: neither.
        if (left_red > 5.0 * left_blue && right_blue > 5.0 * right_red) return 1;
        if (left_blue > 5.0 * left_red && right_red > 5.0 * right_blue) return -1;
        return 0;
    };
    EXPECT_EQ(red_on_the_left("transform_none", nullptr), 1);
    EXPECT_EQ(red_on_the_left("transform_half", nlohmann::json{{"offset", {0.5, 0.0}}}), -1);
    EXPECT_EQ(red_on_the_left("transform_whole", nlohmann::json{{"offset", {1.0, 0.0}}}), 1);
    // A half turn about the origin with a whole offset maps u to 1 - u: swapped.
    EXPECT_EQ(red_on_the_left("transform_turn",
                              nlohmann::json{{"rotation", 3.14159265}, {"offset", {1.0, 1.0}}}),
              -1);
}

}  // namespace
