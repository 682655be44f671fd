// The viewer's window and frame loop: GLFW (OpenGL 4.5 core), Dear ImGui, input, the panes.
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <utility>
#include <vector>

#include "app.hpp"
#include "backends/imgui_impl_glfw.h"
#include "backends/imgui_impl_opengl3.h"
#include "leanfade/core/error.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::viewer {
namespace {

namespace fs = std::filesystem;

constexpr int kPanelWidth = 380;  // pixels
constexpr double kPi = 3.14159265358979323846;
// Behind the object: as in the figures of `leanfade render` (the fog colour when fog is on).
constexpr glm::vec3 kBackground{0.012f, 0.013f, 0.016f};

std::string& glfw_error() {
    static std::string message;
    return message;
}

void on_glfw_error(int code, const char* description) {
    glfw_error() = std::string(description ? description : "unknown error") + " (GLFW error " +
                   std::to_string(code) + ")";
}

bool contains_any(std::string text, std::initializer_list<const char*> words) {
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* w : words)
        if (text.find(w) != std::string::npos) return true;
    return false;
}

// The shader folder (edited live): the one asked for, ./shaders of a checkout, the installed
// tree's <program>/../share/leanfade/shaders (in the build tree, a link to the sources), or none
// (the built-in copies).
gl::ShaderSources choose_shaders(const std::string& requested) {
    if (!requested.empty()) return gl::ShaderSources::directory(requested);
    std::error_code ec;
    std::vector<fs::path> folders{fs::path("shaders")};
    const fs::path program = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) folders.push_back(program.parent_path() / ".." / "share" / "leanfade" / "shaders");
    for (const fs::path& folder : folders)
        if (fs::is_regular_file(folder / "lean_shading.glsl", ec) &&
            fs::is_regular_file(folder / "scene.frag", ec))
            return gl::ShaderSources::directory(folder.string());
    return gl::ShaderSources::embedded();
}

}  // namespace

App::App(ViewerOptions options) : options_(std::move(options)) {
    validate(options_.preset, "view");
    if (!options_.load_bumps) throw Error("view", "no bump loader was given");
    open_window();

    gl::ContextOptions context_options;
    context_options.debug = options_.debug_output;
    context_ = gl::Context::adopt_current(context_options, "GLFW window");
    software_renderer_ = contains_any(context_->renderer(), {"llvmpipe", "softpipe", "swrast"});
    max_anisotropy_ = context_->max_anisotropy();
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples_);
    GLint timer_bits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &timer_bits);
    switch (options_.timing) {
        case TimingMode::Auto:
            timing_mode_ =
                software_renderer_ || timer_bits == 0 ? PaneTimer::Mode::Cpu : PaneTimer::Mode::Gpu;
            break;
        case TimingMode::Gpu:
            timing_mode_ = PaneTimer::Mode::Gpu;
            break;
        case TimingMode::Cpu:
            timing_mode_ = PaneTimer::Mode::Cpu;
            break;
    }
    Preset preset = options_.preset;
    if (options_.auto_scale && software_renderer_)
        preset.resolution_scale = std::min(preset.resolution_scale, 0.5f);
    session_ = std::make_unique<Session>(*context_, choose_shaders(options_.shader_dir),
                                         options_.load_bumps, std::move(preset),
                                         options_.scene);
    // The CPU copy is no longer needed.
    options_.scene = {};
    presenter_ = std::make_unique<Presenter>();

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the user's folder
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    imgui_.context = true;
    imgui_.glfw = ImGui_ImplGlfw_InitForOpenGL(window_.window, true);
    imgui_.opengl = imgui_.glfw && ImGui_ImplOpenGL3_Init("#version 450 core");
    if (!imgui_.opengl) throw Error("ImGui", "the GLFW / OpenGL 3 backends did not start");

    preset_field_ = options_.preset_path;
    sync_from_preset();
    if (options_.fly_away) set_fly_away(true);
    context_->take_errors();
}

WindowHandle::~WindowHandle() {
    if (window != nullptr) glfwDestroyWindow(window);
    // No glfwTerminate(): it closes the X display, which unloads Mesa's driver with a few of its
    // allocations still live (LeakSanitizer reports them; gl::Context leaves EGL displays alone
    // for the same reason). The process ends soon after, and a later glfwInit() reuses GLFW.
}

ImGuiHandle::~ImGuiHandle() {
    if (opengl) ImGui_ImplOpenGL3_Shutdown();
    if (glfw) ImGui_ImplGlfw_Shutdown();
    if (context) ImGui::DestroyContext();
}

void App::open_window() {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit())
        throw Error("GLFW", "cannot open a window: " + glfw_error() +
                                " (no X display? headless, run it under xvfb-run)");
    window_.initialised = true;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options_.debug_output ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, 0);
    window_.window =
        glfwCreateWindow(options_.width, options_.height, "leanfade view", nullptr, nullptr);
    if (window_.window == nullptr)
        throw Error("GLFW",
                    "cannot open a window with an OpenGL 4.5 core context: " + glfw_error());
    glfwMakeContextCurrent(window_.window);
    glfwSwapInterval(options_.frames > 0 ? 0 : 1);
}

int App::pane_count() const {
    switch (layout_) {
        case Layout::Single:
            return 1;
        case Layout::Split:
        case Layout::SideBySide2:
            return 2;
        case Layout::SideBySide3:
            return 3;
    }
    return 1;
}

void App::apply_layout() {
    Preset& p = session_->preset();
    const int n = pane_count();
    p.techniques.assign(chosen_.begin(), chosen_.begin() + n);
    p.layout = layout_ == Layout::Single  ? PaneLayout::Single
               : layout_ == Layout::Split ? PaneLayout::Split
                                          : PaneLayout::SideBySide;
}

void App::sync_from_preset() {
    const Preset& p = session_->preset();
    const std::vector<gl::Technique> techniques = session_->techniques();
    const std::size_t n = techniques.size();
    layout_ = p.layout == PaneLayout::Single  ? Layout::Single
              : p.layout == PaneLayout::Split ? Layout::Split
              : n == 3                        ? Layout::SideBySide3
                                              : Layout::SideBySide2;
    // The panes shown first, then the other techniques for panes shown later.
    std::vector<gl::Technique> order = techniques;
    for (gl::Technique t : gl::all_techniques())
        if (std::find(order.begin(), order.end(), t) == order.end()) order.push_back(t);
    for (std::size_t i = 0; i < chosen_.size(); ++i) chosen_[i] = order[i];
    scene_field_ = p.scene;
    bumps_field_ = p.bumps;
    for (Pane& pane : panes_) pane.canvas.key.clear();
}

void App::set_fly_away(bool active) {
    fly_active_ = active;
    if (!active) return;
    // Start at the phase whose distance is the current one, so the camera does not jump.
    const FlyAwaySettings& f = session_->preset().fly_away;
    const double span = std::log(double(f.far_distance)) - std::log(double(f.near_distance));
    const double blend = std::clamp(
        (std::log(double(session_->camera().distance)) - std::log(double(f.near_distance))) / span,
        0.0, 1.0);
    const double phase = std::acos(1.0 - 2.0 * blend) / (2.0 * kPi);
    fly_start_ = now_seconds() - phase * double(f.period);
}

int App::run() {
    while (!glfwWindowShouldClose(window_.window)) {
        frame();
        if (options_.frames > 0 && frame_count_ >= options_.frames) break;
    }
    if (options_.frames > 0) {
        // One line for scripts: what was drawn and how long each pane took.
        int width = 0, height = 0;
        glfwGetFramebufferSize(window_.window, &width, &height);
        std::string panes;
        for (int i = 0; i < pane_count(); ++i) {
            const Pane& pane = panes_[std::size_t(i)];
            char text[96], time[32] = "no time yet";
            if (const auto ms = pane.timer.milliseconds())
                std::snprintf(time, sizeof time, "%.1f ms", *ms);
            std::snprintf(text, sizeof text, "%s%s %dx%d %s", i > 0 ? ", " : "",
                          gl::to_string(chosen_[std::size_t(i)]), pane.canvas.width(),
                          pane.canvas.height(), time);
            panes += text;
        }
        std::printf("view: %d frames, window %dx%d, %s (%s time) on %s%s%s\n", frame_count_, width,
                    height, panes.c_str(), timing_mode_ == PaneTimer::Mode::Cpu ? "CPU" : "GPU",
                    context_->renderer().c_str(), options_.screenshot.empty() ? "" : ", saved ",
                    options_.screenshot.c_str());
    }
    return 0;
}

void App::frame() {
    const bool animating = options_.loop_seconds > 0.0f && !animation_paused_;
    const bool busy = fly_active_ || continuous_ || animating || options_.frames > 0 ||
                      frame_count_ < 3 || ImGui::IsAnyMouseDown();
    if (busy)
        glfwPollEvents();
    else
        glfwWaitEventsTimeout(0.5);
    const double start = now_seconds();
    if (animating && last_frame_start_ > 0.0)
        animation_time_ = std::fmod(animation_time_ + (start - last_frame_start_),
                                    double(options_.loop_seconds));
    if (last_frame_start_ > 0.0) {
        const double ms = (start - last_frame_start_) * 1000.0;
        frame_ms_ = frame_ms_ > 0.0 ? 0.9 * frame_ms_ + 0.1 * ms : ms;
    }
    last_frame_start_ = start;

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_.window, &width, &height);

    handle_input();
    if (fly_active_)
        session_->camera().distance =
            fly_away_distance(session_->preset().fly_away, start - fly_start_);
    if (panel_visible_) draw_panel();
    layout_panes(width, height);
    if (width > 0 && height > 0) {
        render_panes();
        present();
        draw_labels();
    }
    ImGui::Render();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    // GL errors of the frame (the panes report theirs as they happen).
    for (const std::string& e : context_->take_errors()) session_->report_error("GL: " + e);
    ++frame_count_;

    if (screenshot_requested_) {
        screenshot_requested_ = false;
        take_screenshot();
    }
    if (options_.frames > 0 && frame_count_ == options_.frames && !options_.screenshot.empty())
        save_screenshot(options_.screenshot);
    glfwSwapBuffers(window_.window);
}

void App::handle_input() {
    ImGuiIO& io = ImGui::GetIO();
    OrbitCamera& camera = session_->camera();
    const float scale = io.DisplayFramebufferScale.x > 0.0f ? io.DisplayFramebufferScale.x : 1.0f;
    bool zoomed = false;  // a change of distance by hand stops the fly-away animation

    if (!io.WantCaptureMouse) {
        const float mx = io.MousePos.x * scale;
        const float divider_x =
            float(area_x_) + session_->preset().divider * float(std::max(area_width_, 1));
        const bool near_divider =
            layout_ == Layout::Split && std::abs(mx - divider_x) < 6.0f && mx >= float(area_x_);
        if (near_divider && ImGui::IsMouseClicked(0)) dragging_divider_ = true;
        if (near_divider || dragging_divider_) ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
        if (!ImGui::IsMouseDown(0)) dragging_divider_ = false;

        const ImVec2 d(io.MouseDelta.x * scale, io.MouseDelta.y * scale);
        const bool dragged = d.x != 0.0f || d.y != 0.0f;
        if (dragging_divider_) {
            session_->preset().divider =
                std::clamp((mx - float(area_x_)) / float(std::max(area_width_, 1)), 0.0f, 1.0f);
        } else if (dragged && (ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2) ||
                               (ImGui::IsMouseDown(0) && io.KeyShift))) {
            camera.pan(d.x, d.y, std::max(area_height_, 1));
        } else if (dragged && ImGui::IsMouseDown(0)) {
            camera.orbit(-0.3f * d.x, 0.3f * d.y);
        }
        if (io.MouseWheel != 0.0f) {
            camera.zoom(std::pow(0.9f, io.MouseWheel));
            zoomed = true;
        }
    }

    if (!io.WantCaptureKeyboard) {
        const bool shift = io.KeyShift;
        const float pan_step = 0.05f * float(std::max(area_height_, 1));
        auto pressed = [](int key) { return ImGui::IsKeyPressed(key, true); };
        if (pressed(GLFW_KEY_LEFT)) {
            shift ? camera.pan(-pan_step, 0.0f, area_height_) : camera.orbit(5.0f, 0.0f);
        }
        if (pressed(GLFW_KEY_RIGHT)) {
            shift ? camera.pan(pan_step, 0.0f, area_height_) : camera.orbit(-5.0f, 0.0f);
        }
        if (pressed(GLFW_KEY_UP)) {
            shift ? camera.pan(0.0f, -pan_step, area_height_) : camera.orbit(0.0f, -5.0f);
        }
        if (pressed(GLFW_KEY_DOWN)) {
            shift ? camera.pan(0.0f, pan_step, area_height_) : camera.orbit(0.0f, 5.0f);
        }
        if (pressed(GLFW_KEY_EQUAL) || pressed(GLFW_KEY_KP_ADD) || pressed(GLFW_KEY_PAGE_UP)) {
            camera.zoom(1.0f / 1.1f);
            zoomed = true;
        }
        if (pressed(GLFW_KEY_MINUS) || pressed(GLFW_KEY_KP_SUBTRACT) ||
            pressed(GLFW_KEY_PAGE_DOWN)) {
            camera.zoom(1.1f);
            zoomed = true;
        }
        if (ImGui::IsKeyPressed(GLFW_KEY_HOME, false)) {
            camera = OrbitCamera(CameraSettings{});
            zoomed = true;
        }
        if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false)) set_fly_away(!fly_active_);
        if (ImGui::IsKeyPressed(GLFW_KEY_P, false)) animation_paused_ = !animation_paused_;
        if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) session_->reload_shaders();
        if (ImGui::IsKeyPressed(GLFW_KEY_F12, false)) screenshot_requested_ = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_F1, false)) panel_visible_ = !panel_visible_;
        if (ImGui::IsKeyPressed(GLFW_KEY_T, false)) {
            // Cycles the first pane's technique.
            const std::vector<gl::Technique>& all = gl::all_techniques();
            auto it = std::find(all.begin(), all.end(), chosen_[0]);
            gl::Technique next = it == all.end() || it + 1 == all.end() ? all.front() : *(it + 1);
            for (int i = 1; i < pane_count(); ++i)
                if (chosen_[std::size_t(i)] == next) chosen_[std::size_t(i)] = chosen_[0];
            chosen_[0] = next;
            apply_layout();
        }
        if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false))
            glfwSetWindowShouldClose(window_.window, 1);
    }
    if (zoomed) fly_active_ = false;
}

void App::layout_panes(int width, int height) {
    area_x_ = panel_visible_ ? std::min(kPanelWidth, width / 2) : 0;
    area_width_ = std::max(0, width - area_x_);
    area_height_ = std::max(0, height);
    const int n = pane_count();
    const int divider_x =
        area_x_ + int(std::lround(session_->preset().divider * float(area_width_)));
    for (int i = 0; i < n; ++i) {
        Pane& pane = panes_[std::size_t(i)];
        pane.y = 0;
        pane.height = area_height_;
        if (layout_ == Layout::Single || layout_ == Layout::Split) {
            pane.x = area_x_;
            pane.width = area_width_;
        } else {
            pane.x = area_x_ + i * area_width_ / n;
            pane.width = area_x_ + (i + 1) * area_width_ / n - pane.x;
        }
        pane.visible_x = pane.x;
        pane.visible_width = pane.width;
        if (layout_ == Layout::Split) {
            pane.visible_x = i == 0 ? area_x_ : divider_x;
            pane.visible_width = i == 0 ? divider_x - area_x_ : area_x_ + area_width_ - divider_x;
        }
    }
}

void App::render_panes() {
    const Preset snapshot = session_->snapshot();
    const std::string base = preset_to_json(snapshot) + "#" +
                             std::to_string(session_->generation()) + "#t" +
                             std::to_string(animation_time_) + "#v" + std::to_string(scene_view_);
    const int n = pane_count();
    const glm::vec3 background =
        snapshot.shading.fog == FogMode::None ? kBackground : snapshot.shading.fog_color;
    for (int i = 0; i < n; ++i) {
        Pane& pane = panes_[std::size_t(i)];
        pane.timer.poll();
        if (pane.width < 1 || pane.height < 1) continue;
        const int w = std::max(16, int(std::lround(float(pane.width) * snapshot.resolution_scale)));
        const int h =
            std::max(16, int(std::lround(float(pane.height) * snapshot.resolution_scale)));
        pane.canvas.ensure(w, h);
        const gl::Technique technique = chosen_[std::size_t(i)];
        const std::string key = base + "#" + gl::to_string(technique) + "#" + std::to_string(w) +
                                "x" + std::to_string(h);
        // --frames runs redraw every frame, so that their frame times mean something.
        if (key == pane.canvas.key && !continuous_ && options_.frames == 0) continue;
        pane.canvas.key = key;
        const std::string timed = std::string(gl::to_string(technique)) + "#" + std::to_string(w) +
                                  "x" + std::to_string(h) + "#" +
                                  std::to_string(session_->generation());
        if (timed != pane.timed) {
            pane.timer.reset();
            pane.timed = timed;
        }
        gl::RenderRequest request;
        request.technique = technique;
        request.width = w;
        request.height = h;
        request.settings = snapshot.shading;
        request.reference_samples = snapshot.reference_samples;
        request.background = background;
        request.time = float(animation_time_);
        try {
            request.view = options_.scene_views.empty()
                               ? session_->camera().view()
                               : options_.scene_views[std::size_t(scene_view_)].second;
            pane.timer.begin(timing_mode_);
            session_->renderer().render_to(request, pane.canvas.framebuffer(), 0, 0);
            pane.timer.end();
            pane.error.clear();
        } catch (const Error& e) {
            pane.timer.end();
            context_->take_errors();
            if (pane.error != e.what()) {
                pane.error = e.what();
                session_->report_error(std::string(gl::to_string(technique)) + ": " + e.what());
            }
        }
    }
}

void App::present() {
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_.window, &width, &height);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0.06f, 0.06f, 0.07f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    for (int i = 0; i < pane_count(); ++i) {
        const Pane& pane = panes_[std::size_t(i)];
        presenter_->draw(pane.canvas, pane.x, pane.y, pane.width, pane.height, pane.visible_x,
                         pane.visible_width);
    }
}

void App::draw_labels() {
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const ImGuiIO& io = ImGui::GetIO();
    const float scale = io.DisplayFramebufferScale.x > 0.0f ? io.DisplayFramebufferScale.x : 1.0f;
    const bool cpu = timing_mode_ == PaneTimer::Mode::Cpu;
    for (int i = 0; i < pane_count(); ++i) {
        const Pane& pane = panes_[std::size_t(i)];
        const gl::Technique technique = chosen_[std::size_t(i)];
        std::string label(info(technique).label);
        if (info(technique).supersampled) {
            const int k = session_->preset().reference_samples;
            char samples[32];
            std::snprintf(samples, sizeof samples, " %dx%d", k, k);
            label += samples;
        }
        char timing[64] = "";
        if (const auto ms = pane.timer.milliseconds())
            std::snprintf(timing, sizeof timing, "   %.1f ms %s", *ms, cpu ? "CPU" : "GPU");
        label += timing;
        float x = float(pane.visible_x) / scale + 8.0f;
        if (layout_ == Layout::Split && i == 1)
            x = float(pane.visible_x + pane.visible_width) / scale - 8.0f -
                ImGui::CalcTextSize(label.c_str()).x;
        const ImVec2 position(x, 8.0f);
        const ImVec2 size = ImGui::CalcTextSize(label.c_str());
        draw->AddRectFilled(ImVec2(position.x - 4, position.y - 2),
                            ImVec2(position.x + size.x + 4, position.y + size.y + 2),
                            IM_COL32(0, 0, 0, 160), 3.0f);
        draw->AddText(position, IM_COL32(235, 235, 235, 255), label.c_str());
        if (!pane.error.empty()) {
            const float wrap = std::max(120.0f, float(pane.visible_width) / scale - 24.0f);
            const ImVec2 at(float(pane.visible_x) / scale + 8.0f, 34.0f);
            const ImVec2 box = ImGui::CalcTextSize(pane.error.c_str(), nullptr, false, wrap);
            draw->AddRectFilled(ImVec2(at.x - 4, at.y - 2),
                                ImVec2(at.x + box.x + 4, at.y + box.y + 2), IM_COL32(60, 0, 0, 200),
                                3.0f);
            draw->AddText(nullptr, 0.0f, at, IM_COL32(255, 120, 110, 255), pane.error.c_str(),
                          nullptr, wrap);
        }
    }
    if (layout_ == Layout::Split && area_width_ > 0) {
        const float x = (float(area_x_) + session_->preset().divider * float(area_width_)) / scale;
        const float h = float(area_height_) / scale;
        draw->AddLine(ImVec2(x, 0.0f), ImVec2(x, h), IM_COL32(255, 255, 255, 200), 2.0f);
        draw->AddRectFilled(ImVec2(x - 4, h * 0.5f - 18), ImVec2(x + 4, h * 0.5f + 18),
                            IM_COL32(255, 255, 255, 220), 3.0f);
    }
    // Distance readout at the bottom of the 3D area.
    char text[96];
    std::snprintf(text, sizeof text, "distance %.2f bounding radii%s",
                  double(session_->camera().distance), fly_active_ ? "   (flying away)" : "");
    const ImVec2 at(float(area_x_) / scale + 8.0f,
                    float(area_height_) / scale - ImGui::GetTextLineHeight() - 8.0f);
    const ImVec2 size = ImGui::CalcTextSize(text);
    draw->AddRectFilled(ImVec2(at.x - 4, at.y - 2), ImVec2(at.x + size.x + 4, at.y + size.y + 2),
                        IM_COL32(0, 0, 0, 160), 3.0f);
    draw->AddText(at, IM_COL32(235, 235, 235, 255), text);
}

std::string App::next_screenshot_name() const {
    for (int i = 1; i < 10000; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "leanfade-view-%03d.png", i);
        std::error_code ec;
        if (!fs::exists(name, ec)) return name;
    }
    return "leanfade-view.png";
}

void App::take_screenshot() {
    const std::string path = screenshot_field_.empty() ? next_screenshot_name() : screenshot_field_;
    try {
        save_screenshot(path);
        session_->report_status("saved screenshot " + path);
    } catch (const Error& e) {
        session_->report_error(e.what());
    }
}

void App::save_screenshot(const std::string& path) {
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_.window, &width, &height);
    if (width < 1 || height < 1) throw Error(path, "the window has no pixels to save");
    std::vector<unsigned char> bytes(std::size_t(width) * std::size_t(height) * 3);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, bytes.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    Image image(width, height, 3);
    for (int y = 0; y < height; ++y) {
        const unsigned char* src =
            bytes.data() + std::size_t(height - 1 - y) * std::size_t(width) * 3;
        float* dst = image.row(y);
        for (int i = 0; i < width * 3; ++i) dst[i] = float(src[i]) / 255.0f;
    }
    io::write_png(path, image, 8);
}

int run_viewer(ViewerOptions options) {
    App app(std::move(options));
    return app.run();
}

}  // namespace leanfade::viewer
