// Flag values and output names the command line refuses before any work (docs/robustness.md):
// an empty number, a camera target no view can hold, an output whose name says another format
// than the one written there, an output inside a folder the run writes whole; and the matrix of
// `bake`'s output flags, formats, storages and plateau layer, each combination writing exactly
// the files it names (or refusing with one line and writing none).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "tools_test_helpers.hpp"

using namespace leanfade;
using test::run_leanfade;
using test::run_leanfade_in;
using test::RunResult;
using test::shell_quote;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

std::string q(const fs::path& p) {
    return shell_quote(p.string());
}

std::size_t line_count(const std::string& text) {
    return std::size_t(std::count(text.begin(), text.end(), '\n'));
}

// A small height map (gray PNG).
fs::path write_height_png(const fs::path& dir, const std::string& name, int side = 16) {
    Image img(side, side, 1);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) img.at(x, y) = float((x * 7 + y * 3) % 16) / 15.0f;
    const fs::path p = dir / name;
    io::write_png(p.string(), img, 8);
    return p;
}

// Every file under `dir` (recursively), as paths relative to it.
std::set<std::string> files_under(const fs::path& dir) {
    std::set<std::string> found;
    if (!fs::exists(dir)) return found;
    for (const auto& entry : fs::recursive_directory_iterator(dir))
        if (!entry.is_directory()) found.insert(fs::relative(entry.path(), dir).string());
    return found;
}

std::string first_bytes(const fs::path& p, std::size_t n) {
    std::ifstream in(p, std::ios::binary);
    std::string bytes(n, '\0');
    in.read(bytes.data(), std::streamsize(n));
    bytes.resize(std::size_t(in.gcount()));
    return bytes;
}

const std::string kPngMagic("\x89PNG\r\n\x1a\n", 8);
const std::string kKtx2Magic("\xABKTX 20\xBB\r\n\x1a\n", 12);

// ---- 13. Empty numeric values ----

// The options of `command` whose values are numbers, from its help: "  --seed UINT [7] ...".
std::vector<std::string> numeric_options(const std::string& command, const fs::path& dir) {
    const RunResult help = run_leanfade(command + " --help", dir);
    EXPECT_EQ(help.exit_code, 0) << help.err;
    std::vector<std::string> flags;
    std::istringstream lines(help.out);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string names, type;
        words >> names >> type;
        if (names.empty() || names[0] != '-') continue;
        type = type.substr(0, type.find_first_of(":="));  // "FLOAT=1", "INT:INT in [0 - 256]"
        if (type != "INT" && type != "UINT" && type != "FLOAT") continue;
        flags.push_back(names.substr(names.rfind(',') + 1));  // "-o,--output" -> "--output"
    }
    return flags;
}

// Before: CLI11 took "" as 0 (or its type's empty value): `--plateau-epsilon ""`, `--seed ""`,
// `render --fade ""` exited 0, `--strength ""` complained of a 0 never typed and
// `--bake-roughness ""` printed a 309-digit bound. Every numeric option of every command now
// says the value is not a number, exit 2, before any work.
TEST(CliFlagValues, EmptyNumericValuesAreNotNumbers) {
    const fs::path dir = test::scratch_dir("flag_values_empty");
    std::size_t checked = 0;
    for (const char* command :
         {"bake", "info", "render", "view", "eval", "calibrate", "bench", "shaders"}) {
        const std::vector<std::string> flags = numeric_options(command, dir);
        for (const std::string& flag : flags) {
            SCOPED_TRACE(std::string(command) + " " + flag);
            const RunResult r =
                run_leanfade_in(std::string(command) + " " + flag + " ''", dir, dir,
                                "env -u DISPLAY -u WAYLAND_DISPLAY");
            EXPECT_EQ(r.exit_code, 2) << r.err;
            EXPECT_EQ(r.err, "leanfade: " + flag +
                                 ": not a number (the value is empty) (see leanfade --help)\n");
            ++checked;
        }
    }
    // The flags of the report: each must have been among those found.
    EXPECT_GT(checked, 40u);
    const std::vector<std::string> bake = numeric_options("bake", dir);
    for (const char* flag : {"--plateau-epsilon", "--seed", "--strength", "--bake-roughness",
                             "--threads", "--max-size"})
        EXPECT_NE(std::find(bake.begin(), bake.end(), flag), bake.end()) << flag;
    const std::vector<std::string> render = numeric_options("render", dir);
    for (const char* flag : {"--fade", "--mip-bias", "--seed"})
        EXPECT_NE(std::find(render.begin(), render.end(), flag), render.end()) << flag;
    // A value that is a number still is one; "=" with nothing after is empty as well.
    const RunResult zero = run_leanfade("bake --builtin bumps --size 8 --plateau-epsilon= -o " +
                                            q(dir / "b.ktx2"),
                                        dir);
    EXPECT_EQ(zero.exit_code, 2) << zero.err;
    EXPECT_FALSE(fs::exists(dir / "b.ktx2"));
    const RunResult fine = run_leanfade(
        "bake --builtin bumps --size 8 --seed 3 --plateau-epsilon 0 -o " + q(dir / "b.ktx2"), dir);
    EXPECT_EQ(fine.exit_code, 0) << fine.err;
    EXPECT_TRUE(fs::exists(dir / "b.ktx2"));
}

// ---- 19. Values no picture can show; names of another format ----

// Before: --target 1e30,0,0 rendered an empty frame with exit 0.
TEST(CliFlagValues, CameraTargetsBeyondEveryViewAreRefused) {
    const fs::path dir = test::scratch_dir("flag_values_target");
    for (const char* target : {"1e30,0,0", "0,-1e5,0", "0,0,10001"}) {
        SCOPED_TRACE(target);
        const RunResult r = run_leanfade(
            std::string("render --size 16x16 --target ") + target + " -o " + q(dir / "t.png"), dir);
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr("leanfade render: --target: components must be in [-1e4, "
                                     "1e4] bounding radii"));
        EXPECT_EQ(line_count(r.err), 1u) << r.err;
        EXPECT_FALSE(fs::exists(dir / "t.png"));
        const RunResult v =
            run_leanfade_in(std::string("view --frames 1 --target ") + target, dir, dir,
                            "env -u DISPLAY -u WAYLAND_DISPLAY");
        EXPECT_EQ(v.exit_code, 1) << v.err;
        EXPECT_THAT(v.err, HasSubstr("--target: components must be in"));
    }
    // A preset's camera target is held to the same bound.
    const fs::path preset = dir / "p.json";
    std::ofstream(preset) << R"({"camera": {"target": [1e30, 0, 0]}})";
    const RunResult p =
        run_leanfade("render --size 16x16 --preset " + q(preset) + " -o " + q(dir / "t.png"), dir);
    EXPECT_NE(p.exit_code, 0) << p.err;
    EXPECT_THAT(p.err, HasSubstr("camera.target"));
    EXPECT_THAT(p.err, HasSubstr("components must be in [-1e4, 1e4]"));
    EXPECT_FALSE(fs::exists(dir / "t.png"));
}

// Before: `render -o x.jpg` wrote PNG bytes under a .jpg name, and `bake -o x.jpg` a KTX2 file.
TEST(CliFlagValues, OutputNamedForAnotherFormatIsRefused) {
    const fs::path dir = test::scratch_dir("flag_values_extension");
    for (const char* name : {"x.jpg", "x.JPEG", "x", "x.png.tmp"}) {
        SCOPED_TRACE(name);
        RunResult r = run_leanfade("render --size 16x16 -o " + q(dir / name), dir);
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr(std::string(name) + ": is written as a PNG file; name it "
                                                         "with .png"));
        EXPECT_EQ(line_count(r.err), 1u) << r.err;
        r = run_leanfade_in("view --frames 1 --screenshot " + q(dir / name), dir, dir,
                            "env -u DISPLAY -u WAYLAND_DISPLAY");
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr("is written as a PNG file"));
        r = run_leanfade("bake --builtin bumps --size 8 -o " + q(dir / name), dir);
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr(std::string(name) + ": is written as a KTX2 file; name it "
                                                         "with .ktx2"));
        EXPECT_TRUE(files_under(dir).empty());
    }
    // The extension in any case is the format's.
    const RunResult upper = run_leanfade("bake --builtin bumps --size 8 -o " + q(dir / "M.KTX2"), dir);
    EXPECT_EQ(upper.exit_code, 0) << upper.err;
    EXPECT_EQ(first_bytes(dir / "M.KTX2", 12), kKtx2Magic);
}

TEST(OutputPlanFormats, ExtensionOfTheWrittenFormatIsRequired) {
    const fs::path dir = test::scratch_dir("flag_values_plan_extension");
    const auto refused = [&](const std::string& name) {
        io::OutputPlan plan;
        plan.add_output((dir / name).string(), "-o", ".png");
        try {
            plan.check();
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), (dir / name).string());
            return std::string(e.cause());
        }
        return std::string();
    };
    EXPECT_EQ(refused("a.png"), "");
    EXPECT_EQ(refused("a.PnG"), "");
    EXPECT_EQ(refused("a.jpg"),
              "is written as a PNG file; name it with .png (leanfade writes no other format "
              "there, and .jpg would hold PNG bytes)");
    EXPECT_EQ(refused("png"), "is written as a PNG file; name it with .png (leanfade writes no "
                              "other format there)");
    EXPECT_THAT(refused(".png"), HasSubstr("name it with .png"));  // a dotfile has no extension
}

// ---- 16. An output inside a folder the run writes whole ----

// Before: an output inside the run's own FILE.levels/ passed the plan and the run failed after
// the bake, naming a temporary.
TEST(CliFlagValues, OutputInsideTheRunsLevelsFolderIsRefused) {
    const fs::path dir = test::scratch_dir("flag_values_levels");
    const fs::path input = write_height_png(dir, "h.png");
    const std::string roughness =
        " --roughness-out " + q(dir / "r.ktx2") + " --roughness-levels ";
    for (const std::string& inside :
         {"-o " + q(dir / "r.levels" / "m.ktx2"), "--json " + q(dir / "r.levels" / "s.json"),
          "--anisotropy-out " + q(dir / "r.levels" / "a.ktx2"),
          "--out-dir " + q(dir / "r.levels" / "maps")}) {
        SCOPED_TRACE(inside);
        for (const bool exists : {false, true}) {
            if (exists) fs::create_directories(dir / "r.levels");
            const RunResult r = run_leanfade("bake " + q(input) + roughness + inside, dir);
            EXPECT_EQ(r.exit_code, 1) << r.err;
            EXPECT_THAT(r.err, HasSubstr("is inside " + (dir / "r.levels").string() +
                                         ", a folder this run writes whole"));
            EXPECT_THAT(r.err, ::testing::Not(HasSubstr(".tmp-")));
            EXPECT_EQ(line_count(r.err), 1u) << r.err;
            std::set<std::string> left = files_under(dir);
            EXPECT_EQ(left, std::set<std::string>{"h.png"});
            fs::remove_all(dir / "r.levels");
        }
    }
}

// The same rule for the outputs of the other flags and however the folder is spelled: through
// "./" and "..", or through a symbolic link to it: refused by the plan, before the bake, naming
// no temporary.
TEST(CliFlagValues, OutputInsideTheLevelsFolderIsRefusedHoweverItIsNamed) {
    const fs::path dir = test::scratch_dir("flag_values_levels_spelled");
    const fs::path input = write_height_png(dir, "h.png");
    fs::create_directories(dir / "sub");
    const std::string levels = " --roughness-out " + q(dir / "r.ktx2") + " --roughness-levels ";
    struct Case {
        std::string flags;
        bool link = false;  // dir/link -> dir/r.levels
    };
    const std::vector<Case> cases{
        {levels + "--plateau-out " + q(dir / "r.levels" / "p.ktx2")},
        {levels + "-o " + q(dir / "m.ktx2") + " --ktx2-2d --json " +
         q(dir / "sub" / ".." / "r.levels" / "s.json")},
        {levels + "-o " + q(dir / "." / "r.levels" / "." / "m.ktx2")},
        {levels + "--format png -o " + q(dir / "r.levels" / "m.png")},
        {levels + "-o " + q(dir / "link" / "m.ktx2"), true},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.flags);
        fs::create_directories(dir / "r.levels");
        if (c.link) fs::create_directory_symlink(dir / "r.levels", dir / "link");
        const RunResult r = run_leanfade("bake " + q(input) + c.flags, dir);
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr(", a folder this run writes whole"));
        EXPECT_THAT(r.err, ::testing::Not(HasSubstr(".tmp-")));
        EXPECT_EQ(line_count(r.err), 1u) << r.err;
        EXPECT_EQ(files_under(dir), std::set<std::string>{"h.png"});
        EXPECT_TRUE(fs::is_empty(dir / "r.levels"));
        fs::remove(dir / "link");
        fs::remove_all(dir / "r.levels");
    }
}

// ---- 18. bake's output flags x format x storage x plateau layer ----

struct Combination {
    std::string format;     // ktx2, png
    std::string bits;       // 8, 16, 16f, 32f
    bool plateau = false;   // --plateau-epsilon default, or 0
    std::string placement;  // -o, --out-dir, beside
    std::string extra;      // "", json, plateau-out, ktx2-2d, roughness, levels, anisotropy
};

std::string describe(const Combination& c) {
    return "--format " + c.format + " --bits " + c.bits + (c.plateau ? "" : " --plateau-epsilon 0") +
           " " + c.placement + " " + c.extra;
}

// Before: `bake --format png --plateau-epsilon 0` planned one output named .ktx2 and the writer
// read the pair's second name past the end of the plan (a PNG under a .ktx2 name, a layer
// written over -o's file or to a garbage name). Each combination either writes exactly the
// files it names, each in its format, or refuses with one line and writes nothing; the
// combinations that must work do.
TEST(CliBakeMatrix, EveryOutputFlagFormatStorageAndPlateauWritesExactlyItsFiles) {
    const fs::path root = test::scratch_dir("flag_values_bake_matrix");
    std::vector<Combination> combinations;
    for (const std::string format : {"ktx2", "png"})
        for (const std::string bits : {"8", "16", "16f", "32f"}) {
            if (format == "png" && (bits == "16f" || bits == "32f")) continue;
            for (const bool plateau : {true, false})
                for (const std::string placement : {"-o", "--out-dir", "beside"})
                    for (const std::string extra : {"", "json", "plateau-out", "ktx2-2d",
                                                    "roughness", "levels", "anisotropy"})
                        combinations.push_back({format, bits, plateau, placement, extra});
        }
    int accepted = 0;
    for (const Combination& c : combinations) {
        SCOPED_TRACE(describe(c));
        const fs::path dir = root / "run";
        fs::remove_all(dir);
        fs::create_directories(dir / "in");
        fs::create_directories(dir / "out");
        const fs::path input = write_height_png(dir / "in", "h.png");
        std::string args = "bake " + q(input) + " --format " + c.format + " --bits " + c.bits;
        if (!c.plateau) args += " --plateau-epsilon 0";
        std::set<std::string> expected{"in/h.png"};
        const bool roughness = c.extra == "roughness" || c.extra == "levels";
        // Where the LEAN map goes (without -o or --out-dir, roughness outputs alone write none
        // in KTX2: docs/roughness.md).
        std::string base;  // relative to dir, without extension
        if (c.placement == "-o") {
            base = "out/m";
            args += " -o " + q(dir / (base + "." + c.format));
        } else if (c.placement == "--out-dir") {
            base = "out/h";
            args += " --out-dir " + q(dir / "out");
        } else {
            base = "in/h";
        }
        const bool writes_map = !((roughness || c.extra == "anisotropy") &&
                                  c.placement == "beside" && c.format != "png");
        if (writes_map && c.format == "ktx2") expected.insert(base + ".ktx2");
        if (writes_map && c.format == "png") {
            expected.insert(base + ".lean1.png");
            expected.insert(base + ".lean2.png");
            if (c.plateau) expected.insert(base + ".plateau.png");
        }
        bool valid = true;
        if (c.extra == "json") {
            args += " --json " + q(dir / "out/s.json");
            expected.insert("out/s.json");
        } else if (c.extra == "plateau-out") {
            args += " --plateau-out " + q(dir / "out/p.ktx2");
            expected.insert("out/p.ktx2");
            valid = c.plateau;
        } else if (c.extra == "ktx2-2d") {
            args += " --ktx2-2d";
            expected.insert(base + ".lean1.ktx2");
            expected.insert(base + ".lean2.ktx2");
            valid = c.format == "ktx2";
        } else if (roughness) {
            args += " --roughness-out " + q(dir / "out/r.ktx2");
            expected.insert("out/r.ktx2");
            expected.insert("out/r.normal.ktx2");
            if (c.extra == "levels") {
                args += " --roughness-levels";
                for (int level = 0; level < 5; ++level)
                    for (const char* what : {"roughness", "normal"})
                        expected.insert("out/r.levels/" + std::string(what) + "_mip" +
                                        std::to_string(level) + ".png");
            }
        } else if (c.extra == "anisotropy") {
            args += " --anisotropy-out " + q(dir / "out/a.ktx2");
            expected.insert("out/a.ktx2");
        }
        const RunResult r = run_leanfade(args, dir);
        std::set<std::string> found = files_under(dir);
        if (!valid) {
            EXPECT_EQ(r.exit_code, 1) << r.err;
            EXPECT_EQ(line_count(r.err), 1u) << r.err;
            EXPECT_EQ(found, std::set<std::string>{"in/h.png"});
            continue;
        }
        ASSERT_EQ(r.exit_code, 0) << args << "\n" << r.err;
        ++accepted;
        EXPECT_EQ(found, expected) << args;
        for (const std::string& file : found) {
            const std::string name = fs::path(file).filename().string();
            if (name.ends_with(".png")) {
                EXPECT_EQ(first_bytes(dir / file, 8), kPngMagic) << file;
            }
            if (name.ends_with(".ktx2")) {
                EXPECT_EQ(first_bytes(dir / file, 12), kKtx2Magic) << file;
            }
        }
    }
    EXPECT_GT(accepted, 150);
}

// ---- 8. The file size limit ----

// Before: under `ulimit -f` the first write past the limit killed the run with SIGXFSZ (status
// 153, no message) and left its temporaries. The signal is ignored: the write fails with EFBIG,
// one line naming the output, exit 1, nothing left.
TEST(CliFlagValues, FileSizeLimitIsAnErrorNotASignal) {
    const fs::path dir = test::scratch_dir("flag_values_fsize");
    fs::create_directories(dir / "out");
    // `ulimit -f 64`: 32 KiB in 512-byte blocks (dash), 64 KiB in bash's 1024-byte ones; the
    // maps below take about 700 KiB.
    const std::string limited = "sh -c 'ulimit -f 64 && exec \"$@\"' sh";
    for (const std::string& flags :
         {std::string("--builtin bumps --size 256 -o ") + q(dir / "out" / "m.ktx2"),
          std::string("--builtin bumps --size 256 --format png -o ") + q(dir / "out" / "m.png")}) {
        SCOPED_TRACE(flags);
        const RunResult r = run_leanfade_in("bake " + flags, dir, {}, limited);
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr("File too large"));
        EXPECT_THAT(r.err, HasSubstr((dir / "out" / "m.").string()));
        EXPECT_THAT(r.err, ::testing::Not(HasSubstr(".tmp-")));
        EXPECT_EQ(line_count(r.err), 1u) << r.err;
        EXPECT_TRUE(files_under(dir / "out").empty());
    }
    // Without the limit the same run writes its map.
    const RunResult r = run_leanfade(
        "bake --builtin bumps --size 256 -o " + q(dir / "out" / "m.ktx2"), dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GT(fs::file_size(dir / "out" / "m.ktx2"), std::uintmax_t(64) << 10);
}

// ---- 1. Files read through other files are inputs of the run ----

// Before: `render -o` could replace a texture an OBJ's .mtl names, or a level NAME_k of
// --roughness-mips: the plan knew only the files the command line named. Now an OBJ's mtllib
// files and every texture they name (map_Kd, map_Pr, map_Bump / bump, norm), and each level of a
// series, are inputs of the plan: refused up front, by the plan's message (not the one of a
// reader that finds its file claimed by an output, which comes only once the scene is read).
TEST(CliFlagValues, FilesNamedByOtherFilesAreInputsOfTheRun) {
    const fs::path dir = test::scratch_dir("flag_values_named_inputs");
    write_height_png(dir, "tex.png");
    write_height_png(dir, "h.png");
    write_height_png(dir, "r.png");
    fs::create_directories(dir / "cells");
    write_height_png(dir / "cells", "lean_d3.png");
    {
        Image normals(16, 16, 3, 0.5f);
        for (std::size_t i = 2; i < normals.pixels.size(); i += 3) normals.pixels[i] = 1.0f;
        io::write_png((dir / "n.png").string(), normals, 8);
    }
    std::ofstream(dir / "m.obj") << "mtllib m.mtl\nusemtl A\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                    "vt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n";
    struct Case {
        std::string mtl;     // the material's statements
        std::string output;  // the output flag and the file it names
        std::string file;    // that file, relative to dir
    };
    const std::string render = "render --scene m.obj --size 16x16 --techniques lean --distances 3 ";
    const std::vector<Case> cases{
        {"map_Kd tex.png\n", render + "-o m.mtl", "m.mtl"},
        {"map_Kd tex.png\n", render + "-o tex.png", "tex.png"},
        {"map_Bump -bm 2 h.png\n", render + "-o h.png", "h.png"},
        {"norm n.png\n", render + "-o ./n.png", "n.png"},
        {"Pr 0.5\nmap_Pr r.png\n", render + "-o r.png", "r.png"},
        {"map_Kd cells/lean_d3.png\n", render + "--cells cells -o grid.png", "cells/lean_d3.png"},
        {"map_Kd tex.png\n", "view --scene m.obj --frames 1 --screenshot tex.png", "tex.png"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.output);
        std::ofstream(dir / "m.mtl") << "newmtl A\n" << c.mtl;
        const std::string before = test::read_text(dir / c.file);
        const auto mtime = fs::last_write_time(dir / c.file);
        // No display: view refuses before it opens a window.
        const RunResult r =
            run_leanfade_in(c.output, dir, dir, "env -u DISPLAY -u WAYLAND_DISPLAY");
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr(c.file + ": is the same file as "));
        EXPECT_THAT(r.err, HasSubstr("input"));
        EXPECT_THAT(r.err, HasSubstr(" of this run; an output may not replace an input"));
        EXPECT_THAT(r.err, ::testing::Not(HasSubstr("an input named by another input")));
        EXPECT_EQ(line_count(r.err), 1u) << r.err;
        EXPECT_EQ(test::read_text(dir / c.file), before);
        EXPECT_EQ(fs::last_write_time(dir / c.file), mtime);
        EXPECT_FALSE(fs::exists(dir / "grid.png"));
    }
    // Each level of a --roughness-mips series, refused by the plan before anything is read.
    Image level(4, 4, 1, 0.5f);
    io::write_png((dir / "r_0.png").string(), level, 8);
    for (const int side : {2, 1}) {
        Image smaller(side, side, 1, 0.5f);
        io::write_png((dir / ("r_" + std::to_string(side == 2 ? 1 : 2) + ".png")).string(),
                      smaller, 8);
    }
    for (const char* output : {"r_1.png", "r_2.png"}) {
        SCOPED_TRACE(output);
        const std::string before = test::read_text(dir / output);
        const RunResult r = run_leanfade_in(
            std::string("render --size 16x16 --roughness-mips r_0.png -o ") + output, dir, dir);
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr(std::string(output) + ": is the same file as an input"));
        EXPECT_EQ(test::read_text(dir / output), before);
    }
}

TEST(OutputPlanFormats, ExistingOutputsAreRefusedByEveryReader) {
    const fs::path dir = test::scratch_dir("flag_values_claimed");
    const fs::path png = write_height_png(dir, "claimed.png");
    const fs::path other = write_height_png(dir, "other.png");
    fs::create_hard_link(png, dir / "alias.png");
    io::OutputPlan plan;
    plan.add_output(png.string(), "-o", ".png");
    plan.check();
    for (const fs::path& name : {png, dir / "alias.png"}) {
        try {
            (void)io::read_image(name.string());
            ADD_FAILURE() << name << ": read";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), name.string());
            EXPECT_EQ(e.cause(), "is the same file as the output " + png.string() +
                                     " of this run (an input named by another input); an output "
                                     "may not replace an input");
        }
    }
    EXPECT_EQ(io::read_image(other.string()).width, 16);
}

// ---- 14. The run's --max-size for the run's own maps ----

// Before: --plateau-out and --ktx2-2d read the staged map back with the default size limit, so a
// bake with a larger --max-size failed after the whole bake, naming its own output as a bad
// input; and `info` could not describe the map at all.
TEST(CliFlagValues, MapsBakedWithALargerMaxSizeAreReadBackWithIt) {
    const fs::path dir = test::scratch_dir("flag_values_max_size");
    Image wide(16400, 1, 1);
    for (int x = 0; x < wide.width; ++x) wide.at(x, 0) = float(x % 7) / 6.0f;
    io::write_png((dir / "wide.png").string(), wide, 8);
    RunResult r = run_leanfade_in("bake wide.png -o m.ktx2", dir, dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr("wide.png: image size 16400x1 exceeds the limit of 16384"));
    r = run_leanfade_in("bake wide.png --max-size 16400 --plateau-out p.ktx2 --ktx2-2d -o m.ktx2",
                        dir, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* file : {"m.ktx2", "p.ktx2", "m.lean1.ktx2", "m.lean2.ktx2"})
        EXPECT_EQ(first_bytes(dir / file, 12), kKtx2Magic) << file;
    r = run_leanfade_in("info m.ktx2", dir, dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr("exceeds the limit of 16384 texels per side"));
    r = run_leanfade_in("info --max-size 16400 m.ktx2", dir, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("kind: a LEAN map"));
    r = run_leanfade_in("info --max-size 100 m.ktx2", dir, dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr("exceeds the limit of 100 texels per side"));
}

// ---- 12. Limits checked on the header, before the file is read ----

// Before: only a DDS had its header checked before the file was read into memory whole; a TGA
// or PFM over the size limit cost its whole size (here 1 and 3 GiB, sparse) before the refusal.
// Now each is refused by its header: one line naming the file, exit 1, the file never read.
TEST(CliFlagValues, SizeLimitIsCheckedOnTheHeaderBeforeTheFileIsRead) {
    const fs::path dir = test::scratch_dir("flag_values_header_first");
    // A raw true-colour TGA of 16384 x 16384 texels, 32 bits each.
    std::vector<std::uint8_t> tga(18, 0);
    tga[2] = 2;
    tga[13] = 0x40;
    tga[15] = 0x40;
    tga[16] = 32;
    const std::string pfm_header = "PF\n16384 16384\n-1.0\n";
    const std::vector<std::uint8_t> pfm(pfm_header.begin(), pfm_header.end());
    for (const auto& [name, header, data] :
         {std::tuple{"big.tga", tga, std::uintmax_t(16384) * 16384 * 4},
          std::tuple{"big.pfm", pfm, std::uintmax_t(16384) * 16384 * 12}}) {
        SCOPED_TRACE(name);
        {
            std::ofstream out(dir / name, std::ios::binary);
            out.write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
        }
        fs::resize_file(dir / name, header.size() + data);
        const RunResult r = test::run_leanfade_bounded(
            "bake --max-size 4096 " + q(dir / name) + " -o " + q(dir / "out.ktx2"), dir, 60);
        EXPECT_EQ(r.exit_code, 1) << r.err;
        EXPECT_THAT(r.err, HasSubstr((dir / name).string() +
                                     ": image size 16384x16384 exceeds the limit of 4096"));
        EXPECT_EQ(line_count(r.err), 1u) << r.err;
        EXPECT_LT(r.max_rss_kib, 512L << 10) << "the file was read";
        EXPECT_FALSE(fs::exists(dir / "out.ktx2"));
        fs::remove(dir / name);
    }
}

// ---- 12. An allocation that fails ----

#if !defined(LEANFADE_TEST_SANITIZED)
// Before: under `ulimit -v` a large file read whole ended the run with "internal error:
// std::bad_alloc", exit 3, naming no file. (Compiled in ordinary builds only: AddressSanitizer
// maps terabytes of shadow memory and cannot run under `ulimit -v`.)
TEST(CliFlagValues, AllocationFailureIsOneLineNamingTheFile) {
    const fs::path dir = test::scratch_dir("flag_values_bad_alloc");
    // An uncompressed 16384 x 16384 RGBA DDS (1 GiB of data, sparse): within every limit.
    std::vector<std::uint8_t> header(128, 0);
    const auto put = [&](std::size_t at, std::uint32_t v) {
        for (int i = 0; i < 4; ++i) header[at + std::size_t(i)] = std::uint8_t(v >> (8 * i));
    };
    header[0] = 'D', header[1] = 'D', header[2] = 'S', header[3] = ' ';
    put(4, 124), put(8, 0x1007), put(12, 16384), put(16, 16384), put(76, 32), put(80, 0x41);
    put(88, 32), put(92, 0x00FF0000), put(96, 0x0000FF00), put(100, 0x000000FF);
    put(104, 0xFF000000), put(108, 0x1000);
    {
        std::ofstream out(dir / "big.dds", std::ios::binary);
        out.write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
    }
    fs::resize_file(dir / "big.dds", 128 + (std::uintmax_t(1) << 30));
    const RunResult r = run_leanfade_in("bake big.dds -o big.ktx2", dir, dir,
                                        "sh -c 'ulimit -v 900000 && exec \"$@\"' sh");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr("leanfade bake: big.dds: out of memory"));
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_FALSE(fs::exists(dir / "big.ktx2"));
    fs::remove(dir / "big.dds");
}
#endif

}  // namespace
