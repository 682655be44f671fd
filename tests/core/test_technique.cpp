// The technique table (leanfade/core/technique.hpp): names parse back to their rows, every row's
// lobe is one of the shared header's, and the lists derived from it agree with it.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/technique.hpp"

namespace leanfade::test {
namespace {

TEST(TechniqueTable, NamesAreUniqueAndParseBackToTheirRow) {
    std::set<std::string_view> names, labels;
    for (const TechniqueInfo& row : kTechniques) {
        EXPECT_TRUE(names.insert(row.name).second) << row.name;
        EXPECT_TRUE(labels.insert(row.label).second) << row.label;
        EXPECT_EQ(parse_technique(row.name), row.id);
        EXPECT_EQ(std::string(to_string(row.id)), row.name);
        EXPECT_FALSE(row.description.empty()) << row.name;
        // Names go into file names, JSON keys, CSV headers and plot scripts (quoted): lower-case
        // letters, with inner hyphens between words.
        for (char c : row.name) EXPECT_TRUE((c >= 'a' && c <= 'z') || c == '-') << row.name;
        EXPECT_NE(row.name.front(), '-') << row.name;
        EXPECT_NE(row.name.back(), '-') << row.name;
        EXPECT_EQ(row.name.find("--"), std::string_view::npos) << row.name;
    }
}

TEST(TechniqueTable, EveryLobeIsOneOfTheSharedHeader) {
    for (const TechniqueInfo& row : kTechniques) {
        EXPECT_GE(row.shader_technique, 0) << row.name;
        EXPECT_LT(row.shader_technique, shading::LF_TECHNIQUE_COUNT) << row.name;
    }
    // Exactly one ground truth, and it shades with the baseline's lobe.
    int supersampled = 0;
    for (const TechniqueInfo& row : kTechniques)
        if (row.supersampled) {
            ++supersampled;
            EXPECT_EQ(row.shader_technique, shading::LF_TECHNIQUE_BUMP);
        }
    EXPECT_EQ(supersampled, 1);
    // The techniques that read B and M are those whose lobe uses them.
    for (const TechniqueInfo& row : kTechniques) {
        const bool moment_lobe = row.shader_technique == shading::LF_TECHNIQUE_LEAN ||
                                 row.shader_technique == shading::LF_TECHNIQUE_FADE ||
                                 row.shader_technique == shading::LF_TECHNIQUE_CLEAN ||
                                 row.shader_technique == shading::LF_TECHNIQUE_ROUGHNESS_MIPS ||
                                 row.shader_technique == shading::LF_TECHNIQUE_TWO_LOBE;
        EXPECT_EQ(row.reads_moments, moment_lobe) << row.name;
        EXPECT_EQ(row.reads_plateau, row.shader_technique == shading::LF_TECHNIQUE_TWO_LOBE)
            << row.name;
        // The truth integrates the footprint itself: it never asks for geometric AA.
        if (row.supersampled) {
            EXPECT_FALSE(row.geometric_aa_by_default) << row.name;
        }
        EXPECT_EQ(row.fades, row.shader_technique == shading::LF_TECHNIQUE_FADE) << row.name;
    }
}

TEST(TechniqueTable, ListsFollowTheTable) {
    ASSERT_EQ(all_techniques().size(), kTechniques.size());
    for (std::size_t i = 0; i < kTechniques.size(); ++i)
        EXPECT_EQ(all_techniques()[i], kTechniques[i].id);
    const std::vector<Technique> measured = approximating_techniques();
    EXPECT_EQ(measured.size(), kTechniques.size() - 1);
    for (Technique t : measured) EXPECT_FALSE(info(t).supersampled);
    EXPECT_EQ(parse_techniques(join_technique_names(all_techniques())), all_techniques());
    // The list for people: every measured row's name in table order, ", " between, "or" last.
    std::string expected;
    for (std::size_t i = 0; i < measured.size(); ++i)
        expected += (i == 0 ? "" : i + 1 == measured.size() ? " or " : ", ") +
                    std::string(info(measured[i]).name);
    EXPECT_EQ(technique_names(measured), expected);
}

TEST(TechniqueTable, BadListsNameTheSettingAndTheCause) {
    try {
        parse_techniques("lean,phong", "techniques");
        FAIL() << "an unknown name must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "techniques");
        EXPECT_NE(e.cause().find("unknown technique 'phong'"), std::string::npos) << e.what();
        EXPECT_NE(e.cause().find(technique_names(all_techniques())), std::string::npos);
    }
    EXPECT_THROW(parse_techniques("lean,lean"), Error);
    EXPECT_THROW(parse_techniques(""), Error);
    EXPECT_THROW(parse_techniques("lean,"), Error);
}

}  // namespace
}  // namespace leanfade::test
