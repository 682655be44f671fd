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

}  // namespace
}  // namespace leanfade
