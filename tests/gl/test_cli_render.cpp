// `leanfade render` as a user runs it: outputs, cells, and one-line errors.
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "gl_test_helpers.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

struct Result {
    int status = -1;
    std::string out, err;
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

Result run_render(const std::string& args, const fs::path& dir) {
    const std::string exe = std::string(LEANFADE_BINARY_DIR) + "/tools/leanfade/leanfade";
    const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
    const std::string command = "cd '" + dir.string() + "' && '" + exe + "' render " + args +
                                " >'" + out.string() + "' 2>'" + err.string() + "' </dev/null";
    const int status = std::system(command.c_str());
    Result r;
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

std::size_t lines(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

TEST(CliRender, WritesTheGridAndTheCells) {
    const fs::path dir = scratch_dir("cli_render");
    const Result r = run_render(
        "--scene sphere --techniques bump,reference --distances 2.5,12 --size 40x32 "
        "--ref-samples 2 --texture-size 64 --bits 8 --shininess 200 --fade-distance eye "
        "--fog linear --fog-start 2 --fog-end 30 --light-dir=-1,1,0.5 --kd 0.4 "
        "--cells cells --cell-format pfm -o grid.png",
        dir);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(lines(r.out), 1u) << r.out;
    EXPECT_TRUE(r.err.empty()) << "no progress line when stderr is not a terminal: " << r.err;
    const Image grid = io::read_image((dir / "grid.png").string());
    EXPECT_GT(grid.width, 2 * 40);
    EXPECT_GT(grid.height, 2 * 32);
    for (const char* name : {"bump_d2.5", "bump_d12", "reference_d2.5", "reference_d12"}) {
        const Image png = io::read_image((dir / "cells" / (std::string(name) + ".png")).string());
        EXPECT_EQ(png.width, 40);
        EXPECT_EQ(png.height, 32);
        const Image pfm = io::read_image((dir / "cells" / (std::string(name) + ".pfm")).string());
        EXPECT_EQ(pfm.width, 40);
        EXPECT_EQ(pfm.channels, 3);
    }
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos)
            << "temporary left behind: " << entry.path();
}

TEST(CliRender, BadInputsAreOneLineErrors) {
    const fs::path dir = scratch_dir("cli_render_errors");
    const std::string cases[] = {
        "--techniques bump,phong",
        "--distances 3,0.5",
        "--size 10x10",
        "--size big",
        "--shininess -1",
        "--pmax 0.5",
        "--fade-distance far",
        "--fog smoke",
        "--light-dir 1,2",
        "--kd red",
        "--msaa 3",
        "--aniso 0",
        "--ref-samples 0",
        "--bits 12",
        "--bumps missing.png",
        "--scene nothing",
        "--from heightmap",
        "--shader-dir nowhere",
        "--fog linear --fog-start 5 --fog-end 5",
    };
    for (const std::string& args : cases) {
        std::string all = args + " -o never.png";
        if (args.find("--scene") == std::string::npos) all += " --scene sphere";
        if (args.find("--size") == std::string::npos) all += " --size 32x32";
        const Result r = run_render(all, dir);
        EXPECT_EQ(r.status, 1) << args << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << args << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "never.png")) << args;
    }
    // CLI11 rejects a non-number itself, also in one line.
    const Result r = run_render("--shininess shiny -o never.png", dir);
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_FALSE(fs::exists(dir / "never.png"));
}

}  // namespace
}  // namespace leanfade::test
