// The viewer's state: loading with all-or-nothing semantics, presets, shader hot reload.
#include "leanfade/viewer/session.hpp"

#include <cctype>
#include <cstdio>
#include <utility>

#include "leanfade/core/error.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::viewer {
namespace {

constexpr std::size_t kMaxErrors = 8;

std::string with_thousands(std::size_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

const char* storage_name(Storage storage) {
    switch (storage) {
        case Storage::Unorm8:
            return "8-bit";
        case Storage::Unorm16:
            return "16-bit";
        case Storage::Float16:
            return "half float";
        case Storage::Float32:
            return "float";
    }
    return "?";
}

bool is_ktx2(const std::string& path) {
    if (path.size() < 5) return false;
    std::string tail = path.substr(path.size() - 5);
    for (char& c : tail) c = char(std::tolower(static_cast<unsigned char>(c)));
    return tail == ".ktx2";
}

}  // namespace

namespace {

// The one-object scene of a mesh and a LEAN map (material 0 without overrides).
scene::Scene single_object_scene(const scene::Mesh& mesh, const PackedLeanMap& map) {
    scene::Scene result;
    result.objects.push_back(scene::Object{mesh, 0, glm::mat4(1.0f)});
    result.materials.push_back(scene::Material{"default", 0, {}, {}, {}, {}});
    result.lean_maps.push_back(map);
    scene::add_plateau_maps(result);  // two-lobe LEAN's layer (docs/math.md §10)
    return result;
}

std::string describe_objects(const scene::Scene& s) {
    std::size_t triangles = 0;
    for (const scene::Object& o : s.objects) triangles += o.mesh.triangle_count();
    const std::string name = s.objects.size() == 1 ? s.objects.front().mesh.name
                                                   : std::to_string(s.objects.size()) + " objects";
    return name + ": " + with_thousands(triangles) + " triangles";
}

}  // namespace

Session::Session(gl::Context& context, gl::ShaderSources sources, BumpLoader loader, Preset preset,
                 const scene::Mesh& mesh, const PackedLeanMap& map)
    : Session(context, std::move(sources), std::move(loader), std::move(preset),
              single_object_scene(mesh, map)) {}

Session::Session(gl::Context& context, gl::ShaderSources sources, BumpLoader loader, Preset preset,
                 const scene::Scene& scene)
    : context_(context),
      renderer_(context, sources),
      loader_(std::move(loader)),
      preset_(std::move(preset)),
      camera_(preset_.camera),
      reloadable_(sources.origin() != "embedded"),
      shader_origin_(sources.origin()) {
    renderer_.set_scene(scene);
    scene_ = scene;
    mesh_description_ = describe_objects(scene_);
}

void Session::set_mesh(const scene::Mesh& mesh) {
    scene::Scene next = scene_;
    next.objects = {scene::Object{mesh, 0, glm::mat4(1.0f)}};
    renderer_.set_scene(next);
    scene_ = std::move(next);
    mesh_description_ = describe_objects(scene_);
    ++generation_;
}

void Session::set_map(const PackedLeanMap& map) {
    scene::Scene next = scene_;
    next.lean_maps = {map};
    next.cross_terms.clear();
    next.weight_maps.clear();
    next.maps_of(scene::MapKind::Plateau).clear();  // the old map's
    for (scene::Material& m : next.materials) {
        m.lean_map = 0;
        m.layered = {};
        m.map(scene::MapKind::Plateau) = -1;
    }
    scene::add_plateau_maps(next);
    renderer_.set_scene(next);
    scene_ = std::move(next);
    ++generation_;
}

Preset Session::snapshot() const {
    Preset p = preset_;
    p.camera = camera_.settings();
    return p;
}

std::vector<gl::Technique> Session::techniques() const {
    return preset_.techniques;
}

void Session::report_error(const std::string& message) {
    std::fprintf(stderr, "leanfade view: %s\n", message.c_str());
    errors_.push_back(message);
    if (errors_.size() > kMaxErrors) errors_.erase(errors_.begin());
}

void Session::report_status(const std::string& message) {
    status_ = message;
}

std::string Session::map_description() const {
    const gl::LeanTextureInfo& info = renderer_.lean_texture();
    return std::to_string(info.width) + "x" + std::to_string(info.height) + ", " +
           std::to_string(info.levels) + " levels, " + storage_name(info.storage) +
           (info.roughness_baked ? ", 1/s baked" : "");
}

bool Session::load_scene(const std::string& name_or_path) {
    try {
        const scene::Mesh mesh = scene::make_scene_mesh(name_or_path);
        set_mesh(mesh);
        preset_.scene = name_or_path;
        report_status("loaded " + mesh_description_);
        return true;
    } catch (const Error& e) {
        report_error(e.what());
        return false;
    }
}

bool Session::load_bumps(const BumpSource& source) {
    try {
        Preset checked = preset_;
        checked.bumps = source;
        validate(checked, "bumps");
        const PackedLeanMap map = loader_(source, preset_.shading);
        set_map(map);
        preset_.bumps = source;
        report_status("loaded " + source.source + " (" + map_description() + ")");
        return true;
    } catch (const Error& e) {
        report_error(e.what());
        return false;
    }
}

bool Session::rebake_bumps() {
    if (is_ktx2(preset_.bumps.source)) {
        report_status("bump strength: " + preset_.bumps.source +
                      " is a baked LEAN map, its strength is fixed");
        return true;
    }
    return load_bumps(preset_.bumps);
}

bool Session::load_preset(const std::string& path) {
    try {
        Preset p = read_preset(path);
        // Everything is read before anything is uploaded.
        const scene::Mesh mesh = scene::make_scene_mesh(p.scene);
        const PackedLeanMap map = loader_(p.bumps, p.shading);
        scene::Scene next = single_object_scene(mesh, map);
        renderer_.set_scene(next);  // all or nothing
        scene_ = std::move(next);
        mesh_description_ = describe_objects(scene_);
        ++generation_;
        camera_ = OrbitCamera(p.camera);
        preset_ = std::move(p);
        report_status("loaded preset " + path);
        return true;
    } catch (const Error& e) {
        report_error(e.what());
        return false;
    }
}

bool Session::save_preset(const std::string& path) {
    try {
        if (path.empty()) throw Error("preset", "no file name given");
        const std::string text = preset_to_json(snapshot());
        io::AtomicFile file(path);
        file.write(text.data(), text.size());
        file.commit();
        report_status("saved preset " + path);
        return true;
    } catch (const Error& e) {
        report_error(e.what());
        return false;
    }
}

bool Session::reload_shaders() {
    if (!reloadable_) {
        report_error(
            "shaders: the built-in shaders are in use; run the viewer from a checkout "
            "(with its shaders/ folder) or with --shader-dir to reload them");
        return false;
    }
    try {
        renderer_.rebuild_shaders();
        ++generation_;
        report_status("shaders reloaded from " + shader_origin_);
        return true;
    } catch (const Error& e) {
        report_error(std::string(e.what()) + " (the previous shaders stay in use)");
        return false;
    }
}

}  // namespace leanfade::viewer
