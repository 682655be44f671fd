// Nothing read from a file or a flag reaches gnuplot as code: results.json technique names are
// checked against the renderer's techniques, every string in a script is a closed gnuplot
// literal, file names cannot be pipes, and gnuplot runs without a shell (docs/robustness.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/eval/calibration.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/core/technique.hpp"
#include "nlohmann/json.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

fs::path gnuplot_folder(const std::string& name) {
    return leanfade::test::fresh_scratch_folder("gnuplot_safety", name);
}

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

// A name that ends gnuplot's string and command, then runs a shell command.
const std::string kHostileName = "x'\nsystem(\"id > PWNED.txt\")\nprint '";

// Every line of a script: blank, a comment, or a set / unset / plot command whose single-quoted
// strings all close on the line and with nothing outside them that gnuplot would take as a
// second command or a substitution.
void expect_only_leanfade_commands(const std::string& script) {
    std::size_t start = 0;
    while (start < script.size()) {
        const std::size_t end = script.find('\n', start);
        ASSERT_NE(end, std::string::npos) << "the script ends with a newline";
        const std::string line = script.substr(start, end - start);
        start = end + 1;
        if (line.empty() || line[0] == '#') continue;
        const std::string command = line.substr(0, line.find(' '));
        EXPECT_TRUE(command == "set" || command == "unset" || command == "plot") << line;
        bool in_string = false;
        for (std::size_t i = 0; i < line.size(); ++i) {
            const char c = line[i];
            if (in_string) {
                if (c == '\'' && i + 1 < line.size() && line[i + 1] == '\'')
                    ++i;
                else if (c == '\'')
                    in_string = false;
                EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20) << line;
            } else if (c == '\'') {
                in_string = true;
            } else {
                EXPECT_TRUE(c != ';' && c != '`' && c != '@' && c != '"') << line;
            }
        }
        EXPECT_FALSE(in_string) << "unclosed string: " << line;
    }
}

std::vector<eval::CaseResult> cases_of(const std::vector<Technique>& techniques) {
    std::vector<eval::CaseResult> cases;
    for (Technique technique : techniques)
        for (float d : {2.0f, 8.0f}) {
            eval::CaseResult c;
            c.technique = technique;
            c.distance = d;
            c.shininess = 128.0f;
            c.energy = c.rmse = c.ssim = c.flicker = 0.5;
            cases.push_back(c);
        }
    return cases;
}

TEST(GnuplotQuoting, AnyTextIsOneClosedSingleQuotedLiteral) {
    EXPECT_EQ(eval::gnuplot_string("lean"), "'lean'");
    EXPECT_EQ(eval::gnuplot_string("it's"), "'it''s'");
    EXPECT_EQ(eval::gnuplot_string(kHostileName),
              "'x''?system(\"id > PWNED.txt\")?print '''");
    EXPECT_EQ(eval::gnuplot_string(std::string("a\0b\r\x7f", 5)), "'a?b?" "?'");  // (split: "??'" would be a trigraph)
    EXPECT_EQ(eval::gnuplot_string("`id` @macro"), "'`id` @macro'")
        << "neither is expanded inside single quotes";
}

TEST(GnuplotQuoting, FileNamesCannotBePipesOrOptions) {
    EXPECT_EQ(eval::gnuplot_file("plot_data.tsv"), "'./plot_data.tsv'");
    EXPECT_EQ(eval::gnuplot_file("|touch PWNED.png"), "'./|touch PWNED.png'");
    EXPECT_EQ(eval::gnuplot_file("<id.tsv"), "'./<id.tsv'");
    EXPECT_EQ(eval::gnuplot_file("-"), "'./-'");
    EXPECT_EQ(eval::gnuplot_file("/tmp/a'b.png"), "'/tmp/a''b.png'");
    EXPECT_THROW(eval::gnuplot_file("a\nb.png"), Error) << "a file name is never changed";
    EXPECT_THROW(eval::gnuplot_file(""), Error);
}

// Cases hold techniques of the table (a name from a file is refused when read, below): each
// line's title is its technique's name as a closed literal.
TEST(GnuplotScripts, TechniqueTitlesAreTheTablesNames) {
    const std::vector<Technique> techniques = approximating_techniques();
    const std::string script = eval::plots_script(cases_of(techniques), {128.0f});
    expect_only_leanfade_commands(script);
    for (Technique t : techniques)
        EXPECT_NE(script.find(std::string("title '") + to_string(t) + "'"), std::string::npos)
            << to_string(t) << "\n" << script;
    // Each technique's line has a colour of its own, the same in every panel.
    std::map<std::string, std::set<std::string>> colors_of;
    const std::regex line_color("lc rgb '(#[0-9a-f]{6})' title '([a-z-]+)'");
    for (auto it = std::sregex_iterator(script.begin(), script.end(), line_color);
         it != std::sregex_iterator(); ++it)
        colors_of[(*it)[2]].insert((*it)[1]);
    std::set<std::string> colors;
    for (Technique t : techniques) {
        ASSERT_EQ(colors_of[to_string(t)].size(), 1u) << to_string(t);
        EXPECT_TRUE(colors.insert(*colors_of[to_string(t)].begin()).second) << to_string(t);
    }
}

TEST(GnuplotScripts, CalibrationPlotNamesAreLiteralsAndFiles) {
    const std::string script = eval::calibration_plot_script(
        "exp:0.05", 0.1, 16.0, {1.0, 0.5}, {1.0, 0.6}, "a' ; system('touch PWNED') ; 'b.png",
        "|id.tsv");
    expect_only_leanfade_commands(script);
    EXPECT_NE(script.find("set output './a'' ; system(''touch PWNED'') ; ''b.png'\n"),
              std::string::npos)
        << script;
    EXPECT_NE(script.find("plot './|id.tsv' using 1:2"), std::string::npos) << script;
}

// gnuplot itself on the script of every measured technique: the lines are drawn, nothing else
// runs.
TEST(GnuplotScripts, GnuplotDrawsEveryTechniqueAndRunsNothingElse) {
    const fs::path dir = gnuplot_folder("plots");
    std::string note;
    const bool plotted =
        eval::write_plots(dir.string(), cases_of(approximating_techniques()), {128.0f}, note);
    EXPECT_FALSE(fs::exists(dir / "PWNED.txt")) << "gnuplot ran the command in the name";
    EXPECT_FALSE(fs::exists("PWNED.txt"));
    expect_only_leanfade_commands(read_text(dir / "plots.gp"));
    if (note.find("not found on PATH") == std::string::npos) {
        // gnuplot is installed (gnuplot-nox): the plots are drawn from the quoted script.
        EXPECT_TRUE(plotted) << note;
        EXPECT_TRUE(fs::is_regular_file(dir / "energy.png")) << note;
    }
}

// gnuplot is started without a shell: a folder name with shell syntax is only a name.
TEST(GnuplotScripts, RunGnuplotUsesNoShell) {
    const fs::path dir = gnuplot_folder("x';touch PWNED;'$(touch PWNED2)");
    write_file(dir / "t.gp", "print 'ok'\n");
    std::string note;
    eval::run_gnuplot((dir / "t.gp").string(), note);
    for (const fs::path& where : {dir, dir.parent_path(), fs::current_path()}) {
        EXPECT_FALSE(fs::exists(where / "PWNED")) << where;
        EXPECT_FALSE(fs::exists(where / "PWNED2")) << where;
    }
}

TEST(ResultsJson, TechniqueNamesMustBeTheTablesMeasuredTechniques) {
    for (const TechniqueInfo& row : kTechniques)
        EXPECT_EQ(eval::is_measured_technique(row.name), !row.supersampled) << row.name;
    for (const char* name : {"", "Lean", "lean ", "phong", "reference"})
        EXPECT_FALSE(eval::is_measured_technique(name)) << name;
}

// A results.json as leanfade eval writes it, with the technique of every case given: LEAN's
// name replaced by `technique` in the text (eval writes only the table's names).
std::string results_with_technique(const std::string& technique) {
    eval::SweepInfo info;
    info.scene = "sphere";
    info.bumps = "bumps";
    info.techniques = {Technique::Lean};
    info.distances = {2.0f};
    info.shininesses = {128.0f};
    info.width = info.height = 32;
    info.reference_samples = 2;
    info.frames = 2;
    info.motion_pixels = 0.5f;
    eval::CaseResult c;
    c.technique = Technique::Lean;
    c.distance = 2.0f;
    c.shininess = 128.0f;
    std::string text = eval::results_json(info, {c});
    const std::string lean = "\"lean\"";
    const std::string quoted = nlohmann::json(technique).dump();
    for (std::size_t at = 0; (at = text.find(lean, at)) != std::string::npos; at += quoted.size())
        text.replace(at, lean.size(), quoted);
    return text;
}

TEST(ResultsJson, UnknownTechniqueIsRefusedWhenRead) {
    const fs::path dir = gnuplot_folder("read");
    write_file(dir / "results.json", results_with_technique(kHostileName));
    eval::SweepInfo info;
    std::vector<eval::CaseResult> cases;
    try {
        eval::read_results_json((dir / "results.json").string(), info, cases);
        FAIL() << "a technique the renderer does not know was accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("unknown technique 'x'?system("), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    }
    write_file(dir / "results.json", results_with_technique("lean"));
    EXPECT_NO_THROW(eval::read_results_json((dir / "results.json").string(), info, cases));
}

TEST(CliEvalHostile, ReplotRefusesATechniqueNameThatIsCode) {
    const fs::path dir = gnuplot_folder("replot");
    fs::create_directories(dir / "out");
    write_file(dir / "out" / "results.json", results_with_technique(kHostileName));
    const RunResult r = run_leanfade_in("eval --replot out", dir, dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("unknown technique"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "PWNED.txt"));
    EXPECT_FALSE(fs::exists(dir / "PWNED.txt"));
}

TEST(CliCalibrateHostile, PlotFileNameIsOnlyAName) {
    const fs::path dir = gnuplot_folder("calibrate");
    const std::string plot = "a' ; system('touch PWNED') ; 'b.png";
    const RunResult r = run_leanfade_in(
        "calibrate --target exp:0.04 --scene sphere --distances 2,8 --size 32x32 "
        "--texture-size 32 --plot " +
            shell_quote(plot),
        dir, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_FALSE(fs::exists(dir / "PWNED"));
    EXPECT_TRUE(fs::is_regular_file(dir / "a' ; system('touch PWNED') ; 'b.tsv"));
    if (r.err.find("not found on PATH") == std::string::npos) {  // gnuplot-nox is installed
        EXPECT_TRUE(fs::is_regular_file(dir / "a' ; system('touch PWNED') ; 'b.png")) << r.err;
    }

    const RunResult newline = run_leanfade_in(
        "calibrate --target exp:0.04 --scene sphere --distances 2,8 --plot " +
            shell_quote("x\nsystem('touch PWNED').png"),
        dir, dir);
    EXPECT_EQ(newline.exit_code, 1) << newline.err;
    EXPECT_NE(newline.err.find("control character"), std::string::npos) << newline.err;
    EXPECT_FALSE(fs::exists(dir / "PWNED"));

    const RunResult script = run_leanfade_in(
        "calibrate --target exp:0.04 --scene sphere --distances 2,8 --plot fit.gp", dir, dir);
    EXPECT_EQ(script.exit_code, 1) << script.err;
    EXPECT_NE(script.err.find("--plot:"), std::string::npos) << script.err;
}

}  // namespace
}  // namespace leanfade::test
