// The viewer panel shows every parameter group of the schema exactly once, and names no group
// the schema lacks (leanfade/viewer/panel_sections.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>

#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/viewer/panel_sections.hpp"

namespace leanfade::viewer {
namespace {

TEST(PanelSections, EverySchemaGroupIsShownExactlyOnce) {
    std::map<std::string_view, int> shown;
    for (const PanelSection& section : panel_sections())
        for (std::string_view group : section.groups) ++shown[group];
    const std::vector<std::string_view> groups = parameter_groups();
    ASSERT_FALSE(groups.empty());
    for (std::string_view group : groups) EXPECT_EQ(shown[group], 1) << group;
    for (const auto& [group, count] : shown)
        EXPECT_NE(std::find(groups.begin(), groups.end(), group), groups.end())
            << "the panel names a group the schema does not have: " << group;
}

TEST(PanelSections, EveryParameterHasAWidgetSection) {
    for (const ParameterInfo& row : shading_parameters()) {
        int sections = 0;
        for (const PanelSection& section : panel_sections())
            sections += int(std::count(section.groups.begin(), section.groups.end(), row.group));
        EXPECT_EQ(sections, 1) << row.key << " (group " << row.group << ")";
    }
}

TEST(PanelSections, TheBumpSectionIsUnique) {
    int bumps = 0;
    for (const PanelSection& section : panel_sections())
        bumps += section.extras == PanelSection::Extras::SceneAndBumps;
    EXPECT_EQ(bumps, 1);
}

TEST(ParameterGroups, EachGroupOnceInTableOrder) {
    const std::vector<std::string_view> groups = parameter_groups();
    for (std::size_t i = 0; i < groups.size(); ++i)
        for (std::size_t j = i + 1; j < groups.size(); ++j) EXPECT_NE(groups[i], groups[j]);
    // The first row's group comes first.
    EXPECT_EQ(groups.front(), shading_parameters().front().group);
}

}  // namespace
}  // namespace leanfade::viewer
