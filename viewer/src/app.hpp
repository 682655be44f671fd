#pragma once
// The viewer application: the GLFW window, the Dear ImGui panel and the frame loop around a
// Session. Internal to leanfade_viewer (run_viewer() is the public entry point).
#include <array>
#include <memory>
#include <string>
#include <string_view>

#include "display.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/viewer/session.hpp"
#include "leanfade/viewer/viewer.hpp"

struct GLFWwindow;

namespace leanfade::viewer {

inline constexpr int kMaxPanes = 3;

enum class Layout { Single, Split, SideBySide2, SideBySide3 };

struct Pane {
    Canvas canvas;
    PaneTimer timer;
    std::string error;  // why the pane shows no image ("" = fine)
    // What the timer measures (technique, size, generation): a change restarts the timer.
    std::string timed;
    // Destination in GL window coordinates (lower-left origin) and the visible columns.
    int x = 0, y = 0, width = 0, height = 0;
    int visible_x = 0, visible_width = 0;
};

// Owners of the GLFW window (destroyed last) and of Dear ImGui (shut down first).
struct WindowHandle {
    GLFWwindow* window = nullptr;
    bool initialised = false;  // glfwInit succeeded (GLFW stays initialised: see the destructor)
    WindowHandle() = default;
    WindowHandle(const WindowHandle&) = delete;
    WindowHandle& operator=(const WindowHandle&) = delete;
    ~WindowHandle();
};

struct ImGuiHandle {
    bool context = false;  // ImGui::CreateContext
    bool glfw = false;     // the GLFW backend started
    bool opengl = false;   // the OpenGL 3 backend started
    ImGuiHandle() = default;
    ImGuiHandle(const ImGuiHandle&) = delete;
    ImGuiHandle& operator=(const ImGuiHandle&) = delete;
    ~ImGuiHandle();
};

class App {
  public:
    explicit App(ViewerOptions options);
    App(const App&) = delete;
    App& operator=(const App&) = delete;

    int run();

  private:
    void open_window();
    void frame();
    void handle_input();
    void layout_panes(int framebuffer_width, int framebuffer_height);
    void render_panes();
    void present();
    void draw_labels();
    void draw_panel();  // panel.cpp
    void panel_view();
    void panel_camera();
    void panel_animation();
    void panel_shading();
    void panel_fade_calibration(ShadingSettings& settings);
    bool parameter_widget(const ParameterInfo& row, ShadingSettings& settings);
    void parameter_group(std::string_view group, ShadingSettings& settings);
    void panel_bumps();
    void panel_files();
    void panel_messages();
    void save_screenshot(const std::string& path);
    std::string next_screenshot_name() const;
    void take_screenshot();
    void apply_layout();
    void sync_from_preset();
    void set_fly_away(bool active);
    int pane_count() const;

    ViewerOptions options_;
    // Destroyed in reverse order: ImGui, the GL objects, then the context and the window.
    WindowHandle window_;
    std::unique_ptr<gl::Context> context_;
    std::unique_ptr<Session> session_;
    std::unique_ptr<Presenter> presenter_;
    std::array<Pane, kMaxPanes> panes_;
    ImGuiHandle imgui_;

    Layout layout_ = Layout::Single;
    std::array<gl::Technique, kMaxPanes> chosen_{gl::Technique::Bump, gl::Technique::Lean,
                                                 gl::Technique::Fade};
    PaneTimer::Mode timing_mode_ = PaneTimer::Mode::Gpu;
    bool software_renderer_ = false;
    bool panel_visible_ = true;
    bool continuous_ = false;
    bool fly_active_ = false;
    double fly_start_ = 0.0;
    // Moving layers: the animation's time in seconds (RenderRequest::time), advancing with the
    // clock unless paused (P), wrapped to [0, loop_seconds).
    double animation_time_ = 0.0;
    bool animation_paused_ = false;
    int scene_view_ = 0;  // index into options_.scene_views
    bool dragging_divider_ = false;
    float max_anisotropy_ = 1.0f;
    int max_samples_ = 1;

    // Panel fields being edited (applied by their Load buttons).
    std::string scene_field_;
    BumpSource bumps_field_;
    std::string preset_field_;
    std::string screenshot_field_;

    bool screenshot_requested_ = false;
    int frame_count_ = 0;
    double frame_ms_ = 0.0;  // whole frame, smoothed
    double last_frame_start_ = 0.0;
    int area_x_ = 0, area_width_ = 0, area_height_ = 0;  // the 3D area, framebuffer pixels
};

}  // namespace leanfade::viewer
