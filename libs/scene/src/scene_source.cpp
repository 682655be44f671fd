// Scenes from their settings (scene_source.hpp).
#include "leanfade/scene/scene_source.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <variant>

#include "leanfade/core/detail/flow_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/io/detail/png_io.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/version.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

bool is_ktx2_path(const std::string& path) {
    return io::has_extension(path, ".ktx2");
}
bool is_obj_path(const std::string& path) {
    return io::has_extension(path, ".obj");
}

io::ReadOptions read_options_within(int max_size) {
    io::ReadOptions options;
    options.max_dimension = max_size;
    return options;
}

std::string map_setting(MapKind kind) {
    return std::string(info(kind).setting);
}

}  // namespace

bool is_ocean_scene(const std::string& scene) {
    return scene == kOceanSceneName;
}

bool is_builtin_bumps(const std::string& source) {
    const auto& builtins = builtin_bump_names();
    return std::find(builtins.begin(), builtins.end(), source) != builtins.end();
}

BakeOptions on_the_fly_bake_options(const BumpMapSource& source, float bump_strength) {
    BakeOptions options;
    options.strength = bump_strength;
    options.strength_unit = source.strength_unit;
    options.convention = source.directx ? NormalConvention::DirectX : NormalConvention::OpenGL;
    options.strict_normals = source.strict_normals;
    options.spike_fit = source.spike;
    return options;
}

PackedLeanMap load_lean_map(const BumpMapSource& f, const ShadingSettings& settings,
                            SceneSourceReport* report) {
    const std::string generator = std::string(LEANFADE_GENERATOR);
    check_texture_size(f.texture_size, f.max_size, is_builtin_bumps(f.source));
    const io::ReadOptions read_options = read_options_within(f.max_size);
    if (is_ktx2_path(f.source)) return io::read_ktx2(f.source, read_options);
    if (!io::lean_png_pair_base(f.source).empty())  // NAME.lean1.png from `bake --format png`
        return io::read_lean_png_pair(f.source, read_options);

    BakeOptions options = on_the_fly_bake_options(f, settings.bump_strength);
    // The fused fast path of `leanfade bake` (the same bytes as bake_lean_map + pack_lean_map);
    // automatic storage: baked again as 16f or 32f where the StorageProbe finds it better, as
    // `leanfade bake` does.
    auto bake_map = [&](const Image& input, BakeSource kind) {
        return bake(BakeInput(input, kind, f.source), BakeSettings{.options = options,
                                                                   .storage = f.bits,
                                                                   .generator = generator,
                                                                   .keep_empty_plateau = true});
    };
    if (is_builtin_bumps(f.source))
        return bake_map(make_builtin_height(f.source, f.texture_size, f.seed), BakeSource::Height)
            .packed;
    // Integer samples keep their bit depth for the plateau rule (BakeOptions::source_max_code).
    std::variant<Image, UnormImage> read = io::read_image_compact(f.source, read_options);
    if (const UnormImage* samples = std::get_if<UnormImage>(&read)) {
        options.source_max_code = samples->effective_max_code(f.from == BakeSource::Height ? 1 : 3);
        read = samples->to_float();
    }
    const Image& image = std::get<Image>(read);
    PackedBakeResult baked = bake_map(image, f.from);
    // A strength other than the default was given for a normal map.
    const bool strength_given = settings.bump_strength != ShadingSettings{}.bump_strength;
    if (baked.source == BakeSource::Normal && strength_given)
        throw Error::file_mentioning(f.source,
                                     "is a normal map: 'bump_strength' applies to height maps only",
                                     {"bump_strength"});
    if (report != nullptr && baked.packed.normal_repairs.any())
        report->repaired.emplace_back(f.source, baked.packed.normal_repairs);
    if (report != nullptr && baked.source == BakeSource::Normal) {
        const NormalConventionCheck check = check_normal_convention(image, options.convention);
        if (check.looks_flipped())
            report->doubts.push_back({f.source, f.directx,
                                      check.curl_as_read / std::max(check.curl_flipped, 1e-30),
                                      false});
    }
    return std::move(baked.packed);
}

LeanMap load_layer_map(const std::string& source, const BumpMapSource& bumps,
                       const ShadingSettings& settings, SceneSourceReport* report) {
    const io::ReadOptions read_options = read_options_within(bumps.max_size);
    if (is_ktx2_path(source)) {
        LeanMap map = unpack_lean_map(io::read_ktx2(source, read_options));
        if (map.roughness_baked)
            throw Error::file_mentioning(source,
                                         "a bump layer's map must not have roughness baked in "
                                         "(bake it without 'bake_roughness'): the base "
                                         "roughness is added once, after mixing",
                                         {"bake_roughness"});
        return map;
    }
    const BakeOptions options = on_the_fly_bake_options(bumps, settings.bump_strength);
    if (is_builtin_bumps(source))
        return bake_lean_map(make_builtin_height(source, bumps.texture_size, bumps.seed),
                             BakeSource::Height, options)
            .map;
    LeanMap map = bake_lean_map(io::read_image(source, read_options), bumps.from, options).map;
    if (report != nullptr && map.normal_repairs.any())
        report->repaired.emplace_back(source, map.normal_repairs);
    return map;
}

Image top_slopes(const LeanMap& map) {
    const MomentLevel& top = map.levels.front();
    Image slopes(top.width, top.height, 2);
    for (std::size_t t = 0; t < top.mean.size(); ++t) {
        slopes.pixels[2 * t] = top.mean[t].x;
        slopes.pixels[2 * t + 1] = top.mean[t].y;
    }
    return slopes;
}

OceanSettings ocean_settings(const OceanSource& ocean, const BumpMapSource& bumps) {
    OceanSettings settings;
    settings.layers = ocean.layers;
    check_texture_size(bumps.texture_size, bumps.max_size, true);
    settings.texture_size = bumps.texture_size;
    settings.seed = bumps.seed;
    if (ocean.flow == "none") {
        settings.flow = OceanFlow::None;
    } else if (ocean.flow == "gyre") {
        settings.flow = OceanFlow::Gyre;
    } else {
        settings.flow = OceanFlow::Image;
        settings.flow_field = flow_from_rg(
            io::read_image(ocean.flow, read_options_within(bumps.max_size)), ocean.flow);
    }
    validate(settings);
    return settings;
}

namespace {

// A weight map: the first `layers` channels of an image, each texel's weights scaled to sum 1,
// as RGBA (the channels past the layers 0).
Image load_weight_map(const std::string& path, int layers, int max_size) {
    const Image image = io::read_image(path, read_options_within(max_size));
    if (image.channels < layers)
        throw Error(path, "a weight map needs a channel per layer: " + std::to_string(layers) +
                              " layers, " + std::to_string(image.channels) + " channels");
    Image weights(image.width, image.height, 4);
    for (std::size_t t = 0; t < image.texel_count(); ++t) {
        float sum = 0.0f;
        for (int c = 0; c < layers; ++c) {
            const float w = image.pixels[t * std::size_t(image.channels) + std::size_t(c)];
            if (!(w >= 0.0f) || !std::isfinite(w))
                throw Error(path, "weights must be finite and >= 0");
            sum += w;
        }
        if (!(sum > 0.0f))
            throw Error(path, "texel " + std::to_string(t) + " has no weight on any layer");
        for (int c = 0; c < layers; ++c)
            weights.pixels[4 * t + std::size_t(c)] =
                image.pixels[t * std::size_t(image.channels) + std::size_t(c)] / sum;
    }
    return weights;
}

// The roughness map's α0² chain (docs/math.md §9) on every material of the scene. Checked before
// anything is baked: it needs Cook-Torrance and a scene whose material the settings build.
void check_roughness_map(const SceneSource& source, const ShadingSettings& settings) {
    if (source.bumps.map_file(MapKind::BaseRoughness).empty()) return;
    if (settings.brdf != Brdf::CookTorrance)
        throw Error::setting(
            map_setting(MapKind::BaseRoughness),
            "needs 'brdf' cook-torrance (the base roughness of Blinn-Phong is 1/s, "
            "'shininess')",
            {"brdf", "shininess"});
    if (is_ocean_scene(source.scene) || is_gltf_path(source.scene))
        throw Error::setting(
            map_setting(MapKind::BaseRoughness),
            "applies to the material of the bumps or layers, not to the ocean or a "
            "glTF scene's own materials");
}

void add_roughness_map(Scene& result, const BumpMapSource& bumps) {
    const std::string& path = bumps.map_file(MapKind::BaseRoughness);
    if (path.empty()) return;
    io::ReadOptions read_options = read_options_within(bumps.max_size);
    read_options.drop_alpha = false;  // a glTF metallic-roughness texture keeps its channels
    const int slot =
        result.add_map(MapKind::BaseRoughness,
                       base_alpha_squared_mips(
                           base_roughness_channel(io::read_image(path, read_options)), 0, path));
    for (Material& material : result.materials) material.map(MapKind::BaseRoughness) = slot;
}

// Another tool's roughness MIPs on every material of the bumps. Checked before anything is baked.
void check_roughness_mips(const SceneSource& source) {
    if (source.bumps.map_file(MapKind::RoughnessMips).empty()) return;
    if (is_ocean_scene(source.scene) || is_gltf_path(source.scene) || !source.layers.empty())
        throw Error::setting(
            map_setting(MapKind::RoughnessMips),
            "applies to the material of the bumps, not to layers, the ocean or a glTF "
            "scene's own materials");
}

void add_roughness_mips(Scene& result, const BumpMapSource& bumps) {
    const std::string& path = bumps.map_file(MapKind::RoughnessMips);
    if (path.empty()) return;
    std::vector<Image> chain;
    for (const Image& level : io::read_mip_series(path, read_options_within(bumps.max_size)))
        chain.push_back(base_roughness_channel(level));
    int slot = -1;
    try {
        slot = result.add_map(MapKind::RoughnessMips, std::move(chain));
        validate(result);
    } catch (const Error& e) {
        throw Error(path, e.cause());  // the series names the file
    }
    for (Material& material : result.materials) material.map(MapKind::RoughnessMips) = slot;
}

// The maps whose rows read their file generically (MapFileRead::Image). Checked before anything
// is baked: they go on the material the settings build.
void check_image_maps(const SceneSource& source) {
    for (const MapKindInfo& row : kMapKinds) {
        if (row.file_read != MapFileRead::Image || source.bumps.map_file(row.kind).empty())
            continue;
        if (is_ocean_scene(source.scene) || is_gltf_path(source.scene))
            throw Error::setting(
                std::string(row.setting),
                "applies to the material of the bumps or layers, not to the ocean or a "
                "glTF scene's own materials");
    }
}

// `image` with the row's channel count: RGBA (detail::rgba_of: grey replicated to RGB, alpha 1
// where absent) for 4, the first channel (detail::image_channel) for 1. Throws Error(path, cause)
// for a value that is not finite or below 0.
Image map_channels(const Image& image, int channels, const std::string& path) {
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < image.channels; ++c)
                if (const float v = image.at(x, y, c); !std::isfinite(v) || v < 0.0f)
                    throw Error(path, "value " + shortest_text(v) + " at texel (" +
                                          std::to_string(x) + ", " + std::to_string(y) +
                                          ") is not a finite value >= 0");
    return channels == 4 ? detail::rgba_of(image) : detail::image_channel(image, 0);
}

void add_image_maps(Scene& result, const BumpMapSource& bumps) {
    for (const MapKindInfo& row : kMapKinds) {
        const std::string& path = bumps.map_file(row.kind);
        if (row.file_read != MapFileRead::Image || path.empty()) continue;
        const int slot = result.add_map(
            row.kind, {map_channels(io::read_image(path, read_options_within(bumps.max_size)),
                                    row.channels, path)});
        for (Material& material : result.materials) material.map(row.kind) = slot;
    }
}

void add_layered_material(Scene& result, const SceneSource& source, const ShadingSettings& settings,
                          SceneSourceReport* report) {
    const LayerSettings& f = source.layers;
    const BumpMapSource& bumps = source.bumps;
    const std::vector<std::string>& sources = f.sources;
    const std::size_t n = sources.size();
    validate(f);
    const LayerMixing mixing = f.mixing;
    const LayerBlend blend = layer_blend(f);
    const std::vector<float> tilings = layer_tilings(f);
    const std::vector<glm::vec2> velocities = layer_velocities(f);
    check_texture_size(bumps.texture_size, bumps.max_size,
                       std::any_of(sources.begin(), sources.end(), is_builtin_bumps));
    // Automatic storage: the storage a StorageProbe of the float map chooses (as `leanfade bake`).
    auto storage_of = [&](const LeanMap& m) {
        if (!bumps.bits.automatic || m.levels.empty()) return bumps.bits.storage;
        StorageProbe probe(m.levels[0].width, m.levels[0].height);
        probe.add(m);
        return probe.choose(m.scale);
    };

    std::vector<LeanMap> maps;
    for (const std::string& layer : sources)
        maps.push_back(load_layer_map(layer, bumps, settings, report));
    std::vector<Image> slopes;
    for (const LeanMap& m : maps) slopes.push_back(top_slopes(m));
    const std::string generator = std::string(LEANFADE_GENERATOR);

    Material material;
    material.name = "layers";
    bool aligned = f.weight_map.empty();
    for (std::size_t i = 0; i < n; ++i)
        aligned = aligned && velocities[i] == glm::vec2(0.0f) && tilings[i] == 1.0f &&
                  slopes[i].width == slopes[0].width && slopes[i].height == slopes[0].height;
    if (mixing == LayerMixing::Height && aligned) {
        // The height method for layers that lie alike: the slopes mixed first, one map baked
        // from them on the CPU (docs/math.md §6). Layers that move, tile differently or carry
        // per-texel weights are mixed into a map the renderer generates on the GPU for each
        // frame's time (the layered material below).
        BakeOptions options;
        const LeanMap mixed = build_lean_map(mix_slopes(slopes, blend), options);
        material.lean_map = int(result.lean_maps.size());
        result.lean_maps.push_back(pack_lean_map(mixed, storage_of(mixed), generator));
        // The mixed map's own plateau layer, as a bake of it would store it (docs/math.md §10:
        // exact for the height method, which mixes the slopes themselves).
        add_plateau_layer(result.lean_maps.back(), options.plateau_epsilon, 0, 0.0f, bumps.spike);
        result.materials.push_back(std::move(material));
        return;
    }
    material.layered.mixing = mixing;
    material.layered.weights = blend.weights;
    for (std::size_t i = 0; i < n; ++i) {
        MaterialLayer layer;
        layer.lean_map = int(result.lean_maps.size());
        layer.strength = blend.strengths[i];
        layer.tiling = tilings[i];
        layer.velocity = velocities[i];
        material.layered.layers.push_back(layer);
        result.lean_maps.push_back(pack_lean_map(maps[i], storage_of(maps[i]), generator));
    }
    material.lean_map = material.layered.layers.front().lean_map;
    if (mixing == LayerMixing::Textures) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j) {
                if (slopes[i].width != slopes[j].width || slopes[i].height != slopes[j].height)
                    throw Error::setting("layers", "mixing textures needs layers of one size: '" +
                                                       sources[i] + "' and '" + sources[j] +
                                                       "' differ");
                material.layered.cross_terms.push_back(int(result.cross_terms.size()));
                result.cross_terms.push_back(build_cross_terms(slopes[i], slopes[j]));
            }
    }
    if (!f.weight_map.empty()) {
        material.layered.weight_map = int(result.weight_maps.size());
        result.weight_maps.push_back(load_weight_map(f.weight_map, int(n), bumps.max_size));
    }
    result.materials.push_back(std::move(material));
}

// A glTF scene with its own objects, materials and maps, baked through the LEAN-map cache
// ("auto" storage is 16-bit UNORM here: normal textures have bounded slopes).
Scene build_gltf_scene(const std::string& path, const BumpMapSource& bumps,
                       SceneSourceReport* report) {
    const GltfScene gltf = load_gltf(path);
    GltfBakeSettings bake;
    bake.strict_normals = bumps.strict_normals;
    bake.storage = bumps.bits.automatic ? Storage::Unorm16 : bumps.bits.storage;
    if (bumps.max_size > 0) bake.max_image_size = bumps.max_size;
    bake.cache_folder = default_lean_cache_folder();
    GltfBakeReport baked;
    Scene result;
    try {
        result = make_render_scene(gltf, bake, &baked);
    } catch (const Error&) {
        if (report != nullptr)
            report->warnings.insert(report->warnings.end(), gltf.warnings.begin(),
                                    gltf.warnings.end());
        throw;
    }
    if (report != nullptr) {
        report->warnings.insert(report->warnings.end(), gltf.warnings.begin(), gltf.warnings.end());
        report->warnings.insert(report->warnings.end(), baked.warnings.begin(),
                                baked.warnings.end());
        for (const std::string& image : baked.other_convention)
            report->doubts.push_back({image, false, 0.0, true});
        report->repaired.insert(report->repaired.end(), baked.repaired.begin(),
                                baked.repaired.end());
    }
    return result;
}

Scene build_scene_objects(const SceneSource& source, const ShadingSettings& settings,
                          SceneSourceReport* report) {
    check_roughness_map(source, settings);
    check_roughness_mips(source);
    check_image_maps(source);
    // The built-in ocean: a water plane with moving Gabor wave layers (ocean.hpp).
    if (is_ocean_scene(source.scene))
        return make_ocean_scene(ocean_settings(source.ocean, source.bumps));
    if (is_gltf_path(source.scene)) return build_gltf_scene(source.scene, source.bumps, report);
    // An OBJ with MTL materials brings its own maps unless the bumps (or layers) replace them.
    std::optional<ObjModel> model;
    if (is_obj_path(source.scene)) model = load_obj_model(source.scene);
    if (model && !model->libraries.empty() && !source.bumps.replaces_obj_maps &&
        source.layers.empty()) {
        ObjBakeSettings bake;
        bake.auto_storage = source.bumps.bits.automatic;
        bake.storage = source.bumps.bits.storage;
        bake.max_image_size = source.bumps.max_size;
        bake.strict_normals = source.bumps.strict_normals;
        ObjSceneReport obj_report;
        Scene result = make_obj_render_scene(*model, bake, &obj_report);
        if (report != nullptr) {
            report->warnings.insert(report->warnings.end(), obj_report.warnings.begin(),
                                    obj_report.warnings.end());
            report->repaired.insert(report->repaired.end(), obj_report.repaired.begin(),
                                    obj_report.repaired.end());
        }
        add_roughness_map(result, source.bumps);
        add_roughness_mips(result, source.bumps);
        add_image_maps(result, source.bumps);
        validate(result);
        return result;
    }
    Scene result;
    Object object;
    // The OBJ's one part is load_obj's mesh (the same vertices, in the same order); an unknown
    // name: the library's message lists every scene of kBuiltinScenes and the files.
    object.mesh = model && model->parts.size() == 1 ? std::move(model->parts.front())
                                                    : make_scene_mesh(source.scene);
    // The plane's uv runs 0..50 (a repeat per 0.4 world units), right for the built-in sets; a
    // map of one's own (an image or a .ktx2) would be too fine to see: it repeats 5 times
    // across (uv 0..5, a repeat per 4 world units), before the shading's tiling.
    if (source.scene == "plane" && source.layers.empty() && !is_builtin_bumps(source.bumps.source))
        for (Vertex& v : object.mesh.vertices) {
            v.uv *= kUserMapPlaneUvScale;
            v.uv1 = v.uv;
        }
    object.material = 0;
    result.objects.push_back(std::move(object));
    if (source.layers.empty()) {
        Material material;
        material.name = "default";
        material.lean_map = 0;
        result.lean_maps.push_back(load_lean_map(source.bumps, settings, report));
        result.materials.push_back(std::move(material));
    } else {
        add_layered_material(result, source, settings, report);
    }
    add_roughness_map(result, source.bumps);
    add_roughness_mips(result, source.bumps);
    add_image_maps(result, source.bumps);
    validate(result);
    return result;
}

}  // namespace

Scene build_scene(const SceneSource& source, const ShadingSettings& settings,
                  SceneSourceReport* report) {
    Scene result = build_scene_objects(source, settings, report);
    // Two-lobe LEAN's plateau layer of every single-map material (docs/math.md §10).
    add_plateau_maps(result);
    validate(result);
    return result;
}

std::vector<std::string> scene_source_inputs(const SceneSource& source, const std::string& extra) {
    std::vector<std::string> paths{source.scene, source.bumps.source, extra,
                                   source.layers.weight_map};
    if (is_ocean_scene(source.scene)) paths.push_back(source.ocean.flow);
    // The surface maps' files; every level of a roughness MIP series.
    for (const std::string& file : source.bumps.map_files) paths.push_back(file);
    const std::string& mips = source.bumps.map_file(MapKind::RoughnessMips);
    if (!mips.empty())
        for (const std::string& level : io::mip_series_files(mips)) paths.push_back(level);
    // A glTF scene's buffers and images are inputs too.
    if (is_gltf_path(source.scene))
        for (const std::string& file : gltf_referenced_files(source.scene)) paths.push_back(file);
    // So are an OBJ scene's MTL files and the textures they name.
    if (is_obj_path(source.scene))
        for (const std::string& file : obj_referenced_files(source.scene)) paths.push_back(file);
    for (const std::string& layer : source.layers.sources) paths.push_back(layer);
    std::vector<std::string> inputs;
    for (const std::string& path : paths)
        if (!path.empty() && std::filesystem::exists(path)) inputs.push_back(path);
    return inputs;
}

}  // namespace leanfade::scene
