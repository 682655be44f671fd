#pragma once
// The viewer panel's collapsing headers and the shading-parameter groups each one shows, derived
// from the parameter schema (leanfade/core/detail/parameters.hpp): a group of the schema that no named
// section claims gets a header of its own, so every parameter has a widget.
#include <string>
#include <string_view>
#include <vector>

namespace leanfade::viewer {

struct PanelSection {
    // What the panel draws around the groups' widgets.
    enum class Extras {
        None,
        ColourNote,     // "Colours are linear RGB."
        FadeCalibrate,  // the fading formula and the buttons that fit Fade (leanfade calibrate)
        SceneAndBumps,  // the scene and bump-map choosers before the widgets
    };
    std::string header;
    std::vector<std::string_view> groups;  // parameter groups, widgets in schema order
    bool open_by_default = true;
    Extras extras = Extras::None;
};

// The sections in panel order, derived once from the schema. Every group of parameter_groups() is
// in exactly one of them.
const std::vector<PanelSection>& panel_sections();

}  // namespace leanfade::viewer
