// The frame benchmark's protocol with tiny sizes: every technique in every round (interleaved,
// rotated), the fill view covering every pixel, per-view statistics and paired ratios.
#include <algorithm>
#include <cmath>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/frame_bench.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::test {
namespace {

class FrameBench : public GlTest {
  protected:
    void SetUp() override {
        renderer_ = std::make_unique<gl::Renderer>(context());
        renderer_->set_lean_map(make_bumps_map(64));
        for (const char* name : {"sphere", "torus"})
            meshes_.push_back(scene::make_scene_mesh(name));
    }
    void TearDown() override {
        renderer_.reset();
        GlTest::TearDown();
    }
    std::vector<gl::FrameBenchScene> scenes() const {
        return {{"sphere", &meshes_[0]}, {"torus", &meshes_[1]}};
    }
    static gl::FrameBenchRequest tiny_request() {
        gl::FrameBenchRequest r;
        r.width = 64;
        r.height = 48;
        r.frames = 4;
        r.warmup = 1;
        r.distances = {3.0f, 24.0f};
        r.timing = gl::TimingMethod::Cpu;
        return r;
    }
    std::unique_ptr<gl::Renderer> renderer_;
    std::vector<scene::Mesh> meshes_;
};

TEST_F(FrameBench, InterleavesEveryTechniqueInEveryRound) {
    gl::FrameBenchRequest request = tiny_request();
    request.techniques = {gl::Technique::Bump, gl::Technique::Lean, gl::Technique::Fade};
    int progress_calls = 0;
    const gl::FrameBenchResult result =
        gl::run_frame_bench(*renderer_, scenes(), request, [&](int done, int total) {
            ++progress_calls;
            EXPECT_EQ(total, 6);
            EXPECT_EQ(done, progress_calls);
        });
    EXPECT_EQ(progress_calls, 6);
    EXPECT_EQ(result.timing.method, gl::TimingMethod::Cpu);
    EXPECT_FALSE(result.gl_renderer.empty());
    ASSERT_EQ(result.scenes.size(), 2u);
    EXPECT_EQ(result.scenes[0].triangles, meshes_[0].triangle_count());
    for (const gl::SceneResult& scene : result.scenes) {
        ASSERT_EQ(scene.views.size(), 3u);
        EXPECT_EQ(scene.views[0].name, "fill");
        EXPECT_EQ(scene.views[1].name, "d3");
        EXPECT_EQ(scene.views[2].name, "d24");
        for (const gl::ViewResult& view : scene.views) {
            ASSERT_EQ(view.timings.size(), 4u) << scene.name << " " << view.name;
            EXPECT_EQ(view.timings[0].name, gl::kFloorName);
            EXPECT_EQ(view.timings[1].name, "bump");
            EXPECT_EQ(view.timings[3].name, "fade");
            ASSERT_EQ(view.order.size(), 4u);
            for (std::size_t round = 0; round < view.order.size(); ++round) {
                std::vector<int> drawn = view.order[round];
                ASSERT_EQ(drawn.size(), 4u);
                // Rotated by one each round, so that no technique always runs first.
                if (round > 0) {
                    EXPECT_EQ(drawn[0], (view.order[round - 1][0] + 1) % 4);
                }
                std::sort(drawn.begin(), drawn.end());
                EXPECT_EQ(drawn, (std::vector<int>{0, 1, 2, 3})) << "round " << round;
            }
            for (const gl::TechniqueTiming& t : view.timings) {
                ASSERT_EQ(t.frame_ms.size(), 4u);
                for (double ms : t.frame_ms) EXPECT_GT(ms, 0.0) << t.name;
                EXPECT_EQ(t.stats.count, 4);
                EXPECT_LE(t.stats.min, t.stats.median);
                EXPECT_LE(t.stats.median, t.stats.max);
                EXPECT_NEAR(t.fps, 1000.0 / t.stats.median, 1e-9);
            }
            const double r = view.ratio(gl::Technique::Lean, gl::Technique::Bump);
            EXPECT_TRUE(std::isfinite(r) && r > 0.0) << r;
            // A technique that was not measured has no ratio; each timing knows its technique.
            EXPECT_EQ(view.ratio(gl::Technique::Lean, gl::Technique::Toksvig), 0.0);
            EXPECT_EQ(view.find(gl::Technique::Toksvig), nullptr);
            ASSERT_NE(view.floor(), nullptr);
            EXPECT_EQ(view.floor()->name, gl::kFloorName);
            EXPECT_EQ(view.find(gl::Technique::Fade)->name, "fade");
        }
        EXPECT_DOUBLE_EQ(scene.views[0].coverage, 1.0) << scene.name << ": the fill view";
        EXPECT_LT(scene.views[2].coverage, 0.2) << scene.name << ": far away";
        EXPECT_LT(scene.views[0].fov_y_degrees, gl::kDefaultFovYDegrees);
        EXPECT_FLOAT_EQ(scene.views[1].fov_y_degrees, gl::kDefaultFovYDegrees);
        EXPECT_NEAR(scene.views[2].distance, 24.0f, 1e-4f);
    }
}

// Shading every pixel with LEAN costs more than writing a constant colour: the CPU timings are
// ordered sensibly (on llvmpipe the ratio is several times; any driver gives more than 1).
TEST_F(FrameBench, LeanCostsMoreThanTheFloorWhenFillingTheScreen) {
    gl::FrameBenchRequest request = tiny_request();
    request.width = 256;
    request.height = 192;
    request.frames = 5;
    request.distances = {};
    request.techniques = {gl::Technique::Lean};
    const gl::FrameBenchResult result = gl::run_frame_bench(*renderer_, {scenes()[0]}, request);
    const gl::ViewResult& fill = result.scenes[0].views[0];
    EXPECT_GT(fill.ratio_to_floor(gl::Technique::Lean), 1.0);
}

TEST_F(FrameBench, ForcedGpuTimingRunsAndGivesFiniteNumbers) {
    gl::FrameBenchRequest request = tiny_request();
    request.timing = gl::TimingMethod::Gpu;
    if (gl::time_elapsed_counter_bits() <= 0) {  // a driver without timer queries refuses
        EXPECT_THROW(gl::run_frame_bench(*renderer_, {scenes()[1]}, request), Error);
        return;
    }
    request.frames = 2;
    request.distances = {8.0f};
    const gl::FrameBenchResult result = gl::run_frame_bench(*renderer_, {scenes()[1]}, request);
    EXPECT_EQ(result.timing.method, gl::TimingMethod::Gpu);
    for (const gl::ViewResult& view : result.scenes[0].views)
        for (const gl::TechniqueTiming& t : view.timings)
            for (double ms : t.frame_ms) EXPECT_TRUE(std::isfinite(ms) && ms >= 0.0) << t.name;
}

TEST_F(FrameBench, InvalidRequestsNameTheSetting) {
    // The library names settings; `leanfade bench` prints them as flags (tests/bench/test_cli_bench.cpp).
    auto expect_setting = [&](gl::FrameBenchRequest request, const std::string& setting) {
        try {
            gl::run_frame_bench(*renderer_, scenes(), request);
            ADD_FAILURE() << "no error for " << setting;
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), setting) << e.what();
        }
    };
    gl::FrameBenchRequest r = tiny_request();
    r.techniques = {gl::Technique::Reference};
    expect_setting(r, "techniques");
    r = tiny_request();
    r.frames = 0;
    expect_setting(r, "frames");
    r = tiny_request();
    r.warmup = -1;
    expect_setting(r, "warmup");
    r = tiny_request();
    r.width = 8;
    expect_setting(r, "size");
    r = tiny_request();
    r.distances = {0.5f};
    expect_setting(r, "distances");
    r = tiny_request();
    r.settings.shininess = -1.0f;
    expect_setting(r, "shininess");
    EXPECT_THROW(gl::run_frame_bench(*renderer_, {}, tiny_request()), Error);
}

TEST_F(FrameBench, DrawRefusesTheReference) {
    renderer_->set_mesh(meshes_[0]);
    gl::RenderRequest r;
    r.technique = gl::Technique::Reference;
    EXPECT_THROW(renderer_->draw(r, 0), Error);
}

}  // namespace
}  // namespace leanfade::test
