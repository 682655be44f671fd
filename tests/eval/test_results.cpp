// Results files of `leanfade eval`: the sweep lists, CSV, JSON round trip, plots and the report,
// with and without gnuplot on the PATH.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_runner.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/eval/results.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::eval {
namespace {

namespace fs = std::filesystem;

fs::path results_folder(const std::string& name) {
    return leanfade::test::fresh_scratch_folder("eval", name);
}

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<CaseResult> sample_cases() {
    std::vector<CaseResult> cases;
    for (float s : {128.0f, 1024.0f})
        for (float d : {2.0f, 8.0f})
            for (Technique t : {Technique::Bump, Technique::Lean}) {
                CaseResult c;
                c.technique = t;
                c.distance = d;
                c.shininess = s;
                c.energy = 0.5 + d / 10.0;
                c.rmse = 0.25;
                c.ssim = 0.9;
                c.flicker = (d == 8.0f && s == 1024.0f) ? std::nan("") : 1.5;
                c.energy_total = 0.6 + d / 10.0;
                c.object_pixels = 100;
                c.reference_spp = 64;
                c.reference_noise = 0.01;
                c.reference_energy_error = s == 1024.0f ? 0.3 : 0.01;
                cases.push_back(c);
            }
    return cases;
}

SweepInfo sample_info() {
    SweepInfo info;
    info.scene = "sphere";
    info.bumps = "bumps";
    info.techniques = {Technique::Bump, Technique::Lean};
    info.distances = {2.0f, 8.0f};
    info.shininesses = {128.0f, 1024.0f};
    info.width = 64;
    info.height = 48;
    info.fov_y_degrees = 34.0f;
    info.reference_samples = 8;
    info.adaptive_reference = true;
    info.frames = 4;
    info.motion_pixels = 0.25f;
    info.renderer = "test";
    info.seconds = 1.5;
    return info;
}

TEST(SweepLists, DistancesLogSpacedOrListed) {
    EXPECT_EQ(parse_distance_sweep("2:64:6", "--distances"),
              (std::vector<float>{2, 4, 8, 16, 32, 64}));
    const std::vector<float> d = parse_distance_sweep("1.5:64:8", "--distances");
    ASSERT_EQ(d.size(), 8u);
    EXPECT_FLOAT_EQ(d.front(), 1.5f);
    EXPECT_FLOAT_EQ(d.back(), 64.0f);
    for (std::size_t i = 1; i < d.size(); ++i) {
        EXPECT_GT(d[i], d[i - 1]);
        EXPECT_NEAR(d[i] / d[i - 1], std::pow(64.0 / 1.5, 1.0 / 7.0), 0.01);  // 3 digits
    }
    EXPECT_EQ(parse_distance_sweep("3:9:1", "--distances"), (std::vector<float>{3}));
    EXPECT_EQ(parse_distance_sweep("3,24.5", "--distances"), (std::vector<float>{3, 24.5f}));
    for (const char* bad : {"1:64:8", "2:2:3", "64:2:3", "2:64:0", "2:64:2.5", "2:64", "0.5", "3,x",
                            "", "3,3", "2:64:1001"}) {
        try {
            parse_distance_sweep(bad, "--distances");
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), "--distances") << bad;
        }
    }
}

TEST(SweepLists, Shininesses) {
    EXPECT_EQ(parse_shininess_list("128,1024,13777", "--shininess"),
              (std::vector<float>{128, 1024, 13777}));
    for (const char* bad : {"0", "-5", "12,x", "", "64,64"})
        EXPECT_THROW(parse_shininess_list(bad, "--shininess"), Error) << bad;
}

TEST(ResultsFiles, CsvHasTheDocumentedColumns) {
    const std::string csv = results_csv(sample_cases());
    std::istringstream lines(csv);
    std::string header, first;
    std::getline(lines, header);
    std::getline(lines, first);
    EXPECT_EQ(header, "technique,distance,shininess,energy,rmse,ssim,flicker,energy_total,seeds,energy_spread,"
              "energy_total_spread");
    EXPECT_EQ(first, "bump,2,128,0.7,0.25,0.9,1.5,0.8,1,0,0");
    EXPECT_NE(csv.find(",nan,"), std::string::npos) << "an undefined flicker is written as nan";
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 9);
}

TEST(ResultsFiles, JsonRoundTrip) {
    const fs::path dir = results_folder("json");
    write_text_file((dir / "results.json").string(), results_json(sample_info(), sample_cases()));
    SweepInfo info;
    std::vector<CaseResult> cases;
    read_results_json((dir / "results.json").string(), info, cases);
    EXPECT_EQ(info.scene, "sphere");
    EXPECT_EQ(info.distances, sample_info().distances);
    EXPECT_EQ(info.reference_samples, 8);
    EXPECT_TRUE(info.adaptive_reference);
    ASSERT_EQ(cases.size(), sample_cases().size());
    EXPECT_DOUBLE_EQ(cases[0].energy, 0.7);
    EXPECT_TRUE(std::isnan(cases[7].flicker)) << "null comes back as NaN";
    EXPECT_EQ(cases[3].reference_spp, 64);

    write_text_file((dir / "bad.json").string(), "{\"leanfade_eval\": 1, \"sweep\": {}}");
    EXPECT_THROW(read_results_json((dir / "bad.json").string(), info, cases), Error);
    EXPECT_THROW(read_results_json((dir / "missing.json").string(), info, cases), Error);
}

// sweep.preset is written again with indentation by --replot: its depth and size are checked
// first (a 44 KB file nested 22000 deep took gigabytes).
TEST(ResultsFiles, DeepOrLargePresetsAreRefusedBeforeTheyAreWrittenAgain) {
    const fs::path dir = results_folder("json_preset");
    SweepInfo given = sample_info();
    given.preset_json = R"({"scene": "sphere", "bumps": {"source": "bumps"}})";
    const std::string text = results_json(given, sample_cases());
    const std::string marker = "\"sphere\"";
    const std::size_t at = text.find(marker, text.find("\"preset\""));
    ASSERT_NE(at, std::string::npos);
    SweepInfo info;
    std::vector<CaseResult> cases;
    for (const auto& [levels, objects] :
         {std::pair{15, false}, {16, false}, {22000, false}, {22000, true}}) {
        std::string deep;
        for (int i = 0; i < levels; ++i) deep += objects ? "{\"a\":" : "[";
        deep += "1";
        for (int i = 0; i < levels; ++i) deep += objects ? "}" : "]";
        std::string hostile = text;
        hostile.replace(at, marker.size(), deep);
        write_text_file((dir / "results.json").string(), hostile);
        const std::string path = (dir / "results.json").string();
        // The preset itself is one level and its scene key's value the rest.
        if (levels + 1 <= 16) {
            EXPECT_NO_THROW(read_results_json(path, info, cases)) << levels;
            continue;
        }
        try {
            read_results_json(path, info, cases);
            ADD_FAILURE() << levels << " levels were read";
        } catch (const Error& e) {
            EXPECT_EQ(e.cause(), "sweep.preset nests deeper than 16 levels");
        }
    }
    std::string large = text;
    large.replace(at, marker.size(), "\"" + std::string(std::size_t(1) << 21, 'x') + "\"");
    write_text_file((dir / "results.json").string(), large);
    EXPECT_THROW(read_results_json((dir / "results.json").string(), info, cases), Error);
    // The real `eval --replot` on a 44 KB file nested 22000 deep: one line, bounded memory.
    std::string deep;
    for (int i = 0; i < 22000; ++i) deep += "[";
    for (int i = 0; i < 22000; ++i) deep += "]";
    std::string hostile = text;
    hostile.replace(at, marker.size(), deep);
    fs::create_directories(dir / "replot");
    write_text_file((dir / "replot" / "results.json").string(), hostile);
    const test::RunResult r = test::run_leanfade_bounded(
        "eval --replot " + test::shell_quote((dir / "replot").string()), dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("sweep.preset nests deeper than 16 levels"), std::string::npos) << r.err;
    EXPECT_LT(r.max_rss_kib, leanfade::test::memory_bound_kib(512 * 1024));
}

TEST(ResultsFiles, ReportWithPlots) {
    const fs::path dir = results_folder("report");
    CaseImages images;
    images.shininess = 128.0f;
    images.distance = 2.0f;
    images.reference = Image(8, 8, 3, 0.5f);
    images.techniques = {{Technique::Bump, Image(8, 8, 3, 0.2f)},
                         {Technique::Lean, Image(8, 8, 3, 0.4f)}};
    const std::vector<std::string> notes =
        write_report(dir.string(), sample_info(), sample_cases(), {images});
    EXPECT_TRUE(notes.empty()) << notes.front();
    for (const char* f : {"results.csv", "results.json", "index.html", "plot_data.tsv", "plots.gp",
                          "energy.png", "rmse.png", "ssim.png", "flicker.png",
                          "images/s128_d2_reference.png", "images/s128_d2_lean.png"})
        EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
    const std::string html = slurp(dir / "index.html");
    EXPECT_NE(html.find("<img src=\"energy.png\""), std::string::npos);
    EXPECT_NE(html.find("images/s128_d2_lean.png"), std::string::npos);
    EXPECT_NE(html.find("1.5*"), std::string::npos) << "unconverged cases are flagged";
}

TEST(ResultsFiles, WithoutGnuplotTheDataIsWrittenAndTheReportSaysSo) {
    const fs::path dir = results_folder("report_no_gnuplot");
    const char* old = std::getenv("PATH");
    const std::string saved = old ? old : "";
    ::setenv("PATH", "/nonexistent", 1);
    std::vector<std::string> notes;
    EXPECT_NO_THROW(notes = write_report(dir.string(), sample_info(), sample_cases(), {}));
    ::setenv("PATH", saved.c_str(), 1);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("gnuplot not found"), std::string::npos) << notes[0];
    EXPECT_TRUE(fs::is_regular_file(dir / "plot_data.tsv"));
    EXPECT_TRUE(fs::is_regular_file(dir / "plots.gp"));
    EXPECT_FALSE(fs::exists(dir / "energy.png"));
    EXPECT_NE(slurp(dir / "index.html").find("gnuplot not found"), std::string::npos);
}

}  // namespace
}  // namespace leanfade::eval

namespace leanfade::eval {
namespace {

CaseResult seed_case(double specular, double reference, double total, double reference_total,
                     int pixels) {
    CaseResult c;
    c.technique = Technique::Lean;
    c.distance = 8.0f;
    c.shininess = 1024.0f;
    c.specular_mean = specular;
    c.reference_specular_mean = reference;
    c.object_pixels = pixels;
    c.energy = specular / reference;
    c.specular_total = total;
    c.reference_specular_total = reference_total;
    c.energy_total = total / reference_total;
    c.rmse = 0.1;
    c.ssim = 0.9;
    c.flicker = 1.5;
    return c;
}

TEST(CombineSeeds, RatiosOfSumsOverTheMapsWithTheirSpread) {
    // Two maps: one with a bright glint (reference 4, LEAN 2), one dim (reference 1, LEAN 1.5).
    // The ratio of sums is (2 + 1.5) / (4 + 1) = 0.7, not the mean of the ratios (1.0).
    const std::vector<std::vector<CaseResult>> sweeps{{seed_case(0.2, 0.4, 2.0, 4.0, 100)},
                                                      {seed_case(0.15, 0.1, 1.5, 1.0, 100)}};
    const std::vector<CaseResult> combined = combine_seeds(sweeps);
    ASSERT_EQ(combined.size(), 1u);
    const CaseResult& c = combined[0];
    EXPECT_EQ(c.seeds, 2);
    EXPECT_NEAR(c.energy_total, 0.7, 1e-12);
    EXPECT_NEAR(c.energy, 0.7, 1e-12);
    // Standard deviation of 0.5 and 1.5.
    EXPECT_NEAR(c.energy_total_spread, std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(c.energy_spread, std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(c.rmse, 0.1, 1e-12);
    // Masked sums weigh each map by its object pixels.
    const std::vector<CaseResult> weighted =
        combine_seeds({{seed_case(0.2, 0.4, 2.0, 4.0, 300)}, {seed_case(0.15, 0.1, 1.5, 1.0, 100)}});
    EXPECT_NEAR(weighted[0].energy, (0.2 * 300 + 0.15 * 100) / (0.4 * 300 + 0.1 * 100), 1e-12);
    // One map: unchanged but for the count.
    EXPECT_EQ(combine_seeds({sweeps[0]})[0].energy_total_spread, 0.0);
    // Sweeps of different cases are refused.
    std::vector<std::vector<CaseResult>> mismatched = sweeps;
    mismatched[1][0].distance = 16.0f;
    EXPECT_THROW(combine_seeds(mismatched), Error);
    EXPECT_THROW(combine_seeds({}), Error);
}

}  // namespace
}  // namespace leanfade::eval
