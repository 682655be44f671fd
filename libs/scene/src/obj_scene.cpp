// The renderer's scene of an OBJ model with MTL materials (leanfade/scene/detail/obj_loader.hpp).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"
#include "leanfade/version.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;

std::string generator_string() {
    return std::string(LEANFADE_GENERATOR);
}

// `name` (an mtllib or texture name of `statement`) inside `folder`, or Error(`file`, cause).
std::string confined_path(const std::string& file, const std::string& statement,
                          const std::string& name, const fs::path& folder) {
    const auto refuse = [&](const std::string& cause) {
        throw Error(file, statement + " '" + escape_text(name, 80) + "' " + cause);
    };
    if (name.find('\0') != std::string::npos) refuse("contains a NUL character");
    if (name.front() == '/') refuse("is an absolute path (only paths inside the OBJ's folder)");
    const std::size_t colon = name.find(':');
    if (colon != std::string::npos && name.find('/') > colon)
        refuse("has a scheme or drive letter (only paths inside the OBJ's folder)");
    for (const auto& part : fs::path(name))
        if (part == "..") refuse("leaves the OBJ's folder ('..')");
    // Where the name leads, before any byte is read: a symbolic link inside the folder to a file
    // outside it is outside (the glTF loader's rule, gltf_loader.cpp).
    const std::string path = (folder / name).string();
    if (!resolves_inside(path, folder.string()))
        refuse("resolves outside the OBJ's folder (through a symbolic link)");
    return path;
}

struct MaterialBuilder {
    const ObjModel& model;
    const ObjBakeSettings& settings;
    ObjSceneReport& report;
    fs::path folder;
    Scene scene;
    std::map<std::string, int> textures;  // base colour texture path -> index

    Image read(const std::string& path) const {
        io::ReadOptions options;
        options.max_dimension = settings.max_image_size;
        return io::read_image(path, options);
    }

    PackedLeanMap bake(const Image& input, BakeSource source, const BakeOptions& options,
                       const std::string& name) const {
        return leanfade::bake(BakeInput(input, source, name),
                              BakeSettings{.options = options,
                                           .storage = {settings.storage, settings.auto_storage},
                                           .generator = generator_string(),
                                           .keep_empty_plateau = true})
            .packed;
    }

    int lean_map(const MtlMaterial& m, const std::string& mtl) {
        BakeOptions options;
        options.threads = settings.threads;
        options.strict_normals = settings.strict_normals;
        PackedLeanMap map;
        // A normal map (OpenGL convention), its slopes times -bm.
        const auto bake_normals = [&](Image normals, const std::string& path) {
            if (normals.channels < 3)
                throw Error(path, "a normal map needs 3 or 4 channels, this image has " +
                                      std::to_string(normals.channels));
            // Repaired before the multiplier, which would turn (0, 0, 0) padding into a normal.
            NormalRepairs repairs;
            if (!settings.strict_normals) repairs = count_normal_repairs(normals);
            if (repairs.any()) normals = repair_normal_map(normals);
            if (m.bump_multiplier != 1.0f) detail::scale_normals(normals, m.bump_multiplier);
            PackedLeanMap baked = bake(normals, BakeSource::Normal, options, path);
            baked.normal_repairs = repairs;
            if (repairs.any()) report.repaired.emplace_back(path, repairs);
            return baked;
        };
        if (!m.normal_map.empty()) {
            const std::string path = confined_path(mtl, "norm", m.normal_map, folder);
            map = bake_normals(read(path), path);
        } else if (!m.bump_map.empty()) {
            const std::string path = confined_path(mtl, "map_Bump", m.bump_map, folder);
            if (m.bump_multiplier == 0.0f)
                throw Error(mtl, "material '" + m.name + "': -bm must not be 0");
            Image image = read(path);
            if (resolve_bake_source(BakeSource::Auto, image) == BakeSource::Normal) {
                // A colour image where a height map is expected: the normal map that Blender's
                // OBJ exporter (and others) write as map_Bump. Taken by bake's content rule
                // (BakeSource::Auto), and said.
                report.warnings.push_back(
                    mtl + ": material '" + m.name + "': map_Bump " + m.bump_map +
                    " is a colour image (not grey), baked as a normal map (OpenGL convention); "
                    "name it with norm to say so");
                map = bake_normals(std::move(image), path);
            } else {
                options.strength = m.bump_multiplier;
                map = bake(image, BakeSource::Height, options, path);
            }
        } else {
            Image flat(1, 1, 3, 0.5f);
            flat.pixels[2] = 1.0f;
            map = bake(flat, BakeSource::Normal, options, "flat");
        }
        scene.lean_maps.push_back(std::move(map));
        return int(scene.lean_maps.size()) - 1;
    }

    Material material(const MtlMaterial& m, const std::string& mtl) {
        Material out;
        out.name = m.name;
        out.diffuse = m.kd;
        out.specular = m.ks;
        out.shininess = m.ns;
        out.lean_map = lean_map(m, mtl);
        if (!m.kd_map.empty()) {
            const std::string path = confined_path(mtl, "map_Kd", m.kd_map, folder);
            auto found = textures.find(path);
            if (found == textures.end())
                found = textures
                            .emplace(path, scene.add_map(MapKind::BaseColor,
                                                         {detail::linear_base_colour(read(path))}))
                            .first;
            out.map(MapKind::BaseColor) = found->second;
        }
        if (!m.roughness_map.empty()) {
            const std::string path = confined_path(mtl, "map_Pr", m.roughness_map, folder);
            out.map(MapKind::BaseRoughness) =
                scene.add_map(MapKind::BaseRoughness,
                              base_alpha_squared_mips(base_roughness_channel(read(path)), 0, path));
        } else if (m.roughness) {
            out.map(MapKind::BaseRoughness) = scene.add_map(
                MapKind::BaseRoughness, base_alpha_squared_mips(Image(1, 1, 1, *m.roughness)));
        }
        return out;
    }
};

}  // namespace

std::vector<std::string> obj_referenced_files(const std::string& path) {
    std::vector<std::string> files;
    const auto add = [&](const std::string& file) {
        if (std::find(files.begin(), files.end(), file) == files.end()) files.push_back(file);
    };
    try {
        const std::string text = read_regular_file(path, kMaxObjFileBytes, "an OBJ file");
        const fs::path folder = fs::path(path).parent_path();
        const auto is_space = [](char c) {
            return std::isspace(static_cast<unsigned char>(c)) != 0;
        };
        for (std::size_t pos = 0; pos < text.size();) {
            const std::size_t end = std::min(text.find('\n', pos), text.size());
            std::string_view line(text.data() + pos, end - pos);
            pos = end + 1;
            line = line.substr(0, line.find('#'));  // as load_obj_model reads it
            while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
            while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
            if (!line.starts_with("mtllib") || line.size() == 6 || !is_space(line[6])) continue;
            line.remove_prefix(6);
            while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
            if (line.empty()) continue;
            std::string mtl;
            try {
                mtl = confined_path(path, "mtllib", std::string(line), folder);
            } catch (const Error&) {
                continue;  // refused when the scene is loaded
            }
            add(mtl);
            try {
                for (const MtlMaterial& m : load_mtl(mtl)) {
                    for (const std::string* name :
                         {&m.kd_map, &m.roughness_map, &m.bump_map, &m.normal_map}) {
                        if (name->empty()) continue;
                        try {
                            add(confined_path(mtl, "map", *name, folder));
                        } catch (const Error&) {
                        }
                    }
                }
            } catch (const Error&) {
                // A malformed MTL: its own message when the scene is loaded.
            }
        }
    } catch (const Error&) {
        // An OBJ that cannot be read: its own message when the scene is loaded.
    }
    return files;
}

Scene make_obj_render_scene(const ObjModel& model, const ObjBakeSettings& settings,
                            ObjSceneReport* report) {
    ObjSceneReport local;
    MaterialBuilder b{model, settings, report != nullptr ? *report : local,
                      fs::path(model.path).parent_path(), {}, {}};
    // Every material of every mtllib (the first definition of a name wins), with its file.
    std::map<std::string, std::pair<MtlMaterial, std::string>> defined;
    for (const std::string& library : model.libraries) {
        const std::string path = confined_path(model.path, "mtllib", library, b.folder);
        for (MtlMaterial& m : load_mtl(path)) defined.emplace(m.name, std::make_pair(m, path));
    }
    std::map<int, int> materials;  // usemtl index (-1: none or undefined) -> scene material
    for (std::size_t p = 0; p < model.parts.size(); ++p) {
        int use = model.part_materials[p];
        const std::string* name =
            use >= 0 ? &model.material_names[std::size_t(use)] : nullptr;
        const auto definition = name != nullptr ? defined.find(*name) : defined.end();
        if (name != nullptr && definition == defined.end()) {
            b.report.warnings.push_back("usemtl '" + escape_text(*name, 80) +
                                        "' is not defined in the MTL files; drawn without "
                                        "a material");
            use = -1;
        }
        auto found = materials.find(use);
        if (found == materials.end()) {
            Material m;
            if (use >= 0) {
                m = b.material(definition->second.first, definition->second.second);
            } else {
                m.name = "default";
                m.lean_map = b.lean_map(MtlMaterial{}, model.path);
            }
            b.scene.materials.push_back(std::move(m));
            found = materials.emplace(use, int(b.scene.materials.size()) - 1).first;
        }
        b.scene.objects.push_back({model.parts[p], found->second, glm::mat4(1.0f)});
    }
    try {
        validate(b.scene);
    } catch (const Error& e) {
        throw Error::file_mentioning(model.path, e.what(), e.mentioned_settings());
    }
    return std::move(b.scene);
}

}  // namespace leanfade::scene
