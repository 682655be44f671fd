#pragma once
// The viewer's state without its window: the renderer with the current mesh and LEAN map, every
// parameter (a Preset plus the orbit camera), and the messages shown in the panel.
//
// Loading a scene, bumps or a preset and reloading shaders are all-or-nothing: on failure the
// error is recorded (and returned false), and the previous mesh, map, parameters and programs stay
// in use. Nothing here needs a window: the tests drive a Session through a headless EGL context.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/scene/detail/mesh.hpp"
#include "leanfade/viewer/camera.hpp"

namespace leanfade::viewer {

// Loads or bakes a LEAN map (a built-in set, an image or a .ktx2 file) as `leanfade render`
// does; `settings.bump_strength` scales height maps. Throws leanfade::Error.
using BumpLoader =
    std::function<PackedLeanMap(const BumpSource& source, const ShadingSettings& settings)>;

class Session {
  public:
    // `preset` must be valid (validate(Preset)); `mesh` and `map` are its scene and bumps, loaded
    // by the caller. The context must be current. Throws leanfade::Error if they cannot be
    // uploaded or a technique name is unknown.
    Session(gl::Context& context, gl::ShaderSources sources, BumpLoader loader, Preset preset,
            const scene::Mesh& mesh, const PackedLeanMap& map);
    // The same with the whole scene (objects, materials, maps) the command line built for the
    // preset; the renderer draws it through Renderer::set_scene.
    Session(gl::Context& context, gl::ShaderSources sources, BumpLoader loader, Preset preset,
            const scene::Scene& scene);

    // The live parameters: the panel edits them in place. camera is kept in camera().
    Preset& preset() { return preset_; }
    const Preset& preset() const { return preset_; }
    OrbitCamera& camera() { return camera_; }
    // The parameters as a preset file stores them (preset() with camera()).
    Preset snapshot() const;
    // The panes' techniques, parsed from preset().techniques.
    std::vector<gl::Technique> techniques() const;

    gl::Renderer& renderer() { return renderer_; }
    gl::Context& context() { return context_; }

    // Loads a built-in scene or an OBJ file and uploads it; on success preset().scene = name.
    bool load_scene(const std::string& name_or_path);
    // Loads or bakes the bumps with preset().shading's strength; on success preset().bumps =
    // source.
    bool load_bumps(const BumpSource& source);
    // Re-bakes the current bumps (after a change of bump strength); a .ktx2 map is kept.
    bool rebake_bumps();
    // Reads a preset and loads its scene and bumps; everything or nothing is applied.
    bool load_preset(const std::string& path);
    // Writes snapshot() atomically.
    bool save_preset(const std::string& path);
    // Rebuilds the programs from the shader folder (hot reload); on an error the previous
    // programs stay. With the built-in shaders there is nothing to reload (an error says so).
    bool reload_shaders();
    bool shaders_reloadable() const { return reloadable_; }
    const std::string& shader_origin() const { return shader_origin_; }

    // Records an error for the panel (and prints it on stderr as "leanfade view: ...").
    void report_error(const std::string& message);
    // Records a success message for the panel's status line.
    void report_status(const std::string& message);
    const std::vector<std::string>& errors() const { return errors_; }
    const std::string& status() const { return status_; }
    void clear_errors() { errors_.clear(); }

    // Increases whenever the mesh, the LEAN map or the programs change (cached images are stale).
    std::uint64_t generation() const { return generation_; }
    // What is loaded: "teapot: 12,345 triangles", "bumps 256x256, 9 levels, 16-bit".
    const std::string& mesh_description() const { return mesh_description_; }
    std::string map_description() const;

  private:
    // Replaces the scene's objects by `mesh` (material 0) and uploads the scene.
    void set_mesh(const scene::Mesh& mesh);
    // Replaces the scene's maps by `map`, one map for every material, and uploads the scene.
    void set_map(const PackedLeanMap& map);

    gl::Context& context_;
    gl::Renderer renderer_;
    BumpLoader loader_;
    Preset preset_;
    OrbitCamera camera_;
    bool reloadable_ = false;
    std::string shader_origin_;
    std::vector<std::string> errors_;
    std::string status_;
    std::uint64_t generation_ = 1;
    std::string mesh_description_;
    scene::Scene scene_;  // what the renderer draws (set_scene)
};

}  // namespace leanfade::viewer
