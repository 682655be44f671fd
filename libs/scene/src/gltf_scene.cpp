// The renderer's scene of a glTF scene (leanfade/scene/gltf.hpp): normal textures baked to LEAN
// maps through the cache, base colour textures decoded to linear RGBA.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"
#include "leanfade/version.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

std::string generator_string() {
    return std::string(LEANFADE_GENERATOR);
}

// The sRGB transfer function inverted (IEC 61966-2-1): encoded [0, 1] -> linear [0, 1].
float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

Image decode(const GltfScene& gltf, const GltfImage& image, const GltfBakeSettings& settings,
             bool drop_alpha) {
    io::ReadOptions options;
    options.max_dimension = settings.max_image_size;
    options.drop_alpha = drop_alpha;
    try {
        return io::read_image_from_memory(image.bytes, image.name, options);
    } catch (const Error& e) {
        throw Error::file_mentioning(gltf.path, e.what(), e.mentioned_settings());
    }
}

std::string settings_text(float scale, Storage storage, bool strict_normals) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &scale, sizeof bits);
    return "source=normal convention=opengl wrap=repeat roughness=none storage=" +
           std::string(to_string(storage)) + " scale=" + std::to_string(bits) +
           " plateau_epsilon=" + shortest_text(BakeOptions{}.plateau_epsilon) +
           (strict_normals ? " strict_normals" : "");
}

}  // namespace

namespace detail {

void scale_normals(Image& normals, float scale) {
    for (std::size_t i = 0; i < normals.texel_count(); ++i) {
        float* t = &normals.pixels[i * std::size_t(normals.channels)];
        glm::vec3 n(2.0f * t[0] - 1.0f, 2.0f * t[1] - 1.0f, 2.0f * t[2] - 1.0f);
        n.x *= scale;
        n.y *= scale;
        const float length = glm::length(n);
        if (length > 0.0f && std::isfinite(length)) n /= length;
        for (int c = 0; c < 3; ++c) t[c] = 0.5f * n[c] + 0.5f;
    }
}

Image rgba_of(const Image& image) {
    Image rgba(image.width, image.height, 4, 1.0f);
    for (std::size_t i = 0; i < image.texel_count(); ++i) {
        const float* in = &image.pixels[i * std::size_t(image.channels)];
        float* out = &rgba.pixels[i * 4];
        const bool gray = image.channels <= 2;
        for (int c = 0; c < 3; ++c) out[c] = in[gray ? 0 : c];
        if (image.channels == 2 || image.channels == 4) out[3] = in[image.channels - 1];
    }
    return rgba;
}

Image linear_base_colour(const Image& decoded) {
    Image rgba = rgba_of(decoded);
    for (std::size_t i = 0; i < rgba.texel_count(); ++i)
        for (int c = 0; c < 3; ++c)
            rgba.pixels[i * 4 + std::size_t(c)] =
                srgb_to_linear(rgba.pixels[i * 4 + std::size_t(c)]);
    return rgba;
}

// Channel `channel` of `image` as a 1-channel image.
Image image_channel(const Image& image, int channel) {
    Image out(image.width, image.height, 1);
    for (std::size_t i = 0; i < image.texel_count(); ++i)
        out.pixels[i] = image.pixels[i * std::size_t(image.channels) + std::size_t(channel)];
    return out;
}

// The first three channels of `image` with alpha 1 (values kept: a linear texture).
Image linear_rgb(const Image& image) {
    Image out(image.width, image.height, 4, 1.0f);
    for (std::size_t i = 0; i < image.texel_count(); ++i)
        for (int c = 0; c < 3; ++c)
            out.pixels[i * 4 + std::size_t(c)] =
                image.pixels[i * std::size_t(image.channels) + std::size_t(c)];
    return out;
}

}  // namespace detail

bool is_gltf_path(const std::string& path) {
    std::string lower = path.substr(path.size() >= 5 ? path.size() - 5 : 0);
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return lower == ".gltf" || (lower.size() >= 4 && lower.substr(lower.size() - 4) == ".glb");
}

void check_cached_image_size(const GltfScene& gltf, int image, int width, int height,
                             int max_dimension) {
    if (width <= max_dimension && height <= max_dimension) return;
    const std::string name = image >= 0 && std::size_t(image) < gltf.images.size()
                                 ? gltf.images[std::size_t(image)].name
                                 : "image " + std::to_string(image);
    throw Error(gltf.path, name + ": image size " + std::to_string(width) + "x" +
                               std::to_string(height) + " exceeds the limit of " +
                               std::to_string(max_dimension) + " texels per side");
}

PackedLeanMap bake_normal_texture(const GltfScene& gltf, int image_index, float scale,
                                  const GltfBakeSettings& settings, bool* from_cache,
                                  std::string* cache_warning) {
    if (image_index < 0 || std::size_t(image_index) >= gltf.images.size())
        throw Error(gltf.path, "image " + std::to_string(image_index) + " does not exist");
    if (!std::isfinite(scale)) throw Error(gltf.path, "normal texture scale is not finite");
    const GltfImage& image = gltf.images[std::size_t(image_index)];
    const LeanMapCache cache(settings.cache_folder, settings.max_cache_bytes);
    const std::string key = lean_cache_key(
        image.bytes, settings_text(scale, settings.storage, settings.strict_normals));
    if (std::optional<PackedLeanMap> cached = cache.find(key, settings.storage)) {
        if (!cached->levels.empty())
            check_cached_image_size(gltf, image_index, cached->levels.front().width,
                                    cached->levels.front().height, settings.max_image_size);
        if (from_cache != nullptr) *from_cache = true;
        return std::move(*cached);
    }
    Image normals = decode(gltf, image, settings, true);
    if (normals.channels < 3)
        throw Error(gltf.path, image.name + ": a normal texture needs 3 channels (RGB), it has " +
                                   std::to_string(normals.channels));
    // Repaired before the scale, which would turn (0, 0, 0) padding into a normal.
    NormalRepairs repairs;
    if (!settings.strict_normals) repairs = count_normal_repairs(normals);
    if (repairs.any()) normals = repair_normal_map(normals);
    const bool looks_flipped =
        check_normal_convention(normals, NormalConvention::OpenGL).looks_flipped();
    if (scale != 1.0f) detail::scale_normals(normals, scale);
    BakeOptions options;
    options.strict_normals = settings.strict_normals;
    options.wrap = Wrap::Repeat;
    options.convention = NormalConvention::OpenGL;
    options.threads = settings.threads;
    PackedLeanMap map;
    try {
        map = bake(BakeInput(normals, BakeSource::Normal, image.name),
                   BakeSettings{.options = options,
                                .storage = StoragePolicy::fixed(settings.storage),
                                .generator = generator_string(),
                                .keep_empty_plateau = true})
                  .packed;
    } catch (const Error& e) {
        throw Error::file_mentioning(gltf.path, e.what(), e.mentioned_settings());
    }
    map.normal_repairs = repairs;
    map.source_looks_flipped = looks_flipped;
    const std::string warning = cache.store(key, map);
    if (cache_warning != nullptr) *cache_warning = warning;
    if (from_cache != nullptr) *from_cache = false;
    return map;
}

Scene make_render_scene(const GltfScene& gltf, const GltfBakeSettings& settings,
                        GltfBakeReport* report) {
    GltfBakeReport local;
    GltfBakeReport& r = report != nullptr ? *report : local;
    Scene scene;
    std::map<std::pair<int, float>, int> maps;  // (normal image, scale) -> lean map
    std::map<int, int> textures;                // base colour image -> texture
    std::map<std::string, int> files;           // a LEAN map file the glTF names -> lean map
    std::map<std::pair<int, float>, int> roughness;  // (metallic-roughness image, factor) -> map
    // image -> texture of each kind made from one image's channels, decoded once per kind.
    std::map<std::pair<MapKind, int>, int> image_maps;
    const auto image_map = [&](MapKind kind, int image_index, const char* what, int min_channels,
                               Image (*convert)(const Image&)) {
        const auto key = std::make_pair(kind, image_index);
        auto found = image_maps.find(key);
        if (found == image_maps.end()) {
            const GltfImage& image = gltf.images[std::size_t(image_index)];
            const Image decoded = decode(gltf, image, settings, false);
            if (decoded.channels < min_channels)
                throw Error(gltf.path, image.name + ": " + what + " needs " +
                                           std::to_string(min_channels) + " channels, it has " +
                                           std::to_string(decoded.channels));
            found = image_maps.emplace(key, scene.add_map(kind, {convert(decoded)})).first;
        }
        return found->second;
    };
    int flat_map = -1;
    std::uint64_t map_bytes = 0;  // of the LEAN maps held
    for (const GltfMaterial& gm : gltf.materials) {
        Material m;
        m.name = gm.name;
        m.diffuse.emplace(gm.base_color_factor.x, gm.base_color_factor.y, gm.base_color_factor.z);
        m.base_alpha = gm.base_color_factor.w;
        m.alpha_cutoff = gm.alpha_cutoff;
        m.blend = gm.blend;
        m.double_sided = gm.double_sided;
        m.lean_uv = leanfade_uv_transform(gm.normal_transform);
        m.map_uv[std::size_t(MapKind::BaseColor)] = leanfade_uv_transform(gm.base_color_transform);
        m.map_uv[std::size_t(MapKind::BaseRoughness)] =
            leanfade_uv_transform(gm.metallic_roughness_transform);
        m.map_uv[std::size_t(MapKind::Metallic)] =
            leanfade_uv_transform(gm.metallic_roughness_transform);
        m.map_uv[std::size_t(MapKind::Occlusion)] = leanfade_uv_transform(gm.occlusion_transform);
        m.map_uv[std::size_t(MapKind::Emissive)] = leanfade_uv_transform(gm.emissive_transform);
        m.map_uv[std::size_t(MapKind::Anisotropy)] = leanfade_uv_transform(gm.anisotropy_transform);
        // glTF 2.0 §3.9.2: metalness = metallicFactor x the metallic-roughness texture's B.
        m.metallic = gm.metallic_factor;
        if (gm.metallic_roughness_image >= 0)
            m.map(MapKind::Metallic) = image_map(
                MapKind::Metallic, gm.metallic_roughness_image, "a metallic-roughness texture", 3,
                [](const Image& decoded) { return detail::image_channel(decoded, 2); });
        // glTF 2.0 §3.9.4: the occlusion texture's R, weighed by its strength.
        m.occlusion_strength = gm.occlusion_strength;
        if (gm.occlusion_image >= 0)
            m.map(MapKind::Occlusion) =
                image_map(MapKind::Occlusion, gm.occlusion_image, "an occlusion texture", 1,
                          [](const Image& decoded) { return detail::image_channel(decoded, 0); });
        // glTF 2.0 §3.9.5: emissiveFactor x the emissive texture, sRGB decoded.
        m.emissive = gm.emissive_factor;
        if (gm.emissive_image >= 0)
            m.map(MapKind::Emissive) =
                image_map(MapKind::Emissive, gm.emissive_image, "an emissive texture", 1,
                          detail::linear_base_colour);
        // KHR_materials_anisotropy: its texture is linear (RG direction, B strength).
        m.anisotropy_strength = gm.anisotropy_strength;
        m.anisotropy_rotation = gm.anisotropy_rotation;
        if (gm.anisotropy_image >= 0)
            m.map(MapKind::Anisotropy) = image_map(MapKind::Anisotropy, gm.anisotropy_image,
                                                   "an anisotropy texture", 3, detail::linear_rgb);
        if (!gm.lean_map_file.empty() || !gm.lean_map_bytes.empty()) {
            // The map the file names or holds (`bake SCENE -o OUT`): drawn as written.
            const std::string key = !gm.lean_map_file.empty()
                                        ? gm.lean_map_file
                                        : "bufferView " + std::to_string(gm.lean_map_view);
            auto found = files.find(key);
            if (found == files.end()) {
                scene.lean_maps.push_back(
                    !gm.lean_map_file.empty()
                        ? io::read_ktx2(gm.lean_map_file)
                        : io::read_ktx2_from_memory(gm.lean_map_bytes,
                                                    gltf.path + " (" + std::string(kGltfLeanMapExtension) +
                                                        " " + key + ")"));
                for (const PackedLevel& level : scene.lean_maps.back().levels)
                    map_bytes += level.lean1.size() + level.lean2.size();
                if (map_bytes > settings.max_lean_map_bytes)
                    throw Error(gltf.path, "the LEAN maps of its materials exceed " +
                                               std::to_string(settings.max_lean_map_bytes) +
                                               " bytes");
                found = files.emplace(key, int(scene.lean_maps.size()) - 1).first;
            }
            m.lean_map = found->second;
        } else if (gm.normal_image >= 0) {
            const auto key = std::make_pair(gm.normal_image, gm.normal_scale);
            auto found = maps.find(key);
            if (found == maps.end()) {
                bool cached = false;
                std::string warning;
                scene.lean_maps.push_back(bake_normal_texture(gltf, gm.normal_image,
                                                              gm.normal_scale, settings, &cached,
                                                              &warning));
                for (const PackedLevel& level : scene.lean_maps.back().levels)
                    map_bytes += level.lean1.size() + level.lean2.size();
                if (map_bytes > settings.max_lean_map_bytes)
                    throw Error(gltf.path, "the LEAN maps of its normal textures exceed " +
                                               std::to_string(settings.max_lean_map_bytes) +
                                               " bytes (" + std::to_string(maps.size() + 1) +
                                               " maps)");
                ++(cached ? r.from_cache : r.baked);
                if (scene.lean_maps.back().source_looks_flipped)
                    r.other_convention.push_back(gltf.images[std::size_t(gm.normal_image)].name);
                if (scene.lean_maps.back().normal_repairs.any())
                    r.repaired.emplace_back(gltf.images[std::size_t(gm.normal_image)].name,
                                            scene.lean_maps.back().normal_repairs);
                if (!warning.empty()) r.warnings.push_back("cache: " + warning);
                found = maps.emplace(key, int(scene.lean_maps.size()) - 1).first;
            }
            m.lean_map = found->second;
        } else {
            if (flat_map < 0) {
                // A flat surface: B = 0, M = 0 (one texel, no MIP chain to speak of).
                const Image flat(1, 1, 3, 0.5f);
                Image normal = flat;
                normal.pixels[2] = 1.0f;
                BakeOptions options;
                scene.lean_maps.push_back(
                    bake(BakeInput(normal, BakeSource::Normal, "flat"),
                         BakeSettings{.options = options,
                                      .storage = StoragePolicy::fixed(settings.storage),
                                      .generator = generator_string(),
                                      .keep_empty_plateau = true})
                        .packed);
                flat_map = int(scene.lean_maps.size()) - 1;
            }
            m.lean_map = flat_map;
        }
        if (gm.base_color_image >= 0) {
            auto found = textures.find(gm.base_color_image);
            if (found == textures.end()) {
                const GltfImage& image = gltf.images[std::size_t(gm.base_color_image)];
                found = textures
                            .emplace(gm.base_color_image,
                                     scene.add_map(MapKind::BaseColor,
                                                   {detail::linear_base_colour(
                                                       decode(gltf, image, settings, false))}))
                            .first;
            }
            m.map(MapKind::BaseColor) = found->second;
        }
        // The metallic-roughness part's roughness is Cook-Torrance's base roughness per texel:
        // r = roughnessFactor x G of the texture, or the factor alone (docs/gltf.md); α0² = r⁴
        // filtered as the moments are (roughness.hpp), combined with the bumps' covariance at
        // shading time as a roughness map is.
        {
            const auto key = std::make_pair(gm.metallic_roughness_image, gm.roughness_factor);
            auto found = roughness.find(key);
            if (found == roughness.end()) {
                Image r(1, 1, 1, gm.roughness_factor);
                if (gm.metallic_roughness_image >= 0) {
                    const Image texture = decode(
                        gltf, gltf.images[std::size_t(gm.metallic_roughness_image)], settings, false);
                    if (texture.channels < 3)
                        throw Error(gltf.path, gltf.images[std::size_t(gm.metallic_roughness_image)].name +
                                                   ": a metallic-roughness texture has 3 or 4 channels");
                    r = base_roughness_channel(texture);
                    for (float& v : r.pixels) v *= gm.roughness_factor;
                }
                found = roughness
                            .emplace(key, scene.add_map(MapKind::BaseRoughness,
                                                        base_alpha_squared_mips(r)))
                            .first;
            }
            m.map(MapKind::BaseRoughness) = found->second;
        }
        scene.materials.push_back(std::move(m));
    }
    for (const GltfObject& o : gltf.objects)
        scene.objects.push_back({o.mesh, o.material, o.transform});
    try {
        validate(scene);
    } catch (const Error& e) {
        throw Error::file_mentioning(gltf.path, e.what(), e.mentioned_settings());
    }
    return scene;
}

}  // namespace leanfade::scene
