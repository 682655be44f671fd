// The shading parameter schema (leanfade/core/detail/parameters.hpp): every row reaches its field,
// validates its range by its key, round-trips through text and presets.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/parameters.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/core/settings.hpp"

namespace leanfade::test {
namespace {

int accessors(const ParameterInfo& row) {
    return (row.scalar != nullptr) + (row.integer != nullptr) + (row.vector != nullptr) +
           (row.get_choice != nullptr);
}

TEST(Parameters, EveryRowHasOneAccessorOfItsKindAndAUniqueKey) {
    std::set<std::string_view> keys;
    for (const ParameterInfo& row : shading_parameters()) {
        EXPECT_TRUE(keys.insert(row.key).second) << row.key;
        EXPECT_EQ(accessors(row), 1) << row.key;
        EXPECT_FALSE(row.help.empty()) << row.key;
        EXPECT_FALSE(row.label.empty()) << row.key;
        EXPECT_EQ(find_shading_parameter(row.key), &row);
        switch (row.kind) {
            case ParameterKind::Scalar:
                EXPECT_NE(row.scalar, nullptr) << row.key;
                break;
            case ParameterKind::Integer:
                EXPECT_NE(row.integer, nullptr) << row.key;
                break;
            case ParameterKind::Colour:
            case ParameterKind::Direction:
                EXPECT_NE(row.vector, nullptr) << row.key;
                break;
            case ParameterKind::Choice:
                EXPECT_TRUE(row.get_choice && row.set_choice && !row.choices.empty()) << row.key;
                break;
        }
        // The widget range lies within the valid range.
        if (row.kind == ParameterKind::Scalar || row.kind == ParameterKind::Integer) {
            EXPECT_LT(row.ui_min, row.ui_max) << row.key;
            EXPECT_GE(row.ui_min, row.min) << row.key;
            EXPECT_LE(row.ui_max, row.max) << row.key;
        }
    }
    EXPECT_EQ(find_shading_parameter("nonsense"), nullptr);
}

TEST(Parameters, DefaultsAreValidAndRoundTripThroughText) {
    const ShadingSettings defaults;
    EXPECT_NO_THROW(validate(defaults));
    for (const ParameterInfo& row : shading_parameters()) {
        ShadingSettings s;
        EXPECT_NO_THROW(validate_parameter(row, s)) << row.key;
        const std::string text = format_parameter(row, defaults);
        // Parse into settings that differ, then format again: the same text.
        ShadingSettings other;
        parse_parameter(row, text, other);
        EXPECT_EQ(format_parameter(row, other), text) << row.key;
    }
}

// A value outside each row's range is refused, naming the row's key.
TEST(Parameters, OutOfRangeValuesNameTheirKey) {
    for (const ParameterInfo& row : shading_parameters()) {
        ShadingSettings s;
        bool has_bad = true;
        switch (row.kind) {
            case ParameterKind::Scalar:
                s.*row.scalar =
                    std::isfinite(row.min) ? row.min - 1.0f - std::abs(row.min) : std::nanf("");
                break;
            case ParameterKind::Integer:
                s.*row.integer = int(row.max) + 1;
                break;
            case ParameterKind::Colour:
                s.*row.vector = glm::vec3(0.5f, -1.0f, 0.5f);
                break;
            case ParameterKind::Direction:
                s.*row.vector = glm::vec3(0.0f);
                break;
            case ParameterKind::Choice:
                has_bad = false;  // an enum holds only its choices
                EXPECT_THROW(parse_parameter(row, "no-such-choice", s), Error) << row.key;
                break;
        }
        if (!has_bad) continue;
        try {
            validate(s);
            ADD_FAILURE() << row.key << " accepted an out-of-range value";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), row.key) << e.what();
        }
    }
}

TEST(Parameters, TextForms) {
    ShadingSettings s;
    const ParameterInfo& kd = *find_shading_parameter("kd");
    parse_parameter(kd, "0.25", s);
    EXPECT_EQ(s.kd, glm::vec3(0.25f));
    parse_parameter(kd, "0.1,0.2,0.3", s);
    EXPECT_EQ(s.kd, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_THROW(parse_parameter(kd, "red", s), Error);
    const ParameterInfo& light = *find_shading_parameter("light_direction");
    EXPECT_THROW(parse_parameter(light, "1", s), Error);  // a direction has three components
    const ParameterInfo& fog = *find_shading_parameter("fog");
    parse_parameter(fog, "exp2", s);
    EXPECT_EQ(s.fog, FogMode::Exp2);
    EXPECT_EQ(format_parameter(fog, s), "exp2");
    EXPECT_EQ(std::string(to_string(FogMode::Linear)), "linear");
    EXPECT_EQ(std::string(to_string(FadeDistance::Eye)), "eye");
    const ParameterInfo& shininess = *find_shading_parameter("shininess");
    EXPECT_THROW(parse_parameter(shininess, "shiny", s), Error);
    parse_parameter(shininess, "300", s);
    EXPECT_EQ(s.shininess, 300.0f);
}

// Every row is a key of a preset's "shading" object, read back to the same value.
TEST(Parameters, EveryRowIsAPresetKey) {
    Preset p;
    ShadingSettings& s = p.shading;
    s.light_direction = {0.3f, 0.4f, 0.5f};
    s.kd = {0.1f, 0.2f, 0.3f};
    s.shininess = 123.0f;
    s.fog = FogMode::Exp;
    s.fade_distance = FadeDistance::Eye;
    s.anisotropy = 4;
    s.msaa = 8;
    const std::string text = preset_to_json(p);
    for (const ParameterInfo& row : shading_parameters()) {
        std::string quoted(1, '"');
        quoted.append(row.key).push_back('"');
        EXPECT_NE(text.find(quoted), std::string::npos) << row.key;
    }
    const Preset back = preset_from_json(text, "p.json");
    for (const ParameterInfo& row : shading_parameters())
        EXPECT_EQ(format_parameter(row, back.shading), format_parameter(row, s)) << row.key;
}

}  // namespace
}  // namespace leanfade::test
