// MIP chains stored one file per level (io::read_mip_series), as Filament's roughness-prefilter
// writes them: NAME_0.png, NAME_1.png, ... down to 1 x 1.
#include <filesystem>
#include <string>

#include "io_test_helpers.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::io {
namespace {

using test::expect_error;
using test::scratch_folder;

void write_series(const std::string& base, int width, int height, int skip = -1) {
    for (int level = 0;; ++level) {
        if (level != skip)
            write_png(base + "_" + std::to_string(level) + ".png",
                      Image(width, height, 1, float(level) / 16.0f), 8);
        if (width == 1 && height == 1) break;
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
    }
}

TEST(MipSeries, ReadsEveryLevelDownToOneTexel) {
    const std::string folder = scratch_folder();
    write_series(folder + "/r", 8, 2);
    const std::vector<Image> chain = read_mip_series(folder + "/r_0.png");
    ASSERT_EQ(chain.size(), 4u);  // 8x2, 4x1, 2x1, 1x1
    EXPECT_EQ(chain[1].width, 4);
    EXPECT_EQ(chain[1].height, 1);
    EXPECT_EQ(chain[3].width, 1);
    EXPECT_NEAR(chain[2].pixels[0], 2.0f / 16.0f, 0.5f / 255.0f);
}

TEST(MipSeries, RefusesOtherNamesMissingLevelsAndWrongSizes) {
    const std::string folder = scratch_folder();
    write_series(folder + "/gap", 8, 8, 2);
    expect_error([&] { read_mip_series(folder + "/gap_0.png"); }, folder + "/gap_2.png",
                 "level 2 of the MIP series is missing");
    write_series(folder + "/ok", 8, 8);
    expect_error([&] { read_mip_series(folder + "/ok_1.png"); }, folder + "/ok_1.png",
                 "NAME_0.EXT");
    write_png(folder + "/ok_2.png", Image(3, 3, 1, 0.5f), 8);
    expect_error([&] { read_mip_series(folder + "/ok_0.png"); }, folder + "/ok_2.png",
                 "expected 2x2");
}

}  // namespace
}  // namespace leanfade::io
