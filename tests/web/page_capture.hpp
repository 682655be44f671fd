#pragma once
// An example page of examples/web as a browser runs it: headless Chromium (SwiftShader's WebGL2
// and WebGPU) loads the page with a LEAN map baked as half floats (`bake --bits 16f`, Zstandard-
// supercompressed as bake writes by default), its plateau layer (`--plateau-out`) and the
// exported shaders; the page draws each cell ("technique@distance") into a float target and posts
// the linear floats back (examples/web/serve.mjs --capture). Each is compared with
// `leanfade render`'s cell of the same view, as the figures are converted.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/test/cell_comparison.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::test {

inline constexpr int kPageCellSize = 128;  // pixels of a cell, both sides

// A capture of the page: kPageCellSize² RGBA floats, rows bottom first (readPixels), as an RGB
// image with rows top first (io::read_image's order). Empty when the file has another size.
inline Image read_capture(const std::filesystem::path& file) {
    const int n = kPageCellSize;
    const std::string bytes = read_text(file);
    Image image(n, n, 3);
    if (bytes.size() != std::size_t(n) * n * 16) return Image();
    const auto* floats = reinterpret_cast<const float*>(bytes.data());
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c)
                image.pixels[image.index(x, n - 1 - y, c)] =
                    floats[(std::size_t(y) * n + std::size_t(x)) * 4 + std::size_t(c)];
    return image;
}

struct PageCapture {
    std::filesystem::path folder;  // data/, capture/, cells/ (leanfade render's)
    std::string setup;             // what failed while preparing or running the page
};

// Bakes the built-in bumps, exports the shaders (`shaders_args`, DATA standing for the data
// folder), renders the reference cells and runs `page` over `cells` in headless Chromium.
inline PageCapture capture_page(const std::string& name, const std::string& page,
                                std::string shaders_args, const std::vector<std::string>& cells) {
    namespace fs = std::filesystem;
    PageCapture out;
    out.folder = scratch_folder_for_this_selection(name);
    const fs::path& s = out.folder;
    const fs::path data = s / "data";
    fs::create_directories(data);
    fs::create_directories(s / "capture");
    auto run = [&](const std::string& args) {
        const RunResult r = run_leanfade(args, s);
        if (r.exit_code != 0) out.setup += "leanfade " + args + ": " + r.err;
    };
    run("bake --builtin bumps --size 128 --bits 16f -o " + shell_quote(data / "bumps.ktx2") +
        " --plateau-out " + shell_quote(data / "bumps.plateau.ktx2"));
    // The pages read `bake`'s default files: Zstandard-supercompressed levels.
    if (out.setup.empty() &&
        io::inspect_ktx2((data / "bumps.ktx2").string()).supercompression_scheme != 2)
        out.setup += "bumps.ktx2 is not Zstandard-supercompressed (bake's default)";
    const std::size_t at = shaders_args.find("DATA");
    if (at != std::string::npos) shaders_args.replace(at, 4, shell_quote(data.string()));
    run("shaders " + shaders_args);
    const std::string size = std::to_string(kPageCellSize);
    run("render --scene sphere --bumps " + shell_quote(data / "bumps.ktx2") +
        " --techniques bump,lean,two-lobe --distances 3,12 --size " + size + "x" + size +
        " --cells " + shell_quote(s / "cells") + " --cell-format pfm -o " +
        shell_quote(s / "figure.png"));
    if (!out.setup.empty()) return out;
    std::string list;
    for (const std::string& c : cells) list += (list.empty() ? "" : ",") + c;
    const fs::path log = s / "serve.log";
    const std::string command =
        shell_quote(LEANFADE_NODE) + " " +
        shell_quote((fs::path(LEANFADE_WEB_EXAMPLE) / "serve.mjs").string()) + " --data " +
        shell_quote(data.string()) + " --capture " + shell_quote((s / "capture").string()) +
        " --browser " + shell_quote(LEANFADE_CHROMIUM) + " --page " + page + " --cells " + list +
        " --size " + size + " --timeout 240 >" + shell_quote(log.string()) + " 2>&1 </dev/null";
    const int status = std::system(command.c_str());
    if (status != 0)
        out.setup += "serve.mjs --capture failed (" + std::to_string(status) +
                     "): " + read_text(log);
    return out;
}

// Node.js and Chromium are there, and the page ran without an error of its own.
inline void expect_page_ran(const PageCapture& capture) {
    ASSERT_NE(std::string(LEANFADE_NODE).find('/'), std::string::npos)
        << "Node.js is missing (scripts/install-deps.sh installs nodejs)";
    ASSERT_NE(std::string(LEANFADE_CHROMIUM).find('/'), std::string::npos)
        << "Chromium is missing (scripts/install-deps.sh installs chromium)";
    ASSERT_EQ(capture.setup, "");
}

// Every cell against leanfade render's: over the object, RMSE <= 2 8-bit codes, at most 0.5 % of
// the cell's pixels more than 8 codes apart, the sphere covering the cell's middle. Prints one
// line a cell (and writes them to LEANFADE_TEST_TMP/figures_file).
inline void expect_cells_match_render(const PageCapture& capture, const std::string& api,
                                      const std::vector<std::string>& cells,
                                      const std::string& figures_file) {
    namespace fs = std::filesystem;
    const nlohmann::json report =
        nlohmann::json::parse(read_text(capture.folder / "capture" / "done.json"));
    EXPECT_TRUE(report["errors"].empty()) << report.dump();
    // The implementation the page ran on (SwiftShader in headless Chromium without a GPU).
    const std::string renderer = report.value("renderer", "");
    EXPECT_FALSE(renderer.empty()) << report.dump();
    EXPECT_EQ(report.value("size", 0), kPageCellSize);
    std::string figures;
    for (const std::string& cell : cells) {
        const std::size_t at = cell.find('@');
        const std::string technique = cell.substr(0, at), distance = cell.substr(at + 1);
        const std::string drawn = technique + "_d" + distance;
        const std::string reference_technique =
            technique.rfind("three-", 0) == 0 ? technique.substr(6) : technique;
        const Image image = read_capture(capture.folder / "capture" / (drawn + ".f32"));
        ASSERT_FALSE(image.empty()) << "no capture of " << cell;
        const Image reference = io::read_image(
            (capture.folder / "cells" / (reference_technique + "_d" + distance + ".pfm"))
                .string());
        const CellComparison c = compare_cells(image, reference);
        char line[400];
        std::snprintf(line, sizeof line,
                      "%s %-10s d=%-3s on %s: vs leanfade render: RMSE %.3f 8-bit codes "
                      "over the object (%.1f%% of the cell), %.3f over the cell, %.2f%% of "
                      "pixels > 8 codes, max %d\n",
                      api.c_str(), technique.c_str(), distance.c_str(), renderer.c_str(),
                      c.object_rmse, 100.0 * c.covered, c.rmse, 100.0 * c.far_fraction,
                      c.max_difference);
        std::fputs(line, stdout);
        figures += line;
        EXPECT_LE(c.object_rmse, 2.0) << cell;
        EXPECT_LE(c.far_fraction, 0.005) << cell;
        // Not a comparison of two empty images: the sphere covers the cell's middle.
        EXPECT_GT(c.covered, distance == "3" ? 0.25 : 0.01) << cell;
    }
    std::ofstream(fs::path(LEANFADE_TEST_TMP) / figures_file) << figures;
}

}  // namespace leanfade::test
