// The WebGPU example page (examples/web/webgpu.html) as a browser runs it: headless Chromium's
// WebGPU on SwiftShader draws bump, LEAN and two-lobe LEAN with the WGSL of
// `leanfade shaders --lang wgsl`, compared with `leanfade render`'s cells (page_capture.hpp). And
// the WGSL read by a parser independent of the translator that wrote it (wgsl_reflect).
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "leanfade/test/cell_comparison.hpp"
#include "leanfade/test/scratch.hpp"
#include "page_capture.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kWebGpuCells = {"bump@3",  "lean@3",  "two-lobe@3",
                                         "bump@12", "lean@12", "two-lobe@12"};

class WebGpuPage : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        capture_ = new PageCapture(
            capture_page("webgpu_page", "webgpu.html", "--lang wgsl -o DATA/wgsl", kWebGpuCells));
    }
    static void TearDownTestSuite() { delete capture_; }
    void SetUp() override {
        ASSERT_TRUE(fs::exists(fs::path(LEANFADE_NODE_TOOLS) / "node_modules" / "naga-wasm"))
            << "naga-wasm is missing: npm ci in tools/node (scripts/install-deps.sh does it)";
        expect_page_ran(*capture_);
    }
    static PageCapture* capture_;
};

PageCapture* WebGpuPage::capture_ = nullptr;

// The tolerance of the WebGL2 page (test_webgl_page.cpp): SwiftShader's Vulkan against llvmpipe,
// each with its own rasteriser and texture LOD (measured: RMSE 0.9 codes over a 3-radii cell, all
// of it ~10 silhouette pixels; 0.02-0.05 at 12 radii).
TEST_F(WebGpuPage, DrawsTheViewsAsLeanfadeRenderInHeadlessChromium) {
    expect_cells_match_render(*capture_, "webgpu", kWebGpuCells, "webgpu_figures.txt");
}

// Every exported WGSL file parses with wgsl_reflect; its entry point is the one shaders.json
// names, and its bindings are those of the reflection (textures at their units, samplers at
// sampler_binding_offset + the unit, blocks at uniform_block_binding_offset + their binding).
TEST_F(WebGpuPage, TheWgslParsesWithAnIndependentParserAndBindsAsReflected) {
    const fs::path wgsl = capture_->folder / "data" / "wgsl";
    const fs::path output = capture_->folder / "parsed.json";
    const std::string command =
        shell_quote(LEANFADE_NODE) + " " +
        shell_quote((fs::path(LEANFADE_WEB_TESTS) / "parse_wgsl.mjs").string()) + " " +
        shell_quote((fs::path(LEANFADE_NODE_TOOLS) / "node_modules" / "wgsl_reflect" /
                     "wgsl_reflect.module.js")
                        .string()) +
        " " + shell_quote(wgsl.string()) + " >" + shell_quote(output.string());
    ASSERT_EQ(std::system(command.c_str()), 0);
    const nlohmann::json parsed = nlohmann::json::parse(read_text(output));
    const nlohmann::json index = nlohmann::json::parse(read_text(wgsl / "shaders.json"));
    EXPECT_EQ(index["language"], "wgsl");
    std::size_t files = 0, omitted = 0;
    for (const nlohmann::json& s : index["shaders"]) {
        if (s.contains("omitted")) {
            ++omitted;
            continue;
        }
        ++files;
        const std::string file = s["file"];
        ASSERT_TRUE(parsed.contains(file)) << file;
        const nlohmann::json& p = parsed[file];
        ASSERT_FALSE(p.contains("error")) << file << ": " << p.dump();
        const std::string stage = s["stage"] == "vert" ? "vertex" : "fragment";
        EXPECT_EQ(p["entries"], nlohmann::json::array({stage + " main"})) << file;
        std::size_t resources = 0;
        for (const nlohmann::json& r : s["reflection"]["resources"]) {
            const std::string binding = std::to_string(r["binding"].get<int>());
            ASSERT_TRUE(p["bindings"].contains(binding)) << file << " binding " << binding;
            EXPECT_EQ(p["bindings"][binding]["group"], r["set"]) << file;
            if (r["descriptor_type"] != "uniform_buffer") {  // blocks lose their instance name
                EXPECT_EQ(p["bindings"][binding]["name"], r["name"]) << file;
            }
            ++resources;
        }
        EXPECT_EQ(p["bindings"].size(), resources) << file;
    }
    std::printf("wgsl: %zu files parsed by wgsl_reflect, %zu variants without a WGSL form\n",
                files, omitted);
    // The vertex stage and every technique's plain variant have a WGSL form.
    EXPECT_GE(files, 1u + 9u);
    for (const auto& [technique, variant] : index["defaults"]["variants"].items()) {
        bool found = false;
        for (const nlohmann::json& s : index["shaders"])
            if (s["variant"] == variant && !s.contains("omitted")) found = true;
        if (technique != "roughness") {
            EXPECT_TRUE(found) << technique << " (" << variant << ")";
        }
    }
}

}  // namespace
}  // namespace leanfade::test
