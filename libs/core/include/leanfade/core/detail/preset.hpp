#pragma once
// Presets: every parameter of a view (scene, bumps, shading, camera, panes) as a JSON file, saved
// and loaded by the viewer and read by `leanfade render` as its starting settings. GL-free.
//
// Format (every key optional; a missing key keeps the default below; see docs/viewer.md):
//   {
//     "leanfade_preset": 1,
//     "scene": "teapot",
//     "bumps": {"source": "bumps", "from": "auto", "directx": false, "bits": "auto",
//               "seed": 1, "texture_size": 256},
//     "layers": {"sources": [], "weights": [], "strengths": [], "tiling": [],
//                "velocity": [], "weight_map": "", "mixing": "textures"},
//     "maps": {"roughness_map": "rough.png"},
//     "shading": {"light_direction": [-1, 1, 1], "light_color": [1, 1, 1], ...,
//                 "fade_distance": "tangent-z", "fog": "none", ..., "msaa": 1},
//     "camera": {"target": [0, 0, 0], "direction": [0, 0.3, 1], "distance": 3,
//                "fov_y_degrees": 34},
//     "view": {"techniques": ["lean"], "layout": "single", "divider": 0.5,
//              "reference_samples": 4, "resolution_scale": 1,
//              "fly_away": {"near": 2.5, "far": 60, "period": 8}}
//   }
// The keys of "shading" are the member names of ShadingSettings; vectors are arrays of three
// numbers; enums are the command line's names. Reading is strict: an unknown or repeated key, a
// value of the wrong type (a string for a number, 2.5 for an integer), a number that is not
// finite, or a value out of range throws leanfade::Error(file, "key 'shading.fade': cause").
// Techniques, sources, storages, layouts and mixing methods are the command line's names; layer
// velocities are [u, v] pairs. The keys of "maps" are checked by the callers (the map kinds are
// the scene library's).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "leanfade/core/detail/bump_source.hpp"
#include "leanfade/core/detail/camera.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/core/technique.hpp"

namespace leanfade {

// An orbit camera in world space (units are object bounding radii, y up; see gl/renderer.hpp).
struct CameraSettings {
    glm::vec3 target{0.0f};                 // the point looked at; the object's centre is 0
    glm::vec3 direction = kDefaultViewDirection;  // from the target toward the eye, non-zero
    float distance = 3.0f;                  // eye to target, > 1 and <= kMaxCameraDistance
    float fov_y_degrees = 34.0f;            // vertical field of view, (1, 170)
};

// The "fly away" animation of the viewer: the distance goes from near to far and back.
struct FlyAwaySettings {
    float near_distance = 2.5f;  // bounding radii, > 1
    float far_distance = 60.0f;  // > near_distance, <= kMaxCameraDistance
    float period = 8.0f;         // seconds for near -> far -> near, [0.5, 600]
};

// How the viewer shows its panes: one, two with a draggable divider, or two or three side by side.
enum class PaneLayout { Single, Split, SideBySide };
const char* to_string(PaneLayout layout);  // "single", "split", "side-by-side"
// Throws leanfade::Error(setting, "expected single, split or side-by-side, got '...'").
PaneLayout parse_pane_layout(std::string_view name, const std::string& setting = "layout");
// Whether `layout` shows `panes` techniques (1; 2; 2 or 3), and what it needs, for messages
// ("exactly 2 techniques").
bool layout_accepts(PaneLayout layout, std::size_t panes);
const char* layout_requirement(PaneLayout layout);

// A surface map of the material given as a file (a `--roughness-map` of the rendering commands):
// the setting of its map kind (scene::kMapKinds, "roughness_map") and the file. The kinds are the
// scene library's: callers check `kind`.
struct MapFile {
    std::string kind;
    std::string path;
    bool operator==(const MapFile&) const = default;
};

struct Preset {
    std::string scene = "teapot";  // built-in name or an .obj path
    BumpSource bumps;
    LayerSettings layers;        // bump layers instead of bumps.source when not empty
    std::vector<MapFile> maps;   // surface maps of the material, one per kind at most
    ShadingSettings shading;
    CameraSettings camera;
    // The panes, left to right: 1 for single, 2 for split, 2 or 3 for side-by-side.
    std::vector<Technique> techniques{Technique::Lean};
    PaneLayout layout = PaneLayout::Single;
    float divider = 0.5f;           // split: divider position, fraction of the width, [0, 1]
    int reference_samples = 4;      // k of the reference technique, [1, 16]
    float resolution_scale = 1.0f;  // viewer: internal resolution / window, [0.1, 1]
    FlyAwaySettings fly_away;
};

// Names of the layouts in the order of the viewer's list (the enum's order).
const std::vector<std::string>& preset_layouts();

// Parses a preset from JSON text; `name` (the file) is named in errors. Throws leanfade::Error.
Preset preset_from_json(const std::string& text, const std::string& name);
// Reads a preset file: a regular file of at most kMaxPresetFileBytes (input_text.hpp; a directory,
// FIFO or device is refused without a blocking read). Throws leanfade::Error(path, cause) for a
// missing, unreadable, irregular or too large file and for everything preset_from_json refuses
// (text of the file in messages is escaped).
Preset read_preset(const std::string& path);
// The preset as pretty-printed JSON with every key; numbers in their shortest exact form, so that
// preset_from_json(preset_to_json(p)) == p.
std::string preset_to_json(const Preset& preset);
// Checks every value as read_preset does; throws leanfade::Error(name, "key '...': cause").
void validate(const Preset& preset, const std::string& name);

}  // namespace leanfade
