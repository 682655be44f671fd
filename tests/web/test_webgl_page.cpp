// The WebGL2 example page (examples/web) as a browser runs it: headless Chromium (SwiftShader's
// WebGL2) loads the page with a LEAN map baked as half floats (`bake --bits 16f`, Zstandard-
// supercompressed as bake writes by default), its plateau
// layer (`--plateau-out`) and the GLSL ES shaders (`shaders --lang glsl-es`); the page draws
// bump, LEAN and two-lobe LEAN with plain WebGL2 and LEAN through its three.js material into a
// float target and posts the linear floats back (examples/web/serve.mjs --capture). Each is
// compared with `leanfade render`'s cell of the same view, as the figures are converted. And
// the filtered glTF of `bake SCENE -o OUT.glb` in three.js's GLTFLoader (examples/web/gltf.html).
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <utility>
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

const std::vector<std::string> kWebGlCells = {"bump@3",  "lean@3",  "two-lobe@3",  "three-lean@3",
                                         "bump@12", "lean@12", "two-lobe@12", "three-lean@12"};

class WebGlPage : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        capture_ = new PageCapture(capture_page("webgl_page", "index.html",
                                                "--lang glsl-es -o DATA/shaders", kWebGlCells));
    }
    static void TearDownTestSuite() { delete capture_; }
    void SetUp() override {
        ASSERT_TRUE(fs::exists(fs::path(LEANFADE_WEB_EXAMPLE) / "node_modules" / "three"))
            << "three.js is missing: npm ci in examples/web (scripts/install-deps.sh does it)";
        expect_page_ran(*capture_);
    }
    static PageCapture* capture_;
};

PageCapture* WebGlPage::capture_ = nullptr;

// The tolerance: over the object, RMSE <= 2 8-bit codes, and at most 0.5 % of the cell's pixels
// more than 8 codes apart (measured: 1.6 and 0.07 % at 3 radii, 0.4 and 0 at 12; the Vulkan
// consumer on lavapipe, which shares llvmpipe's rasteriser and sampler, agrees to 0.1). SwiftShader
// and llvmpipe rasterise and filter with their own arithmetic: a silhouette pixel one covers and
// the other does not differs by the whole object colour (the largest differences, ~146 codes, on
// about ten pixels of a cell), and each computes a pixel's texture LOD from the uv derivatives
// with its own approximation, which shifts a glint's texels by a fraction of a level (9-19 codes
// on a handful of pixels in the highlight).
TEST_F(WebGlPage, DrawsTheViewsAsLeanfadeRenderInHeadlessChromium) {
    expect_cells_match_render(*capture_, "webgl2", kWebGlCells, "webgl_figures.txt");
}

// The techniques differ on the page as they do in leanfade render: the captures are not one
// picture drawn three times (LEAN's filtered highlight against bump mapping's, far away).
TEST_F(WebGlPage, TheTechniquesDrawDifferentPictures) {
    const Image bump = read_capture(capture_->folder / "capture" / "bump_d12.f32");
    const Image lean = read_capture(capture_->folder / "capture" / "lean_d12.f32");
    ASSERT_FALSE(bump.empty());
    ASSERT_FALSE(lean.empty());
    const CellComparison c = compare_cells(bump, lean);
    EXPECT_GT(c.object_rmse, 2.0);
}

// A glTF plane of 8 x 8 world units, its uv tiled 24 times, with a normal texture (a normal map
// of the built-in bumps), smooth (roughnessFactor 0.1) and not metallic.
void write_plane_gltf(const fs::path& gltf, const std::string& normal_png) {
    const float s = 4.0f, t = 24.0f;
    const float positions[] = {-s, 0, s, s, 0, s, s, 0, -s, -s, 0, -s};
    const float normals[] = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
    const float uvs[] = {0, t, t, t, t, 0, 0, 0};
    const std::uint32_t indices[] = {0, 1, 2, 0, 2, 3};
    std::string bytes;
    for (const auto& [data, size] : {std::pair{static_cast<const void*>(positions), sizeof positions},
                                     std::pair{static_cast<const void*>(normals), sizeof normals},
                                     std::pair{static_cast<const void*>(uvs), sizeof uvs},
                                     std::pair{static_cast<const void*>(indices), sizeof indices}})
        bytes.append(static_cast<const char*>(data), size);
    std::ofstream(gltf.parent_path() / "plane.bin", std::ios::binary) << bytes;
    const nlohmann::json j = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}, {"name", "plane"}}}},
        {"meshes",
         {{{"primitives",
            {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
              {"indices", 3},
              {"material", 0}}}}}}},
        {"materials",
         {{{"name", "bumps"},
           {"pbrMetallicRoughness",
            {{"baseColorFactor", {0.6, 0.6, 0.65, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.1}}},
           {"normalTexture", {{"index", 0}}}}}},
        {"textures", {{{"source", 0}, {"sampler", 0}}}},
        {"samplers", {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}}}},
        {"images", {{{"uri", normal_png}}}},
        {"buffers", {{{"byteLength", bytes.size()}, {"uri", "plane.bin"}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
          {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 48}},
          {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
          {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 24}}}},
        {"accessors",
         {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
           {"min", {-s, 0.0f, -s}}, {"max", {s, 0.0f, s}}},
          {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
          {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
          {{"bufferView", 3}, {"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}}}};
    std::ofstream(gltf) << j.dump(1);
}

// The filtered glTF of `bake SCENE -o OUT.glb` in three.js (examples/web/gltf.html): GLTFLoader
// with KTX2Loader takes every level of leanfade's roughness and normal KTX2 files (and makes no
// MIPs of its own); without KTX2Loader it takes the PNG fallbacks and makes its MIPs.
TEST(WebGltf, ThreeJsLoadsEveryLevelOfTheFilteredGltf) {
    const fs::path s = fresh_scratch_folder(".", "webgl_gltf");
    const fs::path site = s / "site";
    fs::create_directories(site);
    fs::create_directories(s / "capture");
    ASSERT_NE(std::string(LEANFADE_CHROMIUM).find('/'), std::string::npos) << "Chromium is missing";
    // The normal map: level 0 of the normal MIPs of the built-in bumps.
    const RunResult normal = run_leanfade(
        "bake --builtin bumps --size 128 -o " + shell_quote(s / "b.ktx2") + " --roughness-out " +
            shell_quote(s / "r.ktx2") + " --roughness-levels",
        s);
    ASSERT_EQ(normal.exit_code, 0) << normal.err;
    fs::copy_file(s / "r.levels" / "normal_mip0.png", s / "normal.png");
    write_plane_gltf(s / "plane.gltf", "normal.png");
    const RunResult bake = run_leanfade(
        "bake " + shell_quote(s / "plane.gltf") + " -o " + shell_quote(site / "plane.glb"), s);
    ASSERT_EQ(bake.exit_code, 0) << bake.err;
    const std::string command =
        shell_quote(LEANFADE_NODE) + " " +
        shell_quote((fs::path(LEANFADE_WEB_EXAMPLE) / "serve.mjs").string()) + " --data " +
        shell_quote(site.string()) + " --capture " + shell_quote((s / "capture").string()) +
        " --browser " + shell_quote(LEANFADE_CHROMIUM) +
        " --page gltf.html --scene plane.glb --size 128 --timeout 240 >" +
        shell_quote((s / "serve.log").string()) + " 2>&1 </dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << read_text(s / "serve.log");
    const nlohmann::json report = nlohmann::json::parse(read_text(s / "capture" / "done.json"));
    EXPECT_TRUE(report["errors"].empty()) << report.dump();
    ASSERT_EQ(report["report"].size(), 1u) << report.dump();
    const nlohmann::json& m = report["report"][0];
    for (const char* map : {"roughness", "normal"}) {
        const nlohmann::json& ktx2 = m["ktx2"][map];
        // KTX2Loader transcodes leanfade's Basis Universal UASTC (bake's default for a glTF)
        // to a format the GPU has, every level of the file.
        EXPECT_EQ(ktx2["kind"], "compressed") << map;
        EXPECT_EQ(ktx2["width"], 128) << map;
        EXPECT_EQ(ktx2["levels"], 8) << map << ": every level of the file";
        EXPECT_EQ(ktx2["generateMipmaps"], false) << map;
        const nlohmann::json& png = m["png"][map];
        EXPECT_EQ(png["kind"], "image") << map;
        EXPECT_EQ(png["levels"], 0) << map;
        EXPECT_EQ(png["generateMipmaps"], true) << map;
    }
    EXPECT_TRUE(m["ktx2"]["anisotropy"].is_null()) << "the bumps are isotropic";
}

// Before: one request with a bad % escape ("/%") or the path "//" threw out of the request handler
// and ended the server, so any page open in the same browser could end a `make web` session.
// Each malformed request is answered 400 and the server keeps serving.
TEST(WebServer, MalformedRequestsGet400AndTheServerKeepsServing) {
    const fs::path s = scratch_folder_for_this_selection("web_server");
    fs::create_directories(s / "data");
    const std::vector<std::pair<std::string, std::string>> expected = {
        {"/%", "400"},        {"/%E0%A4%A", "400"}, {"//", "400"},
        {"//host/x", "400"},  {"/data/%00", "400"}, {"http://x/index.html", "400"},
        {"/", "200"},         {"/index.html", "200"}, {"/../../etc/passwd", "404"},
        {"/%2e%2e/%2e%2e/etc/passwd", "404"}};
    nlohmann::json targets = nlohmann::json::array();
    for (const auto& [target, status] : expected) targets.push_back(target);
    const std::string command =
        "TARGETS=" + shell_quote(targets.dump()) + " " + shell_quote(LEANFADE_NODE) + " " +
        shell_quote(std::string(LEANFADE_WEB_TESTS) + "/serve_requests.mjs") + " " +
        shell_quote((fs::path(LEANFADE_WEB_EXAMPLE) / "serve.mjs").string()) + " " +
        shell_quote((s / "data").string()) + " >" + shell_quote((s / "replies.json").string()) +
        " 2>" + shell_quote((s / "stderr.txt").string()) + " </dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << read_text(s / "stderr.txt");
    const nlohmann::json replies = nlohmann::json::parse(read_text(s / "replies.json"));
    for (const auto& [target, status] : expected) {
        ASSERT_TRUE(replies.contains(target)) << target;
        EXPECT_EQ(replies[target].get<std::string>().substr(0, 12), "HTTP/1.1 " + status)
            << target << ": " << replies[target];
    }
    EXPECT_TRUE(replies["alive"].get<bool>()) << "serve.mjs ended";
}

}  // namespace
}  // namespace leanfade::test
