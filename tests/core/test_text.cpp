#include <gtest/gtest.h>

#include "leanfade/core/text.hpp"

namespace leanfade {
namespace {

using Pieces = std::vector<std::string>;

TEST(Split, KeepsEmptyPieces) {
    EXPECT_EQ(split("a,,b", ','), (Pieces{"a", "", "b"}));
    EXPECT_EQ(split("", ','), (Pieces{""}));
    EXPECT_EQ(split(",", ','), (Pieces{"", ""}));
    EXPECT_EQ(split("2:64:6", ':'), (Pieces{"2", "64", "6"}));
    EXPECT_EQ(split("no separator", ','), (Pieces{"no separator"}));
}

TEST(NumberText, ParsesTheWholeTextAsAFiniteNumber) {
    EXPECT_EQ(parse_finite_float("1.5"), 1.5f);
    EXPECT_EQ(parse_finite_float("-2e-3"), -2e-3f);
    EXPECT_EQ(parse_finite_float(" 4"), 4.0f);  // leading white space, as strtof
    EXPECT_EQ(parse_finite_double("0.1"), 0.1);
    for (const char* bad : {"", "1.5x", "1.5 ", "nan", "inf", "-inf", "1e39", "x", ","}) {
        EXPECT_FALSE(parse_finite_float(bad).has_value()) << bad;
    }
    EXPECT_FALSE(parse_finite_double("1e309").has_value());
    EXPECT_EQ(parse_finite_double("1e39"), 1e39);
    // An embedded NUL is not the end of the number.
    EXPECT_FALSE(parse_finite_float(std::string_view("1\0" "2", 3)).has_value());
}

TEST(NumberText, ShortestTextReadsBackExactly) {
    EXPECT_EQ(shortest_text(0.15f), "0.15");
    EXPECT_EQ(shortest_text(300.0f), "300");
    EXPECT_EQ(shortest_text(0.1), "0.1");
    for (float v : {0.1f, 1.0f / 3.0f, 13777.0f, 1e-8f, -2.5e30f, 7e-45f}) {
        const std::optional<float> back = parse_finite_float(shortest_text(v));
        ASSERT_TRUE(back.has_value()) << v;
        EXPECT_EQ(*back, v);
    }
}

}  // namespace
}  // namespace leanfade
