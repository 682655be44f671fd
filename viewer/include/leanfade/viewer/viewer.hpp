#pragma once
// `leanfade view`: an interactive window (GLFW, OpenGL 4.5 core) on the renderer with a Dear ImGui
// panel for every parameter, an orbit camera, split views of two or three techniques, frame
// times, shader hot reload, screenshots and presets. See docs/viewer.md.
#include <string>
#include <utility>
#include <vector>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/scene/material.hpp"
#include "leanfade/viewer/session.hpp"

namespace leanfade::viewer {

enum class TimingMode {
    Auto,  // GPU timer queries, except on software renderers (llvmpipe, softpipe): CPU
    Gpu,   // GL_TIME_ELAPSED queries
    Cpu,   // CPU time around each pane's rendering, bracketed by glFinish
};

struct ViewerOptions {
    Preset preset;          // the initial parameters (valid: validate(Preset))
    scene::Scene scene;     // preset.scene with preset.bumps, already loaded (scene::build_scene)
    BumpLoader load_bumps;  // for bumps chosen later in the panel
    // Shader folder for hot reload; empty: ./shaders when run from a checkout, else the source
    // tree the binary was built from if it still exists, else the built-in shaders.
    std::string shader_dir;
    int width = 1280;  // window size in pixels
    int height = 800;
    // Lower preset.resolution_scale to 0.5 on software renderers (llvmpipe) for interactivity.
    bool auto_scale = true;
    bool fly_away = false;  // start with the fly-away animation running
    // Moving bump layers (the ocean, docs/ocean.md): the animation's period in seconds, the
    // range of the panel's time slider; 0: the scene does not move (no slider).
    float loop_seconds = 0.0f;
    // A scene's own cameras in world space (the ocean's near, mid and far): when given, the panel
    // chooses among them instead of the orbit camera.
    std::vector<std::pair<std::string, gl::View>> scene_views;
    TimingMode timing = TimingMode::Auto;
    // > 0: render this many frames, save `screenshot` (the whole window, panel included) if
    // given, and return: for automation and tests.
    int frames = 0;
    std::string screenshot;
    std::string preset_path = "leanfade_preset.json";  // default file of the panel's presets
    bool debug_output = false;                         // print GL debug messages
};

// Opens the window and runs until it is closed (Esc, the window's close button) or `frames`
// frames are done; returns the exit code (0). Errors inside the viewer (a missing file, a shader
// that does not compile) are shown in the panel and leave the previous state. Throws
// leanfade::Error when no window with an OpenGL 4.5 core context can be opened (no X display,
// say), when the initial state cannot be uploaded, or when the screenshot cannot be written.
int run_viewer(ViewerOptions options);

}  // namespace leanfade::viewer
