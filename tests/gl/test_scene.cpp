// Scenes of several objects and materials (Renderer::set_scene, leanfade/scene/material.hpp):
// each object is shaded with its own material's LEAN map and parameters, a one-object scene is
// the single-mesh renderer bit for bit, and bad scenes are refused before anything changes.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"

namespace leanfade::test {
namespace {

class SceneRendering : public GlTest {};

gl::RenderRequest diffuse_request() {
    gl::RenderRequest request;
    request.technique = gl::Technique::Lean;
    request.width = 96;
    request.height = 48;
    request.view = gl::view_at_distance(2.0f, 30.0f, {0.0f, 0.0f, 1.0f});
    request.settings.light_direction = {1.0f, 0.0f, 0.6f};
    request.output = gl::OutputMode::Diffuse;
    return request;
}

// Mean of channel c over the pixels of columns [x0, x1).
double column_mean(const Image& image, int x0, int x1, int c) {
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = x0; x < x1; ++x, ++n) sum += image.at(x, y, c);
    return sum / n;
}

// Two quads side by side: the left one's map tilts its normals toward +x (toward the light), the
// right one's is flat; the right one's material also overrides Kd to pure green.
scene::Scene two_quads(int left_map, int right_map) {
    scene::Scene s;
    s.lean_maps.push_back(
        make_constant_lean_map({0.6f, 0.0f}, {0.001f, 0.001f, 0.0f}, 1.0f, Storage::Float32));
    s.lean_maps.push_back(
        make_constant_lean_map({0.0f, 0.0f}, {0.001f, 0.001f, 0.0f}, 1.0f, Storage::Float32));
    scene::Material tilted;
    tilted.name = "tilted";
    tilted.lean_map = left_map;
    scene::Material green;
    green.name = "flat green";
    green.lean_map = right_map;
    green.diffuse = glm::vec3(0.0f, 0.6f, 0.0f);
    s.materials = {tilted, green};
    for (int i = 0; i < 2; ++i) {
        scene::Object o;
        o.mesh = make_test_quad();
        o.material = i;
        o.transform = glm::translate(glm::mat4(1.0f), glm::vec3(i == 0 ? -1.05f : 1.05f, 0, 0));
        s.objects.push_back(std::move(o));
    }
    return s;
}

TEST_F(SceneRendering, EachObjectUsesItsMaterial) {
    gl::Renderer renderer(context());
    renderer.set_scene(two_quads(0, 1));
    const Image image = renderer.render(diffuse_request());
    // Left: default Kd (terracotta, red > green); right: the override (green only).
    const double left_red = column_mean(image, 8, 40, 0), left_green = column_mean(image, 8, 40, 1);
    const double right_red = column_mean(image, 56, 88, 0),
                 right_green = column_mean(image, 56, 88, 1);
    EXPECT_GT(left_red, 2.0 * left_green);
    EXPECT_GT(right_green, 5.0 * right_red);
    // The left normals lean toward the light: NdotL larger than the flat one's. Compare the
    // green channel's share of Kd: left Kd.g = 0.22, right 0.6.
    const ShadingSettings defaults;
    const double left_ndotl = left_green / defaults.kd.g;
    const double right_ndotl = right_green / 0.6;
    EXPECT_GT(left_ndotl, 1.1 * right_ndotl) << left_ndotl << " " << right_ndotl;

    // The same objects with the maps swapped: the flat map now on the left.
    renderer.set_scene(two_quads(1, 0));
    const Image swapped = renderer.render(diffuse_request());
    EXPECT_LT(column_mean(swapped, 8, 40, 1) / defaults.kd.g, 0.95 * left_ndotl);
    EXPECT_GT(column_mean(swapped, 56, 88, 1) / 0.6, 1.05 * right_ndotl);
}

TEST_F(SceneRendering, OneObjectSceneIsTheSingleMeshRenderer) {
    const PackedLeanMap map = make_bumps_map(32);
    gl::Renderer single(context());
    single.set_mesh(make_test_quad(2.0f));
    single.set_lean_map(map);
    scene::Scene s;
    s.lean_maps = {map};
    s.materials.resize(1);
    s.materials[0].name = "bumps";
    s.objects.push_back({make_test_quad(2.0f), 0, glm::mat4(1.0f)});
    gl::Renderer from_scene(context());
    from_scene.set_scene(s);
    for (gl::Technique t : gl::all_techniques()) {
        gl::RenderRequest request = diffuse_request();
        request.technique = t;
        request.output = gl::OutputMode::Color;
        request.reference_samples = 2;
        const Image a = single.render(request), b = from_scene.render(request);
        EXPECT_EQ(a.pixels, b.pixels) << gl::to_string(t);
    }
}

TEST_F(SceneRendering, BadScenesAreRefusedAndKeepThePreviousOne) {
    gl::Renderer renderer(context());
    renderer.set_scene(two_quads(0, 1));
    const Image before = renderer.render(diffuse_request());
    scene::Scene bad = two_quads(0, 1);
    bad.materials[1].lean_map = 5;
    EXPECT_THROW(renderer.set_scene(bad), Error);
    bad = two_quads(0, 1);
    bad.objects[0].material = 2;
    EXPECT_THROW(renderer.set_scene(bad), Error);
    bad = two_quads(0, 1);
    bad.objects[1].transform = glm::mat4(0.0f);
    EXPECT_THROW(renderer.set_scene(bad), Error);
    bad = two_quads(0, 1);
    bad.materials[0].shininess = -1.0f;
    EXPECT_THROW(renderer.set_scene(bad), Error);
    // The glTF material factors outside their ranges (glTF 2.0 §3.9, KHR_materials_anisotropy).
    const auto refused = [&](void (*spoil)(scene::Material&), const char* named) {
        scene::Scene spoiled = two_quads(0, 1);
        spoil(spoiled.materials[1]);
        try {
            renderer.set_scene(spoiled);
            ADD_FAILURE() << named << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), "scene");
            EXPECT_NE(e.cause().find(named), std::string::npos) << e.what();
        }
    };
    refused([](scene::Material& m) { m.metallic = 1.5f; }, "metallic");
    refused([](scene::Material& m) { m.occlusion_strength = -0.1f; }, "occlusion strength");
    refused([](scene::Material& m) { m.emissive.y = std::nanf(""); }, "emissive");
    refused([](scene::Material& m) { m.emissive.x = -1.0f; }, "emissive");
    refused([](scene::Material& m) { m.anisotropy_strength = 2.0f; }, "anisotropy strength");
    refused([](scene::Material& m) { m.anisotropy_rotation = INFINITY; }, "anisotropy rotation");
    EXPECT_THROW(renderer.set_scene(scene::Scene{}), Error);
    EXPECT_EQ(renderer.render(diffuse_request()).pixels, before.pixels);
}

}  // namespace
}  // namespace leanfade::test
