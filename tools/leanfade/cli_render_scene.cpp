// The scene every rendering command draws (cli_render_scene.hpp).
#include "cli_render_scene.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "cli_bake_gltf.hpp"
#include "cli_bake_roughness.hpp"
#include "cli_flags.hpp"
#include "cli_preset.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/core/plateau.hpp"
#include "leanfade/core/procedural.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/core/text.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/obj_loader.hpp"
#include "leanfade/scene/scene.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {
namespace {

bool is_ktx2(const std::string& path) {
    if (path.size() < 5) return false;
    std::string tail = path.substr(path.size() - 5);
    for (char& c : tail) c = char(std::tolower(static_cast<unsigned char>(c)));
    return tail == ".ktx2";
}

}  // namespace

LeanMap load_layer_map(const std::string& source, const LeanSourceFlags& f,
                       const ShadingSettings& settings) {
    io::ReadOptions read_options;
    read_options.max_dimension = f.max_size;
    if (is_ktx2(source)) {
        LeanMap map = unpack_lean_map(io::read_ktx2(source, read_options));
        if (map.roughness_baked)
            throw Error(source, "a bump layer's map must not have roughness baked in (bake it "
                                "without --bake-roughness): the base roughness is added once, "
                                "after mixing");
        return map;
    }
    const BakeOptions options = on_the_fly_bake_options(f, settings);
    if (is_builtin_bumps(source))
        return bake_lean_map(make_builtin_height(source, f.texture_size, f.seed),
                             BakeSource::Height, options)
            .map;
    LeanMap map = bake_lean_map(io::read_image(source, read_options), f.from, options).map;
    if (map.normal_repairs.any())
        std::fprintf(stderr, "leanfade: %s\n",
                     normal_repairs_note(source, map.normal_repairs).c_str());
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

namespace {

// A weight map: the first `layers` channels of an image, each texel's weights scaled to sum 1,
// as RGBA (the channels past the layers 0).
Image load_weight_map(const std::string& path, int layers, int max_size) {
    io::ReadOptions read_options;
    read_options.max_dimension = max_size;
    const Image image = io::read_image(path, read_options);
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

// --roughness-map: its α0² chain (docs/math.md §9) on every material of the scene. Checked before
// anything is baked: it needs Cook-Torrance and a scene whose material the flags build.
void check_roughness_map(const RenderSourceFlags& flags, const ShadingSettings& settings) {
    const std::string& path = flags.bumps.roughness_map;
    if (path.empty()) return;
    if (settings.brdf != Brdf::CookTorrance)
        throw Error(map_flag(scene::MapKind::BaseRoughness),
                    "needs --brdf cook-torrance (the base roughness of Blinn-Phong is 1/s, "
                    "--shininess)");
    if (is_ocean_scene(flags.scene) || scene::is_gltf_path(flags.scene))
        throw Error(map_flag(scene::MapKind::BaseRoughness),
                    "applies to the material of --bumps or --layers, not to the ocean or a "
                    "glTF scene's own materials");
}

void add_roughness_map(scene::Scene& result, const RenderSourceFlags& flags) {
    const std::string& path = flags.bumps.roughness_map;
    if (path.empty()) return;
    io::ReadOptions read_options;
    read_options.max_dimension = flags.bumps.max_size;
    int slot = -1;
    try {
        slot = result.add_map(scene::MapKind::BaseRoughness,
                              base_alpha_squared_mips(
                                  base_roughness_channel(read_roughness_map(path, read_options))));
    } catch (const Error& e) {
        // Name the file for the map's errors.
        if (e.file() == "roughness map") throw Error(path, e.cause());
        throw;
    }
    for (scene::Material& material : result.materials)
        material.map(scene::MapKind::BaseRoughness) = slot;
}

// --roughness-mips: another tool's roughness MIP chain on every material of --bumps (the
// roughness technique reads it, docs/roughness.md). Checked before anything is baked.
void check_roughness_mips(const RenderSourceFlags& flags) {
    if (flags.bumps.roughness_mips.empty()) return;
    if (is_ocean_scene(flags.scene) || scene::is_gltf_path(flags.scene) || !flags.layers.empty())
        throw Error(map_flag(scene::MapKind::RoughnessMips),
                    "applies to the material of --bumps, not to layers, the ocean or a glTF "
                    "scene's own materials");
}

void add_roughness_mips(scene::Scene& result, const RenderSourceFlags& flags) {
    const std::string& path = flags.bumps.roughness_mips;
    if (path.empty()) return;
    io::ReadOptions read_options;
    read_options.max_dimension = flags.bumps.max_size;
    std::vector<Image> chain;
    for (const Image& level : io::read_mip_series(path, read_options))
        chain.push_back(base_roughness_channel(level));
    int slot = -1;
    try {
        slot = result.add_map(scene::MapKind::RoughnessMips, std::move(chain));
        scene::validate(result);
    } catch (const Error& e) {
        throw Error(path, e.cause());  // the series names the file
    }
    for (scene::Material& material : result.materials)
        material.map(scene::MapKind::RoughnessMips) = slot;
}

bool is_obj_path(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    return extension == ".obj";
}

void add_layered_material(scene::Scene& result, const RenderSourceFlags& flags,
                          const ShadingSettings& settings) {
    const LayerSettings& f = flags.layers;
    const std::vector<std::string>& sources = f.sources;
    const std::size_t n = sources.size();
    validate(f);
    const LayerMixing mixing = f.mixing;
    const LayerBlend blend = layer_blend(f);
    const std::vector<float> tilings = layer_tilings(f);
    const std::vector<glm::vec2> velocities = layer_velocities(f);
    check_texture_size(flags.bumps.texture_size, flags.bumps.max_size,
                       std::any_of(sources.begin(), sources.end(), is_builtin_bumps));
    // --bits auto: the storage a StorageProbe of the float map chooses (as `leanfade bake`).
    auto storage_of = [&](const LeanMap& m) {
        if (!flags.bumps.bits.automatic || m.levels.empty()) return flags.bumps.bits.storage;
        StorageProbe probe(m.levels[0].width, m.levels[0].height);
        probe.add(m);
        return probe.choose(m.scale);
    };

    std::vector<LeanMap> maps;
    for (const std::string& source : sources)
        maps.push_back(load_layer_map(source, flags.bumps, settings));
    std::vector<Image> slopes;
    for (const LeanMap& m : maps) slopes.push_back(top_slopes(m));
    const std::string generator = std::string(LEANFADE_GENERATOR);

    scene::Material material;
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
        add_plateau_layer(result.lean_maps.back(), options.plateau_epsilon, 0, 0.0f,
                          flags.bumps.spike);
        result.materials.push_back(std::move(material));
        return;
    }
    material.layered.mixing = mixing;
    material.layered.weights = blend.weights;
    for (std::size_t i = 0; i < n; ++i) {
        scene::MaterialLayer layer;
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
                    throw Error("--layers", "mixing textures needs layers of one size: '" +
                                                sources[i] + "' and '" + sources[j] + "' differ");
                material.layered.cross_terms.push_back(int(result.cross_terms.size()));
                result.cross_terms.push_back(build_cross_terms(slopes[i], slopes[j]));
            }
    }
    if (!f.weight_map.empty()) {
        material.layered.weight_map = int(result.weight_maps.size());
        result.weight_maps.push_back(
            load_weight_map(f.weight_map, int(n), flags.bumps.max_size));
    }
    result.materials.push_back(std::move(material));
}

}  // namespace

void add_layer_options(CLI::App& app, LayerSettings& f) {
    const std::string group = "Bump layers (docs/math.md §6)";
    add_typed_option(app, "--layers", f.sources, parse_names,
                     "2-4 bump layers mixed on one surface instead of --bumps: built-in sets, "
                     "height/normal images or .ktx2 maps, comma-separated")
        ->group(group);
    add_typed_option(
        app, "--layer-weights", f.weights,
        [](const std::string& text) { return parse_numbers(text, "--layer-weights"); },
        "Weight t of each layer, comma-separated, summing to 1 (default: equal)")
        ->group(group);
    add_typed_option(
        app, "--layer-strengths", f.strengths,
        [](const std::string& text) { return parse_numbers(text, "--layer-strengths"); },
        "Strength k of each layer: slopes times k, < 0 flips the layer (default: 1)")
        ->group(group);
    add_typed_option(
        app, "--layer-tiling", f.tiling,
        [](const std::string& text) { return parse_numbers(text, "--layer-tiling"); },
        "Repeats of each layer per unit of the tiled uv (default: 1)")
        ->group(group);
    add_typed_option(
        app, "--layer-velocity", f.velocity,
        [](const std::string& text) { return parse_velocities(text, "--layer-velocity"); },
        "Velocity U:V of each layer in uv per second, comma-separated (a moving "
        "layer; render --time sets the moment)")
        ->group(group);
    app.add_option("--layer-weight-map", f.weight_map,
                   "Image whose channels give each layer's weight per texel (RGBA = t_0..t_3, "
                   "normalised per texel), instead of --layer-weights")
        ->group(group);
    std::string help = "How the layers' moments mix:";
    for (const LayerMixingInfo& row : kLayerMixings)
        help += std::string(" ") + row.name + " (" + row.description + ");";
    help.back() = '.';
    add_typed_option(
        app, "--mixing", f.mixing,
        [](const std::string& text) { return parse_layer_mixing(text, "--mixing"); }, help,
        to_string(f.mixing))
        ->group(group);
}

std::string layers_text(const LayerSettings& layers) {
    return join(layers.sources) + " (" + to_string(layers.mixing) + ")";
}

namespace {

scene::Scene load_scene_objects(const RenderSourceFlags& flags, const ShadingSettings& settings) {
    check_roughness_map(flags, settings);
    check_roughness_mips(flags);
    // The built-in ocean: a water plane with moving Gabor wave layers (cli_ocean.hpp).
    if (is_ocean_scene(flags.scene))
        return scene::make_ocean_scene(ocean_settings(flags.ocean, flags.bumps));
    // A glTF scene brings its own objects, materials and maps (cli_bake_gltf.hpp).
    if (scene::is_gltf_path(flags.scene))
        return load_gltf_render_scene(flags.scene, to_string(flags.bumps.bits),
                                      flags.bumps.max_size, flags.bumps.strict_normals);
    // An OBJ with MTL materials brings its own maps unless --bumps (or --layers) replaces them.
    std::optional<scene::ObjModel> model;
    if (is_obj_path(flags.scene)) model = scene::load_obj_model(flags.scene);
    if (model && !model->libraries.empty() && !flags.bumps.bumps_given && flags.layers.empty()) {
        scene::ObjBakeSettings bake;
        bake.auto_storage = flags.bumps.bits.automatic;
        bake.storage = flags.bumps.bits.storage;
        bake.max_image_size = flags.bumps.max_size;
        bake.strict_normals = flags.bumps.strict_normals;
        scene::ObjSceneReport report;
        scene::Scene result = scene::make_obj_render_scene(*model, bake, &report);
        for (const std::string& warning : report.warnings)
            std::fprintf(stderr, "leanfade: %s: %s\n", flags.scene.c_str(), warning.c_str());
        for (const auto& [file, repairs] : report.repaired)
            std::fprintf(stderr, "leanfade: %s\n", normal_repairs_note(file, repairs).c_str());
        add_roughness_map(result, flags);
        add_roughness_mips(result, flags);
        scene::validate(result);
        return result;
    }
    scene::Scene result;
    scene::Object object;
    // The OBJ's one part is load_obj's mesh (the same vertices, in the same order); an unknown
    // name: the library's message lists every scene of kBuiltinScenes and the files.
    object.mesh = model && model->parts.size() == 1 ? std::move(model->parts.front())
                                                    : scene::make_scene_mesh(flags.scene);
    // The plane's uv runs 0..50 (a repeat per 0.4 world units), right for the built-in sets; a
    // map of one's own (an image or a .ktx2) would be too fine to see: it repeats 5 times
    // across (uv 0..5, a repeat per 4 world units), before --tiling.
    if (flags.scene == "plane" && flags.layers.empty() && !is_builtin_bumps(flags.bumps.source))
        for (scene::Vertex& v : object.mesh.vertices) {
            v.uv *= kUserMapPlaneUvScale;
            v.uv1 = v.uv;
        }
    object.material = 0;
    result.objects.push_back(std::move(object));
    if (flags.layers.empty()) {
        scene::Material material;
        material.name = "default";
        material.lean_map = 0;
        result.lean_maps.push_back(load_lean_map(flags.bumps, settings));
        result.materials.push_back(std::move(material));
    } else {
        add_layered_material(result, flags, settings);
    }
    add_roughness_map(result, flags);
    add_roughness_mips(result, flags);
    scene::validate(result);
    return result;
}

}  // namespace

scene::Scene load_render_scene(const RenderSourceFlags& flags, const ShadingSettings& settings) {
    scene::Scene result = load_scene_objects(flags, settings);
    // Two-lobe LEAN's plateau layer of every single-map material (docs/math.md §10).
    scene::add_plateau_maps(result);
    scene::validate(result);
    return result;
}

std::vector<std::string> render_source_inputs(const RenderSourceFlags& flags,
                                              const std::string& extra) {
    std::vector<std::string> inputs;
    std::vector<std::string> paths{flags.scene, flags.bumps.source, extra,
                                   flags.layers.weight_map, flags.bumps.roughness_map};
    if (is_ocean_scene(flags.scene)) paths.push_back(flags.ocean.flow);
    // Every level of a --roughness-mips series.
    if (!flags.bumps.roughness_mips.empty())
        for (const std::string& level : io::mip_series_files(flags.bumps.roughness_mips))
            paths.push_back(level);
    // A glTF scene's buffers and images are inputs too.
    if (scene::is_gltf_path(flags.scene))
        for (const std::string& file : scene::gltf_referenced_files(flags.scene))
            paths.push_back(file);
    // So are an OBJ scene's MTL files and the textures they name.
    if (is_obj_path(flags.scene))
        for (const std::string& file : scene::obj_referenced_files(flags.scene))
            paths.push_back(file);
    for (const std::string& source : flags.layers.sources) paths.push_back(source);
    for (const std::string& path : paths)
        if (!path.empty() && std::filesystem::exists(path)) inputs.push_back(path);
    return inputs;
}

}  // namespace leanfade::cli
