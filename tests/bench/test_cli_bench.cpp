// `leanfade bench` as a user runs it, with tiny sizes: the tables, the JSON and its documented
// keys (ratios per scene), --bake, --generate, and one-line errors for bad flags.

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "gl_test_helpers.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

RunResult run_bench(const std::string& args, const fs::path& dir) {
    return run_leanfade_in("bench " + args, dir, dir);
}

std::size_t lines(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

bool positive_number(const nlohmann::json& j) {
    return j.is_number() && std::isfinite(j.get<double>()) && j.get<double>() > 0.0;
}

TEST(CliBench, PrintsTheTablesAndWritesTheDocumentedJson) {
    const fs::path dir = scratch_dir("cli_bench");
    const RunResult r = run_bench(
        "--size 48x32 --frames 2 --warmup 1 --scenes sphere,torus --distances 3,24 "
        "--texture-size 64 --timing cpu --json frames.json",
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << "no progress line when stderr is not a terminal: " << r.err;
    for (const char* text : {"GL: ", "Timing: glFinish", "LEAN Fig. 12 layout", "Overhead ratios",
                             "lean/bump", "fade/lean", "lean/floor", "sphere", "torus", "d24"})
        EXPECT_NE(r.out.find(text), std::string::npos) << text << " missing from:\n" << r.out;

    const nlohmann::json j = nlohmann::json::parse(read_text(dir / "frames.json"));
    EXPECT_EQ(j.at("tool"), "leanfade bench");
    const nlohmann::json& system = j.at("system");
    for (const char* key : {"date", "cpu", "gl_renderer", "gl_version", "timing",
                            "timing_description", "load_average"})
        EXPECT_TRUE(system.contains(key)) << key;
    EXPECT_EQ(system.at("timing"), "cpu");
    const nlohmann::json& frames = j.at("frames");
    EXPECT_EQ(frames.at("size"), nlohmann::json({48, 32}));
    EXPECT_EQ(frames.at("frames"), 2);
    for (const char* scene : {"sphere", "torus"}) {
        SCOPED_TRACE(scene);
        const nlohmann::json& s = frames.at("scenes").at(scene);
        EXPECT_EQ(s.at("ratios_view"), "fill");
        for (const char* ratio :
             {"lean/bump", "fade/lean", "lean/floor", "bump/floor", "fade/floor"})
            EXPECT_TRUE(positive_number(s.at("ratios").at(ratio))) << ratio;
        for (const char* view : {"fill", "d3", "d24"}) {
            const nlohmann::json& v = s.at("views").at(view);
            EXPECT_TRUE(v.contains("coverage") && v.contains("fov_y_degrees"));
            for (const char* technique : {"floor", "bump", "lean", "fade"}) {
                const nlohmann::json& t = v.at("techniques").at(technique);
                EXPECT_TRUE(positive_number(t.at("median_ms"))) << view << " " << technique;
                EXPECT_TRUE(positive_number(t.at("fps")));
                EXPECT_EQ(t.at("frame_ms").size(), 2u);
                for (const char* key : {"p25_ms", "p75_ms", "min_ms", "max_ms"})
                    EXPECT_TRUE(t.contains(key)) << key;
            }
        }
        EXPECT_DOUBLE_EQ(s.at("views").at("fill").at("coverage").get<double>(), 1.0);
    }
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

// --timing gpu runs the GL_TIME_ELAPSED path on any driver with timer counter bits; on llvmpipe the
// output says that the figures under-report.
TEST(CliBench, ForcedGpuTimingRunsAndSaysSo) {
    const fs::path dir = scratch_dir("cli_bench_gpu");
    const RunResult r = run_bench(
        "--timing gpu --size 32x32 --frames 2 --warmup 0 --scenes sphere --distances none "
        "--texture-size 16 --json gpu.json",
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("Timing: GL_TIME_ELAPSED"), std::string::npos) << r.out;
    const nlohmann::json j = nlohmann::json::parse(read_text(dir / "gpu.json"));
    EXPECT_EQ(j.at("system").at("timing"), "gpu");
    const std::string renderer = j.at("system").at("gl_renderer");
    if (renderer.find("llvmpipe") != std::string::npos) {
        EXPECT_NE(r.out.find("under-report"), std::string::npos) << r.out;
    }
    for (const auto& [name, t] :
         j.at("frames").at("scenes").at("sphere").at("views").at("fill").at("techniques").items())
        for (const nlohmann::json& ms : t.at("frame_ms"))
            EXPECT_TRUE(ms.is_number() && ms.get<double>() >= 0.0) << name;
}

TEST(CliBench, BakeAndGenerateModes) {
    const fs::path dir = scratch_dir("cli_bench_modes");
    const RunResult r = run_bench(
        "--bake --bake-sizes 32,64 --bake-runs 1 --generate --generate-sizes 16,32 --frames 2 "
        "--warmup 0 --json modes.json",
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("Bake throughput"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("copy bandwidth"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Per-frame LEAN map generation"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("LEAN Fig. 12"), std::string::npos) << "frames not measured here";
    const nlohmann::json j = nlohmann::json::parse(read_text(dir / "modes.json"));
    EXPECT_FALSE(j.contains("frames"));
    const nlohmann::json& bake = j.at("bake");
    EXPECT_TRUE(positive_number(bake.at("copy_bytes_per_second")));
    ASSERT_EQ(bake.at("rows").size(), 4u);  // normal and height inputs, two sizes each
    for (const nlohmann::json& row : bake.at("rows")) {
        EXPECT_TRUE(positive_number(row.at("megabytes_per_second")));
        EXPECT_TRUE(positive_number(row.at("texels_per_second")));
        EXPECT_TRUE(positive_number(row.at("floor_ratio")));
    }
    EXPECT_EQ(bake.at("rows")[1].at("size"), 64);
    EXPECT_EQ(bake.at("rows")[0].at("input"), "normal");
    EXPECT_EQ(bake.at("rows")[3].at("input"), "height");
    const nlohmann::json& generate = j.at("generate");
    ASSERT_EQ(generate.size(), 2u);
    EXPECT_EQ(generate[0].at("size"), 16);
    EXPECT_EQ(generate[0].at("storage"), "16");
    EXPECT_TRUE(positive_number(generate[1].at("total").at("median_ms")));
    EXPECT_TRUE(positive_number(generate[1].at("texels_per_second")));
}

// The LEAN paper's Fig. 12 columns: the five documented keys per scene, single LEAN the unit of
// the ratios, and the settings that say what was drawn (moving layers, the clock per frame).
TEST(CliBench, LayerColumnsWriteTheFiveColumns) {
    const fs::path dir = scratch_dir("cli_bench_fig12");
    const RunResult r = run_bench(
        "--layer-columns --scenes sphere --size 48x32 --frames 2 --warmup 1 --texture-size 32 "
        "--timing cpu --json fig12.json",
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("per-frame generation"), std::string::npos) << r.out;
    const nlohmann::json j = nlohmann::json::parse(read_text(dir / "fig12.json"));
    const nlohmann::json& sphere = j.at("fig12").at("sphere");
    for (const char* key : {"blinn_phong", "single_lean", "per_frame_generation",
                            "mixture_textures", "mixture_approximation"}) {
        const nlohmann::json& column = sphere.at(key);
        EXPECT_TRUE(positive_number(column.at("frame_ms"))) << key;
        EXPECT_TRUE(positive_number(column.at("fps"))) << key;
        EXPECT_TRUE(positive_number(column.at("ratio_to_single_lean"))) << key;
    }
    EXPECT_EQ(sphere.at("single_lean").at("ratio_to_single_lean"), 1.0);
    const nlohmann::json& settings = j.at("fig12_settings");
    EXPECT_EQ(settings.at("layers"), "bumps,noise");
    EXPECT_EQ(settings.at("layer_velocity"), "0.02:0,-0.01:0.03");
    EXPECT_TRUE(positive_number(settings.at("seconds_per_frame")));
}

TEST(CliBench, BadFlagsAreOneLineErrors) {
    const fs::path dir = scratch_dir("cli_bench_errors");
    const std::string cases[] = {
        "--techniques bump,phong",
        "--techniques reference",
        "--techniques lean,lean",
        "--frames 0",
        "--warmup -1",
        "--size 8x8",
        "--size wide",
        "--timing fast",
        "--scenes sphere,sphere",
        "--scenes cube",
        "--distances 3,0.5",
        "--bake --bake-sizes 2",
        "--bake --bake-input png",
        "--generate --generate-sizes 64,x",
        "--threads -1",
        "--bits 12",
        "--shininess -1",
        "--json missing-folder/out.json",
    };
    for (const std::string& args : cases) {
        std::string all = args;
        for (const std::string flag : {"--size 32x32", "--frames 1", "--warmup 0"})
            if (args.find(flag.substr(0, flag.find(' '))) == std::string::npos) all += " " + flag;
        const RunResult r = run_bench(all, dir);
        EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << args << ": " << r.err;
        EXPECT_NE(r.err.find("leanfade bench: "), std::string::npos) << args << ": " << r.err;
    }
    // CLI11 rejects a non-number itself, also in one line.
    const RunResult r = run_bench("--frames many", dir);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
}

}  // namespace
}  // namespace leanfade::test
