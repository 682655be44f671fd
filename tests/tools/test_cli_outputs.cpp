// Outputs (docs/robustness.md, "Outputs"): every subcommand that writes checks its outputs before
// any work (an output may only create or replace a regular file that is not an input and not
// another output of the run), publishes the outputs that belong together all or nothing, and
// leaves no temporary behind when it is interrupted by SIGINT or SIGTERM.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/core/detail/preset.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
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

void write_text(const fs::path& p, const std::string& text) {
    std::ofstream out(p, std::ios::binary);
    out << text;
}

std::string read_text(const fs::path& p) {
    return test::read_text(p);
}

// A small height map (gray PNG).
fs::path write_height_png(const fs::path& dir, const std::string& name) {
    Image img(16, 16, 1);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) img.at(x, y) = float((x * 7 + y * 3) % 16) / 15.0f;
    const fs::path p = dir / name;
    io::write_png(p.string(), img, 8);
    return p;
}

// A one-triangle OBJ file.
fs::path write_obj(const fs::path& dir, const std::string& name) {
    const fs::path p = dir / name;
    write_text(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
    return p;
}

// Names in `dir` (recursively) that look like temporaries (`.tmp-`).
std::vector<std::string> temporaries_in(const fs::path& dir) {
    std::vector<std::string> found;
    std::error_code error;
    for (fs::recursive_directory_iterator it(dir, error), end; !error && it != end;
         it.increment(error))
        if (it->path().filename().string().find(".tmp-") != std::string::npos)
            found.push_back(it->path().string());
    return found;
}

// A process id that is not running: a child that has exited and been waited for.
pid_t dead_pid() {
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    int status = 0;
    ::waitpid(child, &status, 0);
    return child;
}

// A Unix socket at `p`, bound from its folder (socket paths are limited to about 100 bytes).
fs::path make_socket(const fs::path& p) {
    const fs::path previous = fs::current_path();
    fs::current_path(p.parent_path());
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, p.filename().c_str(), sizeof address.sun_path - 1);
    EXPECT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0)
        << std::strerror(errno);
    ::close(fd);
    fs::current_path(previous);
    return p;
}

bool is_a_fifo(const fs::path& p) {
    struct stat info {};
    return ::lstat(p.c_str(), &info) == 0 && S_ISFIFO(info.st_mode);
}

void expect_one_line_error(const RunResult& r, const std::string& cause, const std::string& file) {
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr(cause));
    EXPECT_THAT(r.err, HasSubstr(file));
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// ---- 3. Outputs that replace what is not theirs ----

TEST(CliOutputs, OutputThatIsADirectorySaysSo) {
    const fs::path dir = test::scratch_dir("outputs_directory");
    const RunResult r = run_leanfade_in("bake --builtin bumps --size 16 -o .", dir, dir);
    expect_one_line_error(r, "is a directory", ".");
    EXPECT_THAT(r.err, ::testing::Not(HasSubstr("busy")));
    EXPECT_TRUE(temporaries_in(dir).empty());
}

TEST(CliOutputs, FifoSocketAndSymbolicLinkAreNotReplaced) {
    const fs::path dir = test::scratch_dir("outputs_special");
    ASSERT_EQ(::mkfifo((dir / "pipe.ktx2").c_str(), 0666), 0);
    make_socket(dir / "sock.ktx2");
    write_text(dir / "target.ktx2", "not mine");
    fs::create_symlink("target.ktx2", dir / "link.ktx2");

    RunResult r = run_leanfade("bake --builtin bumps --size 16 -o " + q(dir / "pipe.ktx2"), dir);
    expect_one_line_error(r, "is a FIFO", "pipe.ktx2");
    EXPECT_TRUE(is_a_fifo(dir / "pipe.ktx2"));

    r = run_leanfade("bake --builtin bumps --size 16 -o " + q(dir / "sock.ktx2"), dir);
    expect_one_line_error(r, "is a socket", "sock.ktx2");
    EXPECT_TRUE(fs::is_socket(fs::symlink_status(dir / "sock.ktx2")));

    r = run_leanfade("bake --builtin bumps --size 16 -o " + q(dir / "link.ktx2"), dir);
    expect_one_line_error(r, "is a symbolic link", "link.ktx2");
    EXPECT_TRUE(fs::is_symlink(dir / "link.ktx2"));
    EXPECT_EQ(read_text(dir / "target.ktx2"), "not mine");
    EXPECT_TRUE(temporaries_in(dir).empty());
}

TEST(CliOutputs, DeviceIsNotReplaced) {
    const fs::path dir = test::scratch_dir("outputs_device");
    const RunResult r = run_leanfade("bake --builtin bumps --size 16 -o /dev/null", dir);
    expect_one_line_error(r, "is a character device", "/dev/null");
    struct stat info {};
    ASSERT_EQ(::lstat("/dev/null", &info), 0);
    EXPECT_TRUE(S_ISCHR(info.st_mode));
}

TEST(CliOutputs, JsonThatIsTheInputOrTheOutputIsRefused) {
    const fs::path dir = test::scratch_dir("outputs_json");
    const fs::path input = write_height_png(dir, "in.png");
    const std::string before = read_text(input);

    RunResult r = run_leanfade(
        "bake " + q(input) + " -o " + q(dir / "out.ktx2") + " --json " + q(input), dir);
    expect_one_line_error(r, "same file as an input", "in.png");
    EXPECT_EQ(read_text(input), before);
    EXPECT_FALSE(fs::exists(dir / "out.ktx2"));

    r = run_leanfade(
        "bake " + q(input) + " -o " + q(dir / "out.ktx2") + " --json " + q(dir / "out.ktx2"), dir);
    expect_one_line_error(r, "written twice", "out.ktx2");
    EXPECT_FALSE(fs::exists(dir / "out.ktx2"));
    EXPECT_TRUE(temporaries_in(dir).empty());
}

TEST(CliOutputs, BatchDoesNotOverwriteALaterInput) {
    // a.png's outputs are a.lean1.png and a.lean2.png: the first is the batch's second input.
    const fs::path dir = test::scratch_dir("outputs_batch_input");
    const fs::path a = write_height_png(dir, "a.png");
    const fs::path second = write_height_png(dir, "a.lean1.png");
    const std::string before = read_text(second);
    const RunResult r = run_leanfade("bake " + q(a) + " " + q(second) + " --format png", dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr("a.lean1.png: is the same file as"));
    EXPECT_EQ(read_text(second), before);
    EXPECT_FALSE(fs::exists(dir / "a.lean2.png")) << "refused before any work";
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CliOutputs, SameStemInOutDirIsRefused) {
    const fs::path dir = test::scratch_dir("outputs_same_stem");
    fs::create_directories(dir / "one");
    fs::create_directories(dir / "two");
    fs::create_directories(dir / "out");
    write_height_png(dir / "one", "s.png");
    write_height_png(dir / "two", "s.png");
    const RunResult r = run_leanfade("bake " + q(dir / "one" / "s.png") + " " +
                                         q(dir / "two" / "s.png") + " --out-dir " + q(dir / "out"),
                                     dir);
    expect_one_line_error(r, "written twice", "s.ktx2");
    EXPECT_THAT(r.err, HasSubstr("one/s.png"));
    EXPECT_THAT(r.err, HasSubstr("two/s.png"));
    EXPECT_TRUE(fs::is_empty(dir / "out"));
}

TEST(CliOutputs, HardLinkOfTheInputIsRefused) {
    const fs::path dir = test::scratch_dir("outputs_hard_link");
    const fs::path input = write_height_png(dir, "in.png");
    fs::create_hard_link(input, dir / "alias.ktx2");
    const std::string before = read_text(input);
    const RunResult r = run_leanfade("bake " + q(input) + " -o " + q(dir / "alias.ktx2"), dir);
    expect_one_line_error(r, "is the same file as its output", "alias.ktx2");
    EXPECT_THAT(r.err, HasSubstr("in.png"));
    EXPECT_EQ(read_text(input), before);
}

TEST(CliOutputs, RenderDoesNotOverwriteItsSceneOrPreset) {
    const fs::path dir = test::scratch_dir("outputs_render_inputs");
    const fs::path obj = write_obj(dir, "m.obj");
    const std::string obj_before = read_text(obj);
    RunResult r = run_leanfade(
        "render --scene " + q(obj) + " --size 16x16 --texture-size 16 -o " + q(obj), dir);
    expect_one_line_error(r, "same file as an input", "m.obj");
    EXPECT_EQ(read_text(obj), obj_before);

    const fs::path preset = dir / "p.json";
    Preset valid;
    valid.scene = "sphere";
    valid.bumps.texture_size = 16;
    write_text(preset, preset_to_json(valid));
    const std::string preset_before = read_text(preset);
    r = run_leanfade("render --preset " + q(preset) + " --size 16x16 -o " + q(preset), dir);
    expect_one_line_error(r, "same file as an input", "p.json");
    EXPECT_EQ(read_text(preset), preset_before);
    EXPECT_TRUE(temporaries_in(dir).empty());
}

TEST(CliOutputs, ViewScreenshotDoesNotOverwriteAnInput) {
    const fs::path dir = test::scratch_dir("outputs_view");
    const fs::path obj = write_obj(dir, "m.obj");
    const std::string before = read_text(obj);
    // Refused before a window is opened: no display needed.
    const RunResult r =
        run_leanfade_in("view --scene " + q(obj) + " --frames 1 --screenshot " + q(obj), dir, dir,
                        "env -u DISPLAY -u WAYLAND_DISPLAY");
    expect_one_line_error(r, "same file as an input", "m.obj");
    EXPECT_EQ(read_text(obj), before);
}

TEST(CliOutputs, CalibrateAndBenchCheckTheirOutputs) {
    const fs::path dir = test::scratch_dir("outputs_calibrate_bench");
    const fs::path bumps = write_height_png(dir, "h.png");
    const std::string before = read_text(bumps);
    RunResult r = run_leanfade(
        "calibrate --target exp:0.1 --bumps " + q(bumps) + " --plot '' --json " + q(bumps), dir);
    expect_one_line_error(r, "same file as an input", "h.png");
    EXPECT_EQ(read_text(bumps), before);

    fs::create_directories(dir / "c.gp");  // where the plot's script goes
    r = run_leanfade("calibrate --target exp:0.1 --plot " + q(dir / "c.png"), dir);
    expect_one_line_error(r, "is a directory", "c.gp");
    EXPECT_FALSE(fs::exists(dir / "c.tsv"));

    r = run_leanfade("bench --bumps " + q(bumps) + " --json " + q(bumps), dir);
    expect_one_line_error(r, "same file as an input", "h.png");
    EXPECT_EQ(read_text(bumps), before);
    r = run_leanfade("bench --json " + q(dir / "no" / "b.json"), dir);
    expect_one_line_error(r, "does not exist", "b.json");
}

// ---- 5. Failures that destroy or leave outputs ----

TEST(CliOutputs, PngPairThatCannotBeWrittenKeepsTheExistingFiles) {
    const fs::path dir = test::scratch_dir("outputs_png_pair");
    write_text(dir / "x.lean1.png", "previous lean1");
    fs::create_directories(dir / "x.lean2.png");  // the second file cannot be written
    const RunResult r =
        run_leanfade("bake --builtin bumps --size 16 --format png -o " + q(dir / "x.png"), dir);
    expect_one_line_error(r, "is a directory", "x.lean2.png");
    ASSERT_TRUE(fs::exists(dir / "x.lean1.png")) << "the existing first file was deleted";
    EXPECT_EQ(read_text(dir / "x.lean1.png"), "previous lean1");
    EXPECT_TRUE(temporaries_in(dir).empty());
}

TEST(CliOutputs, JsonInAMissingFolderWritesNothing) {
    const fs::path dir = test::scratch_dir("outputs_json_folder");
    const RunResult r = run_leanfade("bake --builtin bumps --size 16 -o " + q(dir / "x.ktx2") +
                                         " --json " + q(dir / "nonexist" / "x.json"),
                                     dir);
    expect_one_line_error(r, "does not exist", "x.json");
    EXPECT_FALSE(fs::exists(dir / "x.ktx2")) << "the map was written before the failure";
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CliOutputs, BakeOutputCreatesItsFolderAndRemovesItOnFailure) {
    // -o into a missing folder creates it, as --out-dir does; a bake that fails leaves none.
    const fs::path dir = test::scratch_dir("outputs_bake_folder");
    RunResult r = run_leanfade(
        "bake --builtin bumps --size 16 -o " + q(dir / "new" / "deeper" / "x.ktx2"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::is_regular_file(dir / "new" / "deeper" / "x.ktx2"));
    write_text(dir / "bad.png", "not a png");
    r = run_leanfade("bake " + q(dir / "bad.png") + " -o " + q(dir / "other" / "y.ktx2"), dir);
    expect_one_line_error(r, "bad.png", "bad.png");
    EXPECT_FALSE(fs::exists(dir / "other")) << "a failed bake left its output folder";
    // A folder under a file cannot be made.
    write_text(dir / "file", "x");
    r = run_leanfade("bake --builtin bumps --size 16 -o " + q(dir / "file" / "z.ktx2"), dir);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(CliOutputs, RenderCellsAreAllOrNothing) {
    const fs::path dir = test::scratch_dir("outputs_render_cells");
    fs::create_directories(dir / "cells" / "lean_d24.png");  // the last cell cannot be written
    const RunResult r = run_leanfade(
        "render --scene sphere --techniques bump,lean --distances 3,24 --size 16x16 "
        "--texture-size 16 --cells " +
            q(dir / "cells") + " -o " + q(dir / "grid.png"),
        dir);
    expect_one_line_error(r, "is a directory", "lean_d24.png");
    EXPECT_FALSE(fs::exists(dir / "grid.png"));
    EXPECT_FALSE(fs::exists(dir / "cells" / "bump_d3.png"));
    EXPECT_TRUE(temporaries_in(dir).empty());
}

const char* kSmallEval =
    "eval --scene sphere --techniques lean --distances 2,4 --shininess 128 --spp 1 --frames 2 "
    "--size 24x24 --texture-size 16 --out ";

TEST(CliOutputs, EvalRefusesBeforeWritingPartOfItsFolder) {
    const fs::path dir = test::scratch_dir("outputs_eval_refused");
    fs::create_directories(dir / "report" / "index.html");  // the report cannot be written
    const RunResult r = run_leanfade(kSmallEval + q(dir / "report"), dir);
    expect_one_line_error(r, "is a directory", "index.html");
    EXPECT_FALSE(fs::exists(dir / "report" / "results.csv"));
    EXPECT_FALSE(fs::exists(dir / "report" / "images"));
    EXPECT_TRUE(temporaries_in(dir).empty());

    write_text(dir / "file", "x");
    const RunResult f = run_leanfade(kSmallEval + q(dir / "file"), dir);
    expect_one_line_error(f, "not a folder", "file");
    EXPECT_EQ(read_text(dir / "file"), "x");
}

TEST(CliOutputs, EvalPublishesIntoAnExistingFolderAndKeepsOtherFiles) {
    const fs::path dir = test::scratch_dir("outputs_eval_publish");
    fs::create_directories(dir / "report");
    write_text(dir / "report" / "notes.txt", "mine");
    write_text(dir / "report" / "results.csv", "old");
    const RunResult r = run_leanfade(kSmallEval + q(dir / "report"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_text(dir / "report" / "notes.txt"), "mine");
    EXPECT_THAT(read_text(dir / "report" / "results.csv"), HasSubstr("technique"));
    EXPECT_TRUE(fs::exists(dir / "report" / "results.json"));
    EXPECT_TRUE(fs::exists(dir / "report" / "index.html"));
    EXPECT_FALSE(fs::is_empty(dir / "report" / "images"));
    EXPECT_TRUE(temporaries_in(dir).empty());
    EXPECT_THAT(r.err, ::testing::Not(HasSubstr(".tmp-")));

    // --replot publishes the redrawn report the same way, shows the images already there and
    // leaves its input, results.json, as it is.
    const std::string json = read_text(dir / "report" / "results.json");
    fs::remove(dir / "report" / "index.html");
    const RunResult replot = run_leanfade("eval --replot " + q(dir / "report"), dir);
    ASSERT_EQ(replot.exit_code, 0) << replot.err;
    EXPECT_EQ(read_text(dir / "report" / "results.json"), json);
    EXPECT_THAT(read_text(dir / "report" / "index.html"), HasSubstr("src=\"images/"));
    EXPECT_FALSE(fs::is_symlink(dir / "report" / "images"));
    EXPECT_FALSE(fs::is_empty(dir / "report" / "images"));
    EXPECT_TRUE(temporaries_in(dir).empty());

    // A new folder (and its missing parent) is published by one rename.
    const RunResult n = run_leanfade(kSmallEval + q(dir / "new" / "report"), dir);
    ASSERT_EQ(n.exit_code, 0) << n.err;
    EXPECT_TRUE(fs::exists(dir / "new" / "report" / "index.html"));
    EXPECT_TRUE(temporaries_in(dir).empty());
}

TEST(CliOutputs, EvalReportNamesItsFolderNotTheTemporaryOne) {
    // Without gnuplot the report's note names the plot script: in --out, where it is published.
    const fs::path dir = test::scratch_dir("outputs_eval_note");
    const RunResult r = run_leanfade_in(kSmallEval + q(dir / "report"), dir, dir,
                                        "env PATH=/nonexistent");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.err, HasSubstr("report/plots.gp"));
    EXPECT_THAT(r.err, ::testing::Not(HasSubstr(".tmp-")));
    const std::string index = read_text(dir / "report" / "index.html");
    EXPECT_THAT(index, HasSubstr("report/plots.gp"));
    EXPECT_THAT(index, ::testing::Not(HasSubstr(".tmp-")));
    EXPECT_TRUE(temporaries_in(dir).empty());
}

// ---- 4. Interrupted runs ----

// Starts a large bake in `dir`, waits for its temporary, sends `signal_number`, and checks that
// the process ended by that signal and left nothing behind.
void interrupt_large_bake(const fs::path& dir, int signal_number) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        if (::chdir(dir.c_str()) != 0) ::_exit(126);
        std::FILE* quiet = std::freopen("/dev/null", "w", stdout);
        quiet = std::freopen("/dev/null", "w", stderr);
        (void)quiet;
        ::execl(LEANFADE_EXE, "leanfade", "bake", "--builtin", "noise", "--size", "4096", "-o",
                "big.ktx2", static_cast<char*>(nullptr));
        ::_exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    bool seen = false;
    while (!seen && std::chrono::steady_clock::now() < deadline) {
        seen = !temporaries_in(dir).empty();
        if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ::kill(child, signal_number);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(seen) << "the bake's temporary never appeared";
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << status;
    EXPECT_EQ(WTERMSIG(status), signal_number);
    EXPECT_THAT(temporaries_in(dir), ::testing::IsEmpty());
    EXPECT_FALSE(fs::exists(dir / "big.ktx2"));
}

TEST(CliOutputs, SigtermDuringALargeBakeLeavesNoTemporary) {
    interrupt_large_bake(test::scratch_dir("outputs_sigterm"), SIGTERM);
}

TEST(CliOutputs, SigintDuringALargeBakeLeavesNoTemporary) {
    interrupt_large_bake(test::scratch_dir("outputs_sigint"), SIGINT);
}

TEST(CliOutputs, StaleTemporariesOfDeadRunsAreRemoved) {
    const fs::path dir = test::scratch_dir("outputs_stale");
    const std::string id = "-" + io::temporary_run_id();  // this machine, namespace and boot
    const std::string dead = std::to_string(dead_pid());
    const std::string alive = std::to_string(::getpid());
    write_text(dir / ("x.ktx2.tmp-" + dead + "-3" + id), "stale");
    write_text(dir / ("x.ktx2.tmp-" + dead + "-4" + id + ".tmp-" + dead + "-5" + id),
               "stale, staged");
    write_text(dir / ("x.ktx2.tmp-" + alive + "-3" + id), "a running process's");
    write_text(dir / ("y.ktx2.tmp-" + dead + "-3" + id), "another output's");
    write_text(dir / "x.ktx2.tmp-notapid", "not a temporary name");
    const RunResult r = run_leanfade("bake --builtin bumps --size 16 -o " + q(dir / "x.ktx2"), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir / ("x.ktx2.tmp-" + dead + "-3" + id)));
    EXPECT_FALSE(fs::exists(dir / ("x.ktx2.tmp-" + dead + "-4" + id + ".tmp-" + dead + "-5" + id)));
    EXPECT_TRUE(fs::exists(dir / ("x.ktx2.tmp-" + alive + "-3" + id)));
    EXPECT_TRUE(fs::exists(dir / ("y.ktx2.tmp-" + dead + "-3" + id)));
    EXPECT_TRUE(fs::exists(dir / "x.ktx2.tmp-notapid"));
}

// ---- The library: OutputPlan and OutputTransaction ----

template <typename F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "no error";
}

TEST(OutputPlan, RefusesWhatIsNotARegularFileAndDuplicates) {
    const fs::path dir = test::scratch_dir("output_plan_unit");
    make_socket(dir / "s");
    write_text(dir / "in", "input");
    fs::create_directories(dir / "sub");
    auto check_one = [&](const std::string& output) {
        io::OutputPlan plan;
        plan.add_input((dir / "in").string());
        plan.add_output(output);
        return error_of([&] { plan.check(); });
    };
    EXPECT_THAT(check_one((dir / "s").string()), HasSubstr("is a socket"));
    EXPECT_THAT(check_one((dir / "sub").string()), HasSubstr("is a directory"));
    EXPECT_THAT(check_one((dir / "sub/..").string()), HasSubstr("is a directory"));
    EXPECT_THAT(check_one((dir / "sub" / ".." / "in").string()), HasSubstr("same file"));
    EXPECT_THAT(check_one((dir / "in" / "x").string()), HasSubstr("is not a folder"));
    EXPECT_THAT(check_one((dir / "none" / "x").string()), HasSubstr("does not exist"));
    EXPECT_EQ(check_one((dir / "new").string()), "no error");

    io::OutputPlan twice;
    twice.add_output((dir / "a").string(), "first");
    twice.add_output((dir / "sub" / ".." / "a").string(), "second");
    EXPECT_THAT(error_of([&] { twice.check(); }), HasSubstr("written twice"));
}

TEST(OutputTransaction, PublishesTogetherOrLeavesEverythingAsItWas) {
    const fs::path dir = test::scratch_dir("output_transaction_unit");
    write_text(dir / "a", "old a");
    {
        io::OutputTransaction outputs;
        write_text(outputs.stage((dir / "a").string()), "new a");
        outputs.stage((dir / "b").string());  // never written: a failure before publish()
    }
    EXPECT_EQ(read_text(dir / "a"), "old a");
    EXPECT_FALSE(fs::exists(dir / "b"));
    EXPECT_THAT(temporaries_in(dir), ::testing::IsEmpty());
    {
        io::OutputTransaction outputs;
        write_text(outputs.stage((dir / "a").string()), "new a");
        outputs.stage((dir / "b").string());
        EXPECT_THAT(error_of([&] { outputs.publish(); }), HasSubstr("was not written"));
    }
    EXPECT_EQ(read_text(dir / "a"), "old a");
    {
        // A second output that turned into a folder after staging: nothing is published.
        io::OutputTransaction outputs;
        write_text(outputs.stage((dir / "a").string()), "new a");
        write_text(outputs.stage((dir / "c").string()), "new c");
        fs::create_directories(dir / "c");
        EXPECT_THAT(error_of([&] { outputs.publish(); }), HasSubstr("is a directory"));
    }
    EXPECT_EQ(read_text(dir / "a"), "old a");
    fs::remove(dir / "c");
    {
        io::OutputTransaction outputs;
        write_text(outputs.stage((dir / "a").string()), "new a");
        write_text(outputs.stage((dir / "b").string()), "new b");
        EXPECT_FALSE(fs::exists(dir / "b"));
        outputs.publish();
    }
    EXPECT_EQ(read_text(dir / "a"), "new a");
    EXPECT_EQ(read_text(dir / "b"), "new b");
    EXPECT_THAT(temporaries_in(dir), ::testing::IsEmpty());
}

TEST(OutputTransaction, FolderIsRenamedOrMergedIntoTheExistingOne) {
    const fs::path dir = test::scratch_dir("output_transaction_folder");
    {
        io::OutputTransaction outputs;
        const fs::path staged = outputs.stage_folder((dir / "new" / "report").string());
        fs::create_directories(staged / "images");
        write_text(staged / "images" / "x.png", "x");
        EXPECT_FALSE(fs::exists(dir / "new" / "report"));
        outputs.publish();
    }
    EXPECT_EQ(read_text(dir / "new" / "report" / "images" / "x.png"), "x");
    write_text(dir / "new" / "report" / "keep.txt", "kept");
    {
        io::OutputTransaction outputs;
        const fs::path staged = outputs.stage_folder((dir / "new" / "report").string());
        fs::create_directories(staged / "images");
        write_text(staged / "images" / "x.png", "x2");
        write_text(staged / "images" / "y.png", "y");
        outputs.publish();
    }
    EXPECT_EQ(read_text(dir / "new" / "report" / "images" / "x.png"), "x2");
    EXPECT_EQ(read_text(dir / "new" / "report" / "images" / "y.png"), "y");
    EXPECT_EQ(read_text(dir / "new" / "report" / "keep.txt"), "kept");
    EXPECT_THAT(temporaries_in(dir), ::testing::IsEmpty());
    {
        io::OutputTransaction outputs;
        const fs::path staged = outputs.stage_folder((dir / "new" / "report").string());
        write_text(staged / "keep.txt", "replaced?");
    }  // not published
    EXPECT_EQ(read_text(dir / "new" / "report" / "keep.txt"), "kept");
    EXPECT_THAT(temporaries_in(dir), ::testing::IsEmpty());
}

TEST(Temporaries, StaleOnesOfRunningProcessesAreKept) {
    const fs::path dir = test::scratch_dir("temporaries_unit");
    const std::string id = "-" + io::temporary_run_id();
    const std::string dead = std::to_string(dead_pid());
    write_text(dir / ("o.tmp-" + dead + "-1" + id), "");
    fs::create_directories(dir / ("o.tmp-" + dead + "-2" + id) / "images");
    write_text(dir / ("o.tmp-" + std::to_string(::getpid()) + "-1" + id), "");
    EXPECT_EQ(io::remove_stale_temporaries((dir / "o").string()), 2u);
    EXPECT_TRUE(fs::exists(dir / ("o.tmp-" + std::to_string(::getpid()) + "-1" + id)));
    EXPECT_EQ(io::remove_stale_temporaries((dir / "o").string()), 0u);
    // The names leanfade gives its temporaries carry the run id.
    EXPECT_THAT(io::temporary_path_for("p"), ::testing::EndsWith(id));
}

// Before: a temporary was judged by kill(pid, 0) alone, so a run in another PID namespace (a
// container, a CI volume, NFS) deleted a live run's temporary whose pid meant nothing here. A
// pid of another run id (another machine, namespace or boot) or of a name without one (an older
// leanfade) is not asked: such a temporary is removed only once it is a day old.
TEST(Temporaries, OnesOfAnotherHostOrNamespaceAreJudgedByAge) {
    const fs::path dir = test::scratch_dir("temporaries_foreign");
    const std::string own = io::temporary_run_id();
    const std::string other = own == "0123abcd" ? "fedc3210" : "0123abcd";
    const std::string dead = std::to_string(dead_pid());
    const std::vector<std::string> foreign = {"o.tmp-" + dead + "-1-" + other,
                                              "o.tmp-" + dead + "-2"};  // no run id
    for (const std::string& name : foreign) write_text(dir / name, "another machine's run");
    fs::create_directories(dir / ("o.tmp-" + dead + "-3-" + other));
    EXPECT_EQ(io::remove_stale_temporaries((dir / "o").string()), 0u);
    for (const std::string& name : foreign) EXPECT_TRUE(fs::exists(dir / name)) << name;
    // A day and a minute old: stale whatever its process.
    const auto old = fs::file_time_type::clock::now() -
                     std::chrono::seconds(io::kStaleForeignTemporarySeconds + 60);
    fs::last_write_time(dir / foreign[0], old);
    fs::last_write_time(dir / ("o.tmp-" + dead + "-3-" + other), old);
    EXPECT_EQ(io::remove_stale_temporaries((dir / "o").string()), 2u);
    EXPECT_FALSE(fs::exists(dir / foreign[0]));
    EXPECT_FALSE(fs::exists(dir / ("o.tmp-" + dead + "-3-" + other)));
    EXPECT_TRUE(fs::exists(dir / foreign[1]));  // still young
    // The run id is 8 hexadecimal digits, the same at each call.
    EXPECT_EQ(own.size(), 8u);
    EXPECT_EQ(own.find_first_not_of("0123456789abcdef"), std::string::npos);
    EXPECT_EQ(io::temporary_run_id(), own);
}

}  // namespace
