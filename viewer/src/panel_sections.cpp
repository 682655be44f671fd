// The viewer panel's sections (leanfade/viewer/panel_sections.hpp).
#include "leanfade/viewer/panel_sections.hpp"

#include <algorithm>

#include "leanfade/core/detail/parameters.hpp"

namespace leanfade::viewer {

namespace {

std::vector<PanelSection> make_panel_sections() {
    using Extras = PanelSection::Extras;
    std::vector<PanelSection> sections{
        {"Light and material", {"Light", "Material", "Fresnel"}, true, Extras::ColourNote},
        {"Specular fading", {"Fading"}, true, Extras::FadeCalibrate},
        {"Fog", {"Fog"}, false, Extras::None},
        {"Scene, bumps and textures", {"Texturing"}, true, Extras::SceneAndBumps},
    };
    // Groups of the schema that no section above names: a header each, after the shading ones.
    auto claimed = [&](std::string_view group) {
        return std::any_of(sections.begin(), sections.end(), [&](const PanelSection& s) {
            return std::find(s.groups.begin(), s.groups.end(), group) != s.groups.end();
        });
    };
    for (std::string_view group : parameter_groups())
        if (!claimed(group)) sections.push_back({std::string(group), {group}, true, Extras::None});
    return sections;
}

}  // namespace

const std::vector<PanelSection>& panel_sections() {
    static const std::vector<PanelSection> sections = make_panel_sections();
    return sections;
}

}  // namespace leanfade::viewer
