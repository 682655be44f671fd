// The built-in ocean (leanfade/scene/detail/ocean.hpp): a layered water plane reaching the horizon, its
// moving Gabor wave layers, flow weights, cameras and shading. Rendering: test_ocean_render.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/glm.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/flow_map.hpp"
#include "leanfade/scene/detail/ocean.hpp"

using namespace leanfade;
using namespace leanfade::scene;

namespace {

OceanSettings small_ocean() {
    OceanSettings s;
    s.texture_size = 64;  // quick to bake
    return s;
}

float degrees_between(glm::vec2 a, glm::vec2 b) {
    return glm::degrees(
        std::acos(glm::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0f, 1.0f)));
}

}  // namespace

TEST(Ocean, IsAWaterPlaneWithTwoMovingLayers) {
    const OceanSettings settings = small_ocean();
    const Scene scene = make_ocean_scene(settings, 1);
    ASSERT_EQ(scene.objects.size(), 1u);
    ASSERT_EQ(scene.materials.size(), 1u);
    const Mesh& plane = scene.objects[0].mesh;
    // Flat at y = 0, facing up, extent x extent metres, uv over [0, 1] once.
    EXPECT_FLOAT_EQ(plane.bounds.max.x - plane.bounds.min.x, settings.extent);
    EXPECT_FLOAT_EQ(plane.bounds.max.z - plane.bounds.min.z, settings.extent);
    glm::vec2 uv_min(1e9f), uv_max(-1e9f);
    for (const Vertex& v : plane.vertices) {
        EXPECT_EQ(v.position.y, 0.0f);
        EXPECT_NEAR(v.normal.y, 1.0f, 1e-6f);
        uv_min = glm::min(uv_min, v.uv);
        uv_max = glm::max(uv_max, v.uv);
    }
    EXPECT_NEAR(uv_min.x, 0.0f, 1e-5f);
    EXPECT_NEAR(uv_max.x, 1.0f, 1e-5f);
    EXPECT_NEAR(uv_max.y - uv_min.y, 1.0f, 1e-5f);

    const MaterialLayers& layered = scene.materials[0].layered;
    ASSERT_EQ(layered.layers.size(), 2u);
    EXPECT_EQ(layered.mixing, LayerMixing::Approx);
    EXPECT_EQ(layered.weight_map, -1);
    EXPECT_EQ(scene.lean_maps.size(), 2u);
    const std::vector<OceanLayer> ocean = ocean_layers(settings);
    for (std::size_t i = 0; i < 2; ++i) {
        const MaterialLayer& layer = layered.layers[i];
        EXPECT_FLOAT_EQ(layer.tiling, settings.extent / ocean[i].tile_length);
        EXPECT_GT(ocean[i].tile_length, 0.5f * settings.tile_length);
        EXPECT_GT(glm::length(layer.velocity), 0.0f);
        // A whole number of tiles per loop: the motion repeats after loop_seconds.
        const glm::vec2 tiles = layer.velocity * settings.loop_seconds;
        EXPECT_NEAR(tiles.x, std::round(tiles.x), 1e-4f);
        EXPECT_NEAR(tiles.y, std::round(tiles.y), 1e-4f);
    }
    EXPECT_GT(degrees_between(layered.layers[0].velocity, layered.layers[1].velocity), 45.0f);
    EXPECT_FLOAT_EQ(layered.weights[0] + layered.weights[1], 1.0f);
}

TEST(Ocean, LayersTravelAlongTheirWavesAtAboutDeepWaterSpeed) {
    OceanSettings settings = small_ocean();
    settings.texture_size = 256;
    settings.layers = 4;
    const std::vector<OceanLayer> layers = ocean_layers(settings);
    ASSERT_EQ(layers.size(), 4u);
    for (const OceanLayer& layer : layers) {
        const glm::vec2 wave(float(layer.waves.cycles_u), float(layer.waves.cycles_v));
        EXPECT_LT(degrees_between(layer.velocity, wave), 20.0f);
        // c = sqrt(g lambda / 2 pi) within the rounding to whole tiles per loop.
        const float wavelength = layer.tile_length / glm::length(wave);
        const float speed = std::sqrt(9.81f * wavelength / (2.0f * 3.14159265f));
        const float tiles_per_loop = speed * settings.loop_seconds / layer.tile_length;
        EXPECT_NEAR(glm::length(layer.velocity) * settings.loop_seconds, tiles_per_loop, 0.75f);
    }
    // Four directions: every pair at least 45 degrees apart.
    for (std::size_t i = 0; i < layers.size(); ++i)
        for (std::size_t j = i + 1; j < layers.size(); ++j)
            EXPECT_GT(degrees_between(layers[i].velocity, layers[j].velocity), 45.0f) << i << j;
    // Deterministic from the seed, and the seed changes the waves.
    EXPECT_EQ(ocean_layers(settings)[2].waves.seed, layers[2].waves.seed);
    settings.seed = 9;
    EXPECT_NE(ocean_layers(settings)[0].waves.seed, layers[0].waves.seed);
}

TEST(Ocean, AGyreWeightsFourLayersByTheirAgreementWithTheFlow) {
    OceanSettings settings = small_ocean();
    settings.layers = 4;
    settings.flow = OceanFlow::Gyre;
    settings.flow_size = 32;
    const Scene scene = make_ocean_scene(settings, 1);
    const MaterialLayers& layered = scene.materials[0].layered;
    ASSERT_EQ(layered.weight_map, 0);
    const Image& weights = scene.weight_maps[0];
    ASSERT_EQ(weights.channels, 4);
    // At the top of the gyre (north) the current runs east (+u): the layer moving most nearly
    // east has the largest weight; at the bottom it runs west.
    int east = 0, west = 0;
    for (int i = 1; i < 4; ++i) {
        if (layered.layers[std::size_t(i)].velocity.x >
            layered.layers[std::size_t(east)].velocity.x)
            east = i;
        if (layered.layers[std::size_t(i)].velocity.x <
            layered.layers[std::size_t(west)].velocity.x)
            west = i;
    }
    for (int c = 0; c < 4; ++c) {
        if (c != east) {
            EXPECT_GT(weights.at(16, 1, east), weights.at(16, 1, c));
        }
        if (c != west) {
            EXPECT_GT(weights.at(16, 30, west), weights.at(16, 30, c));
        }
    }
    for (std::size_t i = 0; i < weights.texel_count(); ++i) {
        const float* t = &weights.pixels[4 * i];
        EXPECT_NEAR(t[0] + t[1] + t[2] + t[3], 1.0f, 1e-5f);
    }
}

TEST(Ocean, AFlowImageGivesTheWeightMap) {
    OceanSettings settings = small_ocean();
    settings.flow = OceanFlow::Image;
    Image rg(8, 8, 3, 0.5f);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) rg.at(x, y, 0) = 1.0f;  // the whole ocean flows east
    settings.flow_field = flow_from_rg(rg, "east.png");
    const Scene scene = make_ocean_scene(settings, 1);
    const MaterialLayers& layered = scene.materials[0].layered;
    const int east = layered.layers[0].velocity.x > layered.layers[1].velocity.x ? 0 : 1;
    EXPECT_GT(scene.weight_maps[0].at(3, 3, east), 0.6f);
    settings.flow_field = Image(8, 8, 3);
    EXPECT_THROW(make_ocean_scene(settings, 1), Error);
}

TEST(Ocean, CamerasRiseAndLookDownMoreSteeply) {
    const OceanSettings settings;
    float previous_height = 0.0f, previous_pitch = 0.0f;
    for (const std::string& name : ocean_camera_names()) {
        const OceanCamera camera = ocean_camera(name, settings);
        const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
        const float pitch = -std::asin(forward.y);
        EXPECT_GT(camera.eye.y, previous_height) << name;
        EXPECT_GT(pitch, previous_pitch) << name;
        EXPECT_NEAR(forward.x, 0.0f, 1e-6f);
        EXPECT_LT(forward.z, 0.0f);
        // Above the water, and the image's top edge is above the horizon: the water reaches it.
        EXPECT_LT(std::abs(camera.eye.x), 0.5f * settings.extent);
        EXPECT_LT(std::abs(camera.eye.z), 0.5f * settings.extent);
        EXPECT_LT(pitch, glm::radians(0.5f * camera.fov_y_degrees)) << name;
        // The far edge of the plane is within half a degree of the true horizon.
        const float ahead = camera.eye.z + 0.5f * settings.extent;
        EXPECT_LT(glm::degrees(std::atan(camera.eye.y / ahead)), 5.0f) << name;
        previous_height = camera.eye.y;
        previous_pitch = pitch;
    }
    EXPECT_THROW(ocean_camera("space", settings), Error);
}

TEST(Ocean, ShadingHasTheSunJustOffScreenAndExponent13777) {
    const OceanSettings settings;
    const float aspect = 16.0f / 9.0f;
    const ShadingSettings shading = ocean_shading(settings, aspect);
    EXPECT_EQ(shading.shininess, 13777.0f);
    EXPECT_NO_THROW(validate(shading));
    const glm::vec3 sun = glm::normalize(shading.light_direction);
    EXPECT_GT(sun.y, 0.0f);  // above the horizon
    const float elevation = glm::degrees(std::asin(sun.y));
    EXPECT_LT(elevation, 20.0f);  // low: glints on the water ahead
    // Horizontally, just beyond the right edge of every camera's image (all look along -z).
    const float azimuth = glm::degrees(std::atan2(sun.x, -sun.z));
    for (const std::string& name : ocean_camera_names()) {
        const OceanCamera camera = ocean_camera(name, settings);
        const float half_width =
            glm::degrees(std::atan(std::tan(glm::radians(0.5f * camera.fov_y_degrees)) * aspect));
        EXPECT_GT(azimuth, half_width) << name;
        EXPECT_LT(azimuth, half_width + 15.0f) << name;
    }
    EXPECT_GT(shading.fade, 0.0f);
}

TEST(Ocean, RefusesBadSettings) {
    auto refused = [](OceanSettings s, const std::string& setting) {
        try {
            validate(s);
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), setting);
            return;
        }
        ADD_FAILURE() << "accepted, expected an error on " << setting;
    };
    OceanSettings s;
    s.layers = 1;
    refused(s, "ocean_layers");
    s.layers = 5;
    refused(s, "ocean_layers");
    s = OceanSettings{};
    s.extent = std::nanf("");
    refused(s, "ocean-extent");
    s = OceanSettings{};
    s.loop_seconds = 0.0f;
    refused(s, "ocean-loop");
    s = OceanSettings{};
    s.texture_size = 8;
    refused(s, "texture_size");
    s = OceanSettings{};
    s.flow = OceanFlow::Image;  // without a field
    refused(s, "flow");
}
