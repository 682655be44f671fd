#include <gtest/gtest.h>

#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/text.hpp"

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

// Every message the command line prints goes through terminal_text: one line, nothing that a
// terminal acts on or that changes how the line reads, printable text kept.
TEST(TerminalText, ControlAndFormatCharactersAreShownAndTextKept) {
    EXPECT_EQ(terminal_text("plain text: a.png"), "plain text: a.png");
    EXPECT_EQ(terminal_text("caf\xC3\xA9 \xE6\x97\xA5\xE6\x9C\xAC"),
              "caf\xC3\xA9 \xE6\x97\xA5\xE6\x9C\xAC");  // UTF-8 kept
    EXPECT_EQ(terminal_text("a\\x1B"), "a\\x1B");       // backslashes kept
    EXPECT_EQ(terminal_text("\x1B[2J\x1B]0;t\x07"), "\\x1B[2J\\x1B]0;t\\x07");
    EXPECT_EQ(terminal_text("a\nb\rc\td\x7F"), "a\\x0Ab\\x0Dc\\x09d\\x7F");
    EXPECT_EQ(terminal_text(std::string("cut\0here", 8)), "cut\\x00here");
    EXPECT_EQ(terminal_text("\xC2\x85\xC2\x9B"), "\\u{0085}\\u{009B}");  // C1
    EXPECT_EQ(terminal_text("x\xE2\x80\xAEy\xE2\x81\xA6z"), "x\\u{202E}y\\u{2066}z");
    EXPECT_EQ(terminal_text("\xE2\x80\x8B\xEF\xBB\xBF\xE2\x80\xA8"), "\\u{200B}\\u{FEFF}\\u{2028}");
    EXPECT_EQ(terminal_text("\xFF\xC3"), "\\xFF\\xC3");           // invalid, truncated
    EXPECT_EQ(terminal_text("\xC0\xAF"), "\\xC0\\xAF");           // overlong
    EXPECT_EQ(terminal_text("\xED\xA0\x80"), "\\xED\\xA0\\x80");  // a surrogate
    // escape_text's output passes unchanged; a long text is kept whole.
    EXPECT_EQ(terminal_text(escape_text("k\x1B")), "k\\x1B");
    EXPECT_EQ(terminal_text(std::string(5000, 'a')).size(), 5000u);
}

}  // namespace
}  // namespace leanfade
