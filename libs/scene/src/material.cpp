// Scenes of objects and materials (leanfade/scene/material.hpp).
#include "leanfade/scene/material.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>

#include "leanfade/core/error.hpp"

namespace leanfade::scene {
namespace {

bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The layers of material `m` (validate(Scene)); the weights and strengths by LayerBlend's rules.
void validate_layers(const Scene& scene, const Material& m) {
    const MaterialLayers& l = m.layered;
    const std::string where = "material '" + m.name + "'";
    const int n = int(l.layers.size());
    if (n < 2 || n > kMaxLayers)
        throw Error("scene", where + " has " + std::to_string(n) + " bump layers; a layered " +
                                 "material has 2.." + std::to_string(kMaxLayers));
    LayerBlend blend;
    blend.weights = l.weights;
    for (const MaterialLayer& layer : l.layers) {
        blend.strengths.push_back(layer.strength);
        if (layer.lean_map < 0 || layer.lean_map >= int(scene.lean_maps.size()))
            throw Error("scene", where + " has a layer with LEAN map " +
                                     std::to_string(layer.lean_map) + " of " +
                                     std::to_string(scene.lean_maps.size()));
        if (!(layer.tiling > 0.0f) || !std::isfinite(layer.tiling))
            throw Error::setting("layer-tiling", "each layer's tiling must be finite and > 0");
        if (!std::isfinite(layer.velocity.x) || !std::isfinite(layer.velocity.y))
            throw Error::setting("layer-velocity", "each layer's velocity must be finite");
    }
    validate(blend);
    if (int(l.weights.size()) != n)
        throw Error::setting("layer-weights", std::to_string(l.weights.size()) + " weights for " +
                                                  std::to_string(n) + " layers");
    if (l.weight_map >= int(scene.weight_maps.size()) || l.weight_map < -1)
        throw Error("scene", where + " uses weight map " + std::to_string(l.weight_map) + " of " +
                                 std::to_string(scene.weight_maps.size()));
    if (l.weight_map >= 0) {
        const Image& w = scene.weight_maps[std::size_t(l.weight_map)];
        if (w.channels != 4 || w.width < 1 || w.height < 1)
            throw Error::setting(
                "layer-weight-map",
                "a weight map has 4 channels (t_0..t_3), got " + std::to_string(w.channels));
    }
    // Mixed into one generated map (docs/math.md §6): whole tilings, a bounded size.
    if (l.mixing == LayerMixing::Height) mixed_map_size(scene, m);
    if (l.mixing == LayerMixing::Textures) {
        const int pairs = n * (n - 1) / 2;
        if (int(l.cross_terms.size()) != pairs)
            throw Error("scene", where + " mixes by textures and needs " + std::to_string(pairs) +
                                     " cross-term textures, has " +
                                     std::to_string(l.cross_terms.size()));
        for (int index : l.cross_terms) {
            if (index < 0 || index >= int(scene.cross_terms.size()))
                throw Error("scene", where + " uses cross-term texture " + std::to_string(index) +
                                         " of " + std::to_string(scene.cross_terms.size()));
            const std::vector<Image>& chain = scene.cross_terms[std::size_t(index)];
            if (chain.empty() || chain.front().channels != 4)
                throw Error("scene", where + ": a cross-term texture has no 4-channel levels");
        }
    }
}

// A surface map of `kind`: its levels have the kind's channels and halve in size (the full chain
// down to 1x1 for a kind whose MIPs are Given, level 0 alone for one the GPU generates), its
// values are finite, and a roughness map's alpha0^2 is >= 0.
void validate_surface_map(const MapKindInfo& kind, const std::vector<Image>& chain) {
    // A map a setting gives is that setting's error; any other is the scene's.
    const auto fail = [&kind](const std::string& cause) {
        return kind.setting.empty() ? Error("scene", cause)
                                    : Error::setting(std::string(kind.setting), cause);
    };
    const std::string what = "a " + std::string(kind.name);
    if (chain.empty() || chain.front().empty()) throw fail(what + " has no levels");
    int w = chain.front().width, h = chain.front().height;
    const std::size_t levels = kind.mips == MapMips::Given ? std::size_t(mip_level_count(w, h)) : 1;
    if (chain.size() != levels)
        throw fail(what +
                   (kind.mips == MapMips::Given ? " needs its full MIP chain: "
                                                : " holds level 0 only: ") +
                   std::to_string(levels) + " levels, got " + std::to_string(chain.size()));
    for (const Image& level : chain) {
        if (level.width != w || level.height != h || level.channels != kind.channels)
            throw fail(what + "'s levels are " + std::to_string(kind.channels) +
                       "-channel and halve in size");
        for (float v : level.pixels) {
            if (!std::isfinite(v)) throw fail(what + " has a value that is not finite");
            if (kind.kind == MapKind::BaseRoughness && !(v >= 0.0f))
                throw fail(what + "'s alpha0^2 must be finite and >= 0");
            if (kind.kind == MapKind::RoughnessMips && !(v >= 0.0f && v <= 1.0f))
                throw fail(what + "' perceptual roughness must be in [0, 1]");
        }
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
}

}  // namespace

void add_plateau_maps(Scene& scene) {
    std::vector<int> slot_of_map(scene.lean_maps.size(), -1);
    for (Material& material : scene.materials) {
        if (!material.layered.layers.empty() || material.map(MapKind::Plateau) >= 0) continue;
        if (material.lean_map < 0 || std::size_t(material.lean_map) >= scene.lean_maps.size())
            continue;  // validate() reports it
        const PackedLeanMap& lean_map = scene.lean_maps[std::size_t(material.lean_map)];
        if (!lean_map.has_plateau()) continue;
        int& slot = slot_of_map[std::size_t(material.lean_map)];
        if (slot < 0) slot = scene.add_map(MapKind::Plateau, unpack_plateau_layer(lean_map));
        material.map(MapKind::Plateau) = slot;
    }
}

glm::ivec2 mixed_map_size(const Scene& scene, const Material& material) {
    std::vector<glm::ivec2> sizes;
    std::vector<LayerPlacement> placements;
    for (const MaterialLayer& layer : material.layered.layers) {
        const PackedLeanMap& map = scene.lean_maps.at(std::size_t(layer.lean_map));
        if (map.levels.empty())
            throw Error("scene", "material '" + material.name + "' has a layer without levels");
        sizes.emplace_back(map.levels.front().width, map.levels.front().height);
        placements.push_back({layer.tiling, glm::vec2(0.0f)});
    }
    return leanfade::mixed_map_size(sizes, placements);
}

Bounds scene_bounds(const Scene& scene) {
    const float inf = std::numeric_limits<float>::infinity();
    Bounds box{glm::vec3(inf), glm::vec3(-inf)};
    for (const Object& o : scene.objects)
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p((corner & 1) ? o.mesh.bounds.max.x : o.mesh.bounds.min.x,
                              (corner & 2) ? o.mesh.bounds.max.y : o.mesh.bounds.min.y,
                              (corner & 4) ? o.mesh.bounds.max.z : o.mesh.bounds.min.z);
            const glm::vec3 q = glm::vec3(o.transform * glm::vec4(p, 1.0f));
            box.min = glm::min(box.min, q);
            box.max = glm::max(box.max, q);
        }
    if (scene.objects.empty()) return Bounds{};
    return box;
}

void validate(const Scene& scene) {
    if (scene.objects.empty()) throw Error("scene", "the scene has no object");
    for (const Material& m : scene.materials) {
        if (m.lean_map < 0 || m.lean_map >= int(scene.lean_maps.size()))
            throw Error("scene", "material '" + m.name + "' uses LEAN map " +
                                     std::to_string(m.lean_map) + " of " +
                                     std::to_string(scene.lean_maps.size()));
        if ((m.diffuse && !finite(*m.diffuse)) || (m.specular && !finite(*m.specular)) ||
            (m.shininess && !(*m.shininess > 0.0f && std::isfinite(*m.shininess))))
            throw Error("scene", "material '" + m.name +
                                     "' has a colour or shininess that is "
                                     "not a finite, positive number");
        if (!m.layered.layers.empty()) validate_layers(scene, m);
        const auto check_set = [&](const UvTransform& t, std::string_view what) {
            if (t.set < 0 || t.set >= kUvSetCount)
                throw Error("scene", "material '" + m.name + "' samples its " + std::string(what) +
                                         " with texture coordinate set " + std::to_string(t.set) +
                                         " (the meshes have sets 0 and 1)");
        };
        check_set(m.lean_uv, "LEAN map");
        for (const MapKindInfo& kind : kMapKinds) {
            check_set(m.map_uv[std::size_t(kind.kind)], kind.name);
            const int slot = m.map(kind.kind);
            const std::size_t count = scene.maps_of(kind.kind).size();
            if (slot < -1 || slot >= int(count))
                throw Error("scene", "material '" + m.name + "' uses " + std::string(kind.name) +
                                         " " + std::to_string(slot) + " of " +
                                         std::to_string(count));
        }
    }
    for (const MapKindInfo& kind : kMapKinds)
        for (const std::vector<Image>& chain : scene.maps_of(kind.kind))
            validate_surface_map(kind, chain);
    for (const Object& o : scene.objects) {
        if (o.material < 0 || o.material >= int(scene.materials.size()))
            throw Error(o.mesh.name, "uses material " + std::to_string(o.material) + " of " +
                                         std::to_string(scene.materials.size()));
        if (o.mesh.vertices.empty() || o.mesh.indices.empty() || o.mesh.indices.size() % 3 != 0)
            throw Error(o.mesh.name, "the mesh has no triangles");
        for (int c = 0; c < 4; ++c)
            if (!finite(glm::vec3(o.transform[c])) || !std::isfinite(o.transform[c].w))
                throw Error(o.mesh.name, "the object's transform is not finite");
        const float det = glm::determinant(glm::mat3(o.transform));
        if (!(std::abs(det) > 1e-12f) || !std::isfinite(det))
            throw Error(o.mesh.name, "the object's transform is not invertible");
    }
}

}  // namespace leanfade::scene
