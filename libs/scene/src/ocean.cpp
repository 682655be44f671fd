#include "leanfade/scene/detail/ocean.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/flow_map.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "leanfade/version.hpp"

namespace leanfade::scene {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kGravity = 9.81f;  // m/s^2

// The four wave systems: whole cycles per tile along u and v (the wave vector; the waves travel
// along it). Different directions and wavelengths (2.0, 1.7, 1.6 and 1.7 tiles / 10).
constexpr std::array<std::array<int, 2>, 4> kWaveCycles = {{{8, 2}, {-3, 9}, {-9, -4}, {5, -8}}};
// Each layer's tile length in units of OceanSettings::tile_length: incommensurate, so the tiles'
// repeats do not line up and the repetition is harder to see from afar.
constexpr std::array<float, 4> kTileScales = {1.0f, 1.37f, 0.83f, 1.19f};

// Vertical field of view of the ocean's cameras, degrees.
constexpr float kCameraFov = 40.0f;
// The sun: its elevation above the horizon and how far beyond the right edge of the image it
// stands, degrees.
constexpr float kSunElevation = 15.0f;
constexpr float kSunBeyondEdge = 3.0f;

}  // namespace

void validate(const OceanSettings& s) {
    if (!(s.tile_length > 0.0f) || !std::isfinite(s.tile_length))
        throw Error::setting("ocean-tile", "the wave tile's length must be finite and > 0 metres");
    if (!(s.extent >= 1000.0f) || !std::isfinite(s.extent) || s.extent > 1e6f)
        throw Error::setting("ocean-extent", "must be in [1000, 1e6] metres");
    if (s.extent / s.tile_length > 8000.0f)
        throw Error::setting("ocean-extent",
                             "more than 8000 wave tiles across the ocean (texture "
                             "coordinates would lose precision)");
    if (s.texture_size < 16 || s.texture_size > 4096)
        throw Error::setting("texture_size", "the ocean's wave tiles are 16..4096 texels, got " +
                                                 std::to_string(s.texture_size));
    if (s.layers < 2 || s.layers > kMaxLayers)
        throw Error::setting("ocean_layers", "2.." + std::to_string(kMaxLayers) +
                                                 " wave layers, got " + std::to_string(s.layers));
    if (!(s.loop_seconds > 0.0f) || !std::isfinite(s.loop_seconds) || s.loop_seconds > 1e6f)
        throw Error::setting("ocean-loop", "must be in (0, 1e6] seconds");
    if (s.flow == OceanFlow::Image) {
        if (s.flow_field.channels != 2 || s.flow_field.empty())
            throw Error::setting("flow", "the flow field needs 2 channels and at least one texel");
        if (s.flow_field.width > kDefaultMaxImageDimension ||
            s.flow_field.height > kDefaultMaxImageDimension)
            throw Error::setting(
                "flow",
                "larger than " + std::to_string(kDefaultMaxImageDimension) + " texels on a side");
    }
    if (s.flow == OceanFlow::Gyre && (s.flow_size < 4 || s.flow_size > 4096))
        throw Error::setting("flow-size",
                             "must be in [4, 4096] texels, got " + std::to_string(s.flow_size));
    if (!(s.wave_strength > 0.0f) || !std::isfinite(s.wave_strength) || s.wave_strength > 100.0f)
        throw Error::setting("ocean-strength", "must be in (0, 100]");
}

std::vector<OceanLayer> ocean_layers(const OceanSettings& s) {
    validate(s);
    std::vector<OceanLayer> layers;
    for (int i = 0; i < s.layers; ++i) {
        OceanLayer layer;
        GaborNoiseSettings& w = layer.waves;
        w.size = s.texture_size;
        // Fewer cycles on small tiles: at least 8 texels per wavelength (the longest wave vector
        // of kWaveCycles is 9.85 cycles).
        const float shrink = std::min(1.0f, float(s.texture_size) / 8.0f / 9.85f);
        w.cycles_u = int(std::lround(float(kWaveCycles[std::size_t(i)][0]) * shrink));
        w.cycles_v = int(std::lround(float(kWaveCycles[std::size_t(i)][1]) * shrink));
        if (w.cycles_u == 0 && w.cycles_v == 0) w.cycles_u = 1;
        w.orientation_spread = 0.6f;
        w.kernel_wavelengths = 2.0f;
        w.impulses_per_kernel = 24.0f;
        w.slope_rms = 0.12f;
        w.seed = s.seed * 4u + std::uint32_t(i);
        // Deep-water waves travel at c = sqrt(g lambda / (2 pi)); each layer moves a whole number
        // of tiles per loop along its wave vector, so the motion repeats after loop_seconds.
        layer.tile_length = s.tile_length * kTileScales[std::size_t(i)];
        const glm::vec2 cycles(float(w.cycles_u), float(w.cycles_v));
        const float wavelength = layer.tile_length / glm::length(cycles);     // metres
        const float speed = std::sqrt(kGravity * wavelength / (2.0f * kPi));  // metres / second
        const glm::vec2 tiles =
            glm::round(glm::normalize(cycles) * speed * s.loop_seconds / layer.tile_length);
        layer.velocity = (tiles == glm::vec2(0.0f) ? glm::sign(cycles) : tiles) / s.loop_seconds;
        layers.push_back(layer);
    }
    return layers;
}

Scene make_ocean_scene(const OceanSettings& s, int threads) {
    const std::vector<OceanLayer> layers = ocean_layers(s);
    Scene scene;
    Object water;
    water.mesh = make_plane(s.extent, 32);
    water.mesh.name = "ocean";
    // make_plane repeats a tile every kTileLength; the ocean's uv spans [0, 1] once instead.
    for (Vertex& v : water.mesh.vertices) {
        v.uv *= kTileLength / s.extent;
        v.uv1 = v.uv;
    }
    water.material = 0;
    scene.objects.push_back(std::move(water));

    Material material;
    material.name = "water";
    material.layered.mixing = LayerMixing::Approx;
    BakeOptions bake;
    bake.strength = 1.0f;
    bake.threads = threads;
    const std::string generator = std::string(LEANFADE_GENERATOR " ocean");
    std::vector<glm::vec2> velocities;
    for (const OceanLayer& layer : layers) {
        const Image heights = make_gabor_noise(layer.waves, threads);
        scene.lean_maps.push_back(
            leanfade::bake(BakeInput(heights, BakeSource::Height, "gabor"),
                           BakeSettings{.options = bake,
                                        .storage = StoragePolicy::fixed(Storage::Unorm16),
                                        .generator = generator,
                                        .keep_empty_plateau = true})
                .packed);
        MaterialLayer m;
        m.lean_map = int(scene.lean_maps.size()) - 1;
        m.strength = s.wave_strength;
        m.tiling = s.extent / layer.tile_length;
        m.velocity = layer.velocity;
        material.layered.layers.push_back(m);
        material.layered.weights.push_back(1.0f / float(layers.size()));
        velocities.push_back(layer.velocity);
    }
    if (s.flow != OceanFlow::None) {
        const Image flow =
            s.flow == OceanFlow::Gyre ? make_gyre_flow(s.flow_size, 0.1f) : s.flow_field;
        scene.weight_maps.push_back(flow_weights(flow, velocities));
        material.layered.weight_map = 0;
    }
    scene.materials.push_back(std::move(material));
    validate(scene);
    return scene;
}

float ocean_metres_per_world_unit(const OceanSettings& s) {
    // make_plane's box is flat: its bounding radius is half its diagonal.
    return 0.5f * std::sqrt(2.0f) * s.extent;
}

glm::vec3 ocean_sky_colour() {
    return {0.50f, 0.62f, 0.78f};
}

ShadingSettings ocean_shading(const OceanSettings& s, float aspect) {
    validate(s);
    if (!(aspect > 0.0f) || !std::isfinite(aspect))
        throw Error::setting("size", "aspect must be > 0");
    const float metres = ocean_metres_per_world_unit(s);
    ShadingSettings shading;
    // LEAN Fig. 1: "artist-selected shininess equivalent to a Blinn-Phong specular exponent of
    // 13,777", added to the covariance at run time.
    shading.shininess = 13777.0f;
    shading.kd = {0.006f, 0.030f, 0.045f};
    shading.ambient = {0.010f, 0.028f, 0.040f};
    shading.ks = glm::vec3(1.0f);
    shading.light_color = {1.00f, 0.93f, 0.82f};
    // Water: F0 = ((1 - 1.33) / (1 + 1.33))^2 = 0.02, Schlick's (1 - n.v)^5 for the rest.
    shading.fresnel_bias = 0.02f;
    shading.fresnel_scale = 0.98f;
    // The sun kSunBeyondEdge degrees right of the image's right edge (the cameras look along -z),
    // kSunElevation degrees up: its mirror reflection lies off-screen, its glints on the water.
    const float half_width = std::atan(std::tan(0.5f * kCameraFov * kPi / 180.0f) * aspect);
    const float azimuth = half_width + kSunBeyondEdge * kPi / 180.0f;
    const float elevation = kSunElevation * kPi / 180.0f;
    shading.light_direction = {std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                               -std::cos(azimuth) * std::cos(elevation)};
    // Haze toward the horizon in the sky's colour: squared-exponential fog, 1/e at 3 km, so the
    // water is clear nearby and the plane's edge (10 km or more away) is lost in the haze.
    shading.fog = FogMode::Exp2;
    shading.fog_color = ocean_sky_colour();
    shading.fog_density = metres / 3000.0f;
    // Specular fading (fading paper eq. 6-7, d = the eye's height above the water): sf = 2 at
    // 300 m (the far camera), up to Pmax = 16.
    shading.fade = metres / 300.0f;
    shading.pmax = 16.0f;
    shading.tiling = 1.0f;
    return shading;
}

const std::vector<std::string>& ocean_camera_names() {
    static const std::vector<std::string> names = {"near", "mid", "far"};
    return names;
}

OceanCamera ocean_camera(const std::string& name, const OceanSettings& s) {
    validate(s);
    // Heights (metres) and downward pitches (degrees) of LEAN Fig. 1 (a, b, c); every camera
    // stands at the centre, half the extent of water ahead of it.
    float height = 0.0f, pitch = 0.0f;
    if (name == "near") {
        height = 4.0f;
        pitch = 6.0f;
    } else if (name == "mid") {
        height = 40.0f;
        pitch = 12.0f;
    } else if (name == "far") {
        height = 300.0f;
        pitch = 18.0f;
    } else {
        throw Error::setting("views",
                             "unknown ocean view '" + name + "' (valid: near, mid or far)");
    }
    OceanCamera camera;
    camera.name = name;
    camera.eye = {0.0f, height, 0.0f};
    const float p = pitch * kPi / 180.0f;
    camera.target = camera.eye + glm::vec3(0.0f, -std::sin(p), -std::cos(p));
    camera.fov_y_degrees = kCameraFov;
    camera.near_plane = 0.25f;
    camera.far_plane = s.extent;
    return camera;
}

}  // namespace leanfade::scene
