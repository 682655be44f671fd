#pragma once
// The built-in `ocean` scene (LEAN Fig. 1 and 11): a flat water plane reaching the horizon whose
// material mixes 2 to 4 layers of periodic Gabor waves (leanfade/core/detail/gabor_noise.hpp), each
// moving along its own wave direction, weighted equally or by a flow map (a built-in gyre or an
// image; leanfade/core/detail/flow_map.hpp). Also the near / mid / far cameras of LEAN Fig. 1 (a, b, c)
// and the sun just off-screen to their right. GL-free.
//
// Units and spaces: scene space in metres, y up, the water at y = 0, centred on the origin, the
// cameras looking along -z. The plane's uv runs over [0, 1] across the whole ocean (u along +x, v
// along -z): a flow or weight map covers the ocean once, and each layer repeats its wave tile
// `extent / tile_length` times across it.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "leanfade/core/detail/gabor_noise.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/scene/material.hpp"

namespace leanfade::scene {

enum class OceanFlow {
    None,   // fixed, equal weights
    Gyre,   // make_gyre_flow over the whole ocean (a clockwise current)
    Image,  // OceanSettings::flow_field (a flow-map image, flow_from_rg)
};

struct OceanSettings {
    // Metres, side of the square water plane, [1000, 1e6] and at most 8000 tiles: the default
    // reaches 20 km ahead of the cameras, beyond the haze, so the water meets the horizon.
    float extent = 40000.0f;
    float tile_length = 16.0f;  // metres of one wave tile (> 0)
    int texture_size = 256;     // texels per side of each layer's wave tile (16 to 4096)
    int layers = 2;             // wave layers, 2..kMaxLayers
    // The layers' motion repeats after this many seconds (> 0): every layer moves a whole number of
    // tiles in that time, at about the phase speed of deep-water waves of its wavelength.
    float loop_seconds = 32.0f;
    OceanFlow flow = OceanFlow::None;
    Image flow_field;            // OceanFlow::Image: 2 channels over the ocean (flow_from_rg)
    int flow_size = 64;          // OceanFlow::Gyre: texels per side of the gyre and weight maps
    float wave_strength = 2.0f;  // each layer's strength k (slopes times k), finite, > 0
    std::uint32_t seed = 1;
};

// Throws leanfade::Error(setting, cause) for settings outside the ranges above (settings named
// "ocean-extent", "ocean-tile", "texture_size", "ocean_layers", "ocean-loop", "flow",
// "flow-size", "ocean-strength").
void validate(const OceanSettings& settings);

// One wave layer of the ocean: its Gabor noise (one tile), the tile's length and its velocity in
// the layer's own uv (tiles per second).
struct OceanLayer {
    GaborNoiseSettings waves;
    float tile_length = 16.0f;  // metres: tile_length times 1, 1.37, 0.83 or 1.19 by layer
    glm::vec2 velocity{0.0f};
};

// The layers of `settings` (the first settings.layers of four wave systems travelling roughly
// east, north-west, south-west and south-east, seeds derived from settings.seed).
std::vector<OceanLayer> ocean_layers(const OceanSettings& settings);

// The water plane (one object, one layered material: Gabor LEAN maps baked at strength 1 at
// 16-bit without roughness, tiling extent / tile_length, the layers' velocities, equal weights or
// a weight map from the flow). The layers move relative to each other, so their second moments
// mix by the "mixing approximation" (docs/math.md §6): mixing textures baked once would be wrong,
// and the layers are independent noise, whose cross terms the approximation gets right on
// average. threads <= 0: all hardware threads. Throws as validate().
Scene make_ocean_scene(const OceanSettings& settings, int threads = 0);

// The shading of the ocean (LEAN Fig. 1): Blinn-Phong exponent 13,777 added at shading time,
// water colours, water's Fresnel (F0 about 0.02), a low sun just off-screen to the right of the
// cameras below in an image of width / height `aspect`, a sky-coloured haze toward the horizon,
// and specular fading scaled to the ocean's size. Fog and fade distances are in the renderer's
// world units (bounding radii of the scene, settings.hpp), converted from metres.
ShadingSettings ocean_shading(const OceanSettings& settings, float aspect = 16.0f / 9.0f);

// Metres per world unit of the renderer: the bounding radius of the ocean's plane.
float ocean_metres_per_world_unit(const OceanSettings& settings);

// Linear RGB of the sky behind the horizon (the haze's colour).
glm::vec3 ocean_sky_colour();

// A camera in scene space (metres): where it is, what it looks at, its vertical field of view.
struct OceanCamera {
    std::string name;
    glm::vec3 eye{0.0f};
    glm::vec3 target{0.0f, 0.0f, -1.0f};
    float fov_y_degrees = 40.0f;
    float near_plane = 0.25f;    // metres from the eye
    float far_plane = 10000.0f;  // metres from the eye: beyond the plane's far edge
};

// "near", "mid", "far": LEAN Fig. 1 (a, b, c), the camera rising (4, 40, 300 m) and looking down
// more steeply (6, 12, 18 degrees), the horizon always in view, all looking along -z with the
// sun's glints at the right edge.
const std::vector<std::string>& ocean_camera_names();
// Throws leanfade::Error("views", cause) for another name.
OceanCamera ocean_camera(const std::string& name, const OceanSettings& settings);

}  // namespace leanfade::scene
