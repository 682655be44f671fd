// The viewer's Dear ImGui panel: every parameter of the view, loading, presets, messages.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app.hpp"
#include "imgui_stdlib.h"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/eval/runner.hpp"
#include "leanfade/scene/detail/scene.hpp"
#include "leanfade/viewer/panel_sections.hpp"
#include "leanfade/core/technique.hpp"

namespace leanfade::viewer {
namespace {

constexpr ImGuiSliderFlags kLog = ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp;
constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;
constexpr ImGuiColorEditFlags kColour = ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR;

const ImVec4 kErrorColour(1.0f, 0.45f, 0.42f, 1.0f);
const ImVec4 kStatusColour(0.55f, 0.85f, 0.55f, 1.0f);
const ImVec4 kNoteColour(0.65f, 0.65f, 0.7f, 1.0f);

void note(const char* text) {
    ImGui::PushStyleColor(ImGuiCol_Text, kNoteColour);
    ImGui::TextWrapped("%s", text);
    ImGui::PopStyleColor();
}

// A combo over a list of names; returns true when the selection changed.
bool combo(const char* label, int& index, const std::vector<std::string>& names) {
    bool changed = false;
    const char* preview =
        index >= 0 && index < int(names.size()) ? names[std::size_t(index)].c_str() : "";
    if (ImGui::BeginCombo(label, preview)) {
        for (int i = 0; i < int(names.size()); ++i) {
            const bool selected = i == index;
            if (ImGui::Selectable(names[std::size_t(i)].c_str(), selected) && i != index) {
                index = i;
                changed = true;
            }
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndCombo();
    }
    return changed;
}

int index_of(const std::vector<std::string>& names, const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : int(it - names.begin());
}

}  // namespace

void App::draw_panel() {
    const ImGuiIO& io = ImGui::GetIO();
    const float scale = io.DisplayFramebufferScale.x > 0.0f ? io.DisplayFramebufferScale.x : 1.0f;
    ImGui::SetNextWindowPos(ImVec2(0.0f, 0.0f));
    ImGui::SetNextWindowSize(ImVec2(float(area_x_ > 0 ? area_x_ : 380) / scale, io.DisplaySize.y));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                   ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;
    if (ImGui::Begin("leanfade view", nullptr, flags)) {
        ImGui::PushItemWidth(-150.0f);
        panel_messages();
        panel_view();
        panel_animation();
        panel_camera();
        panel_shading();
        panel_bumps();
        panel_files();
        if (ImGui::CollapsingHeader("Mouse and keys")) {
            ImGui::BulletText("left drag: orbit; right/middle or shift+left drag: pan");
            ImGui::BulletText("wheel, +/- or PgUp/PgDn: zoom; arrows: orbit");
            ImGui::BulletText("shift+arrows: pan; Home: reset the camera");
            ImGui::BulletText("Space: fly away; T: next technique");
            ImGui::BulletText("R: reload shaders; F12: screenshot");
            ImGui::BulletText("F1: hide/show this panel; Esc: quit");
            ImGui::BulletText("split view: drag the divider");
        }
        ImGui::PopItemWidth();
    }
    ImGui::End();
}

void App::panel_messages() {
    ImGui::TextWrapped("%s", context_->renderer().c_str());
    ImGui::Text("frame %.1f ms (%.0f fps)", frame_ms_, frame_ms_ > 0.0 ? 1000.0 / frame_ms_ : 0.0);
    if (!session_->status().empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kStatusColour);
        ImGui::TextWrapped("%s", session_->status().c_str());
        ImGui::PopStyleColor();
    }
    if (!session_->errors().empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kErrorColour);
        for (const std::string& e : session_->errors()) ImGui::TextWrapped("%s", e.c_str());
        ImGui::PopStyleColor();
        if (ImGui::SmallButton("clear messages")) session_->clear_errors();
    }
    ImGui::Separator();
}

void App::panel_view() {
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    Preset& p = session_->preset();
    static const std::vector<std::string> layouts{"single", "split (drag the divider)",
                                                  "side by side (2)", "side by side (3)"};
    int layout = int(layout_);
    if (combo("layout", layout, layouts)) {
        layout_ = Layout(layout);
        // Distinct techniques in the visible panes.
        for (int i = 1; i < pane_count(); ++i)
            for (int j = 0; j < i; ++j)
                if (chosen_[std::size_t(i)] == chosen_[std::size_t(j)]) {
                    for (gl::Technique t : gl::all_techniques())
                        if (std::find(chosen_.begin(), chosen_.begin() + i, t) ==
                            chosen_.begin() + i) {
                            chosen_[std::size_t(i)] = t;
                            break;
                        }
                }
        apply_layout();
    }
    std::vector<std::string> names;
    const std::vector<gl::Technique>& all = gl::all_techniques();
    for (gl::Technique t : all) names.push_back(std::string(info(t).label));
    static const char* const two[] = {"left technique", "right technique"};
    static const char* const three[] = {"left technique", "middle technique", "right technique"};
    for (int i = 0; i < pane_count(); ++i) {
        const char* label = pane_count() == 1 ? "technique" : pane_count() == 2 ? two[i] : three[i];
        int index = index_of(names, std::string(info(chosen_[std::size_t(i)]).label));
        if (combo(label, index, names)) {
            const gl::Technique picked = all[std::size_t(index)];
            // Picking one shown in another pane swaps the two.
            for (int j = 0; j < pane_count(); ++j)
                if (j != i && chosen_[std::size_t(j)] == picked)
                    chosen_[std::size_t(j)] = chosen_[std::size_t(i)];
            chosen_[std::size_t(i)] = picked;
            apply_layout();
        }
    }
    if (layout_ == Layout::Split)
        ImGui::SliderFloat("divider", &p.divider, 0.0f, 1.0f, "%.2f", kClamp);
    ImGui::SliderInt("reference k", &p.reference_samples, 1, kMaxReferenceSamples, "%d", kClamp);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Reference technique: k x k samples per pixel at LOD 0 (slow)");
    ImGui::SliderFloat("resolution", &p.resolution_scale, 0.1f, 1.0f, "%.2f", kClamp);
    if (pane_count() > 0 && panes_[0].canvas.width() > 0)
        ImGui::Text("internal %dx%d per pane (%.0f%% of the window)", panes_[0].canvas.width(),
                    panes_[0].canvas.height(), double(p.resolution_scale) * 100.0);
    int timing = timing_mode_ == PaneTimer::Mode::Gpu ? 0 : 1;
    ImGui::Text("frame time per pane:");
    bool changed = ImGui::RadioButton("GPU queries", &timing, 0);
    ImGui::SameLine();
    changed |= ImGui::RadioButton("CPU + glFinish", &timing, 1);
    if (changed) {
        timing_mode_ = timing == 0 ? PaneTimer::Mode::Gpu : PaneTimer::Mode::Cpu;
        for (Pane& pane : panes_) pane.timer.reset();
    }
    if (software_renderer_)
        note(timing_mode_ == PaneTimer::Mode::Cpu
                 ? "Software renderer: CPU time is shown (its timer queries under-report)."
                 : "Software renderer: timer queries under-report here; prefer CPU time.");
    ImGui::Checkbox("redraw every frame", &continuous_);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Keeps the frame times current");
}

// Moving bump layers: the time slider and pause; a scene's own cameras (the ocean's views).
void App::panel_animation() {
    if (options_.loop_seconds <= 0.0f && options_.scene_views.empty()) return;
    if (!ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (options_.loop_seconds > 0.0f) {
        float t = float(animation_time_);
        if (ImGui::SliderFloat("time (s)", &t, 0.0f, options_.loop_seconds, "%.2f", kClamp))
            animation_time_ = double(t);
        ImGui::Checkbox("pause (P)", &animation_paused_);
    }
    for (std::size_t i = 0; i < options_.scene_views.size(); ++i) {
        if (i > 0) ImGui::SameLine();
        ImGui::RadioButton(options_.scene_views[i].first.c_str(), &scene_view_, int(i));
    }
}

void App::panel_camera() {
    if (!options_.scene_views.empty()) return;  // the scene's cameras (panel_animation)
    if (!ImGui::CollapsingHeader("Camera", ImGuiTreeNodeFlags_DefaultOpen)) return;
    OrbitCamera& c = session_->camera();
    if (ImGui::SliderFloat("distance (radii)", &c.distance, kMinOrbitDistance, 1000.0f, "%.2f",
                           kLog))
        fly_active_ = false;
    ImGui::SliderFloat("yaw", &c.yaw_degrees, -180.0f, 180.0f, "%.1f deg", kClamp);
    ImGui::SliderFloat("pitch", &c.pitch_degrees, -kMaxPitchDegrees, kMaxPitchDegrees, "%.1f deg",
                       kClamp);
    ImGui::SliderFloat("field of view", &c.fov_y_degrees, 5.0f, 120.0f, "%.1f deg", kClamp);
    ImGui::DragFloat3("target (pan)", &c.target.x, 0.01f, -50.0f, 50.0f, "%.2f");
    if (ImGui::Button("reset camera (Home)")) {
        c = OrbitCamera(CameraSettings{});
        fly_active_ = false;
    }
    ImGui::SameLine();
    if (ImGui::Button("reset pan")) c.target = glm::vec3(0.0f);

    bool fly = fly_active_;
    if (ImGui::Checkbox("fly away (Space)", &fly)) set_fly_away(fly);
    FlyAwaySettings& f = session_->preset().fly_away;
    ImGui::SliderFloat("near", &f.near_distance, kMinOrbitDistance, 100.0f, "%.2f", kLog);
    ImGui::SliderFloat("far", &f.far_distance, 2.0f, 1000.0f, "%.1f", kLog);
    ImGui::SliderFloat("period (s)", &f.period, 0.5f, 60.0f, "%.1f", kLog);
    f.far_distance = std::max(f.far_distance, f.near_distance * 1.01f);
}

// The widget of one row of the parameter schema (leanfade/core/detail/parameters.hpp): a slider over
// its widget range (logarithmic where it spans decades), a colour editor, a direction or a list.
// Returns true when the value changed.
bool App::parameter_widget(const ParameterInfo& row, ShadingSettings& s) {
    const std::string label(row.label);
    const ImGuiSliderFlags flags = row.logarithmic ? kLog : kClamp;
    bool changed = false;
    switch (row.kind) {
        case ParameterKind::Scalar:
            changed = ImGui::SliderFloat(label.c_str(), &(s.*row.scalar), row.ui_min, row.ui_max,
                                         row.logarithmic ? "%.4g" : "%.3f", flags);
            break;
        case ParameterKind::Integer:
            if (row.key == "msaa") {  // powers of two the driver allows
                std::vector<std::string> names;
                for (int m = 1; m <= int(row.ui_max); m *= 2)
                    if (m == 1 || m <= max_samples_) names.push_back(std::to_string(m));
                int index = index_of(names, std::to_string(s.*row.integer));
                changed = combo(label.c_str(), index, names);
                if (changed) s.*row.integer = std::stoi(names[std::size_t(index)]);
            } else {
                const int limit = row.key == "anisotropy"
                                      ? std::max(1, std::min(int(row.ui_max), int(max_anisotropy_)))
                                      : int(row.ui_max);
                ImGui::BeginDisabled(limit <= int(row.ui_min));
                changed = ImGui::SliderInt(label.c_str(), &(s.*row.integer), int(row.ui_min), limit,
                                           "%d", kClamp);
                ImGui::EndDisabled();
            }
            break;
        case ParameterKind::Colour:
            changed = ImGui::ColorEdit3(label.c_str(), &(s.*row.vector).x, kColour);
            break;
        case ParameterKind::Direction: {
            glm::vec3 v = s.*row.vector;
            if (ImGui::SliderFloat3(label.c_str(), &v.x, row.ui_min, row.ui_max, "%.2f", kClamp) &&
                v != glm::vec3(0.0f)) {
                s.*row.vector = v;
                changed = true;
            }
            break;
        }
        case ParameterKind::Choice: {
            std::vector<std::string> names(row.choices.begin(), row.choices.end());
            int index = row.get_choice(s);
            changed = combo(label.c_str(), index, names);
            if (changed) row.set_choice(s, index);
            break;
        }
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(row.help).c_str());
    return changed;
}

void App::parameter_group(std::string_view group, ShadingSettings& s) {
    for (const ParameterInfo& row : shading_parameters())
        if (row.group == group) parameter_widget(row, s);
}

void App::panel_shading() {
    ShadingSettings& s = session_->preset().shading;
    for (const PanelSection& section : panel_sections()) {
        if (section.extras == PanelSection::Extras::SceneAndBumps) continue;  // panel_bumps()
        const ImGuiTreeNodeFlags open =
            section.open_by_default ? ImGuiTreeNodeFlags_DefaultOpen : ImGuiTreeNodeFlags_None;
        if (!ImGui::CollapsingHeader(section.header.c_str(), open)) continue;
        for (std::string_view group : section.groups) parameter_group(group, s);
        if (section.extras == PanelSection::Extras::ColourNote) note("Colours are linear RGB.");
        if (section.extras == PanelSection::Extras::FadeCalibrate) panel_fade_calibration(s);
    }
}

void App::panel_fade_calibration(ShadingSettings& s) {
    note("sf = clamp(1 + (d Fade)^p, 1, Pmax); Fade = 0 is plain LEAN.");
    // `leanfade calibrate` for this view: Fade such that fade's specular energy relative to
    // LEAN follows exp(-sigma d) (or the fog) over 2 to 64 radii along this direction.
    static float sigma = 0.05f;
    ImGui::SliderFloat("target sigma", &sigma, 0.001f, 1.0f, "%.4f", kLog);
    const bool to_exp = ImGui::Button("fit Fade to exp(-sigma d)");
    ImGui::SameLine();
    const bool to_fog = ImGui::Button("fit Fade to the fog");
    if (!to_exp && !to_fog) return;
    try {
        eval::FadeCalibrationRequest request;
        request.cameras.view_direction = session_->camera().direction();
        request.cameras.fov_y_degrees = session_->camera().fov_y_degrees;
        request.settings = s;
        request.target.kind =
            to_fog ? eval::FadeTarget::Kind::Fog : eval::FadeTarget::Kind::Exponential;
        request.target.sigma = sigma;
        const eval::FadeCalibration c = eval::calibrate_fade(session_->renderer(), request);
        s.fade = c.fit.fade;
        char text[128];
        std::snprintf(text, sizeof text, "Fade %.4g fits %s (RMS residual %.3f)",
                      double(c.fit.fade), eval::to_string(request.target).c_str(),
                      c.achieved_residual);
        session_->report_status(text);
    } catch (const Error& e) {
        session_->report_error(e.what());
    }
}

void App::panel_bumps() {
    const std::vector<PanelSection>& sections = panel_sections();
    const auto section = std::find_if(sections.begin(), sections.end(), [](const PanelSection& s) {
        return s.extras == PanelSection::Extras::SceneAndBumps;
    });
    if (section == sections.end() ||
        !ImGui::CollapsingHeader(section->header.c_str(), ImGuiTreeNodeFlags_DefaultOpen))
        return;
    Preset& p = session_->preset();
    ShadingSettings& s = p.shading;

    ImGui::TextWrapped("%s", session_->mesh_description().c_str());
    const std::vector<std::string> scenes = scene::builtin_scene_names();
    int scene = index_of(scenes, p.scene);
    if (combo("built-in scene", scene, scenes)) session_->load_scene(scenes[std::size_t(scene)]);
    ImGui::InputText("OBJ file", &scene_field_);
    ImGui::SameLine();
    if (ImGui::Button("load##obj")) session_->load_scene(scene_field_);

    ImGui::Separator();
    ImGui::TextWrapped("bumps: %s (%s)", p.bumps.source.c_str(),
                       session_->map_description().c_str());
    const std::vector<std::string>& sets = builtin_bump_names();
    int set = index_of(sets, p.bumps.source);
    if (combo("built-in bumps", set, sets)) {
        BumpSource source = p.bumps;
        source.source = sets[std::size_t(set)];
        if (session_->load_bumps(source)) bumps_field_ = source;
    }
    ImGui::InputText("image / .ktx2", &bumps_field_.source);
    ImGui::SameLine();
    if (ImGui::Button("load##bumps")) session_->load_bumps(bumps_field_);
    int from = int(bumps_field_.from);  // BakeSource: auto, height, normal
    if (ImGui::RadioButton("auto", &from, 0)) bumps_field_.from = BakeSource::Auto;
    ImGui::SameLine();
    if (ImGui::RadioButton("height map", &from, 1)) bumps_field_.from = BakeSource::Height;
    ImGui::SameLine();
    if (ImGui::RadioButton("normal map", &from, 2)) bumps_field_.from = BakeSource::Normal;
    ImGui::SameLine();
    ImGui::Checkbox("DirectX", &bumps_field_.directx);
    const std::vector<std::string>& bits = bake_storage_names();
    int bit = index_of(bits, to_string(bumps_field_.bits));
    if (combo("storage bits", bit, bits))
        bumps_field_.bits = parse_storage_policy(bits[std::size_t(bit)]);
    int seed = int(bumps_field_.seed);
    if (ImGui::InputInt("seed", &seed)) bumps_field_.seed = std::uint32_t(std::max(0, seed));
    static const std::vector<std::string> sizes{"64", "128", "256", "512", "1024", "2048"};
    int size = index_of(sizes, std::to_string(bumps_field_.texture_size));
    if (combo("texture size", size, sizes))
        bumps_field_.texture_size = std::stoi(sizes[std::size_t(size)]);
    if (ImGui::Button("bake / load with these settings")) session_->load_bumps(bumps_field_);

    for (const ParameterInfo& row : shading_parameters()) {
        if (std::find(section->groups.begin(), section->groups.end(), row.group) ==
            section->groups.end())
            continue;
        parameter_widget(row, s);
        // A new strength re-bakes the height map, once the slider is released.
        if (row.scalar == &ShadingSettings::bump_strength && ImGui::IsItemDeactivatedAfterEdit())
            session_->rebake_bumps();
    }
}

void App::panel_files() {
    if (!ImGui::CollapsingHeader("Presets, screenshots, shaders", ImGuiTreeNodeFlags_DefaultOpen))
        return;
    ImGui::InputText("preset", &preset_field_);
    if (ImGui::Button("save preset")) session_->save_preset(preset_field_);
    ImGui::SameLine();
    if (ImGui::Button("load preset") && session_->load_preset(preset_field_)) sync_from_preset();

    ImGui::InputTextWithHint("screenshot", "leanfade-view-NNN.png", &screenshot_field_);
    if (ImGui::Button("save screenshot (F12)")) screenshot_requested_ = true;

    ImGui::TextWrapped("shaders: %s", session_->shader_origin().c_str());
    ImGui::BeginDisabled(!session_->shaders_reloadable());
    if (ImGui::Button("reload shaders (R)")) session_->reload_shaders();
    ImGui::EndDisabled();
    if (!session_->shaders_reloadable())
        note("Built-in shaders: run from a checkout or pass --shader-dir to edit them live.");
}

}  // namespace leanfade::viewer
