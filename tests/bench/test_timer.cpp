// Timing methods: names, the auto choice, both interval timers on this machine's driver, and the
// statistics of frame times.
#include <cmath>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/frame_bench.hpp"
#include "leanfade/gl/detail/timer.hpp"
#include "leanfade/scene/detail/scene.hpp"

namespace leanfade::test {
namespace {

TEST(Timing, NamesRoundTripAndBadNamesAreErrors) {
    for (gl::TimingMethod m : {gl::TimingMethod::Auto, gl::TimingMethod::Gpu, gl::TimingMethod::Cpu,
                               gl::TimingMethod::CpuTime})
        EXPECT_EQ(gl::parse_timing_method(gl::to_string(m)), m);
    try {
        gl::parse_timing_method("fast");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "timing") << e.what();  // the setting; the command line names --timing
    }
}

TEST(Timing, SoftwareRenderersAreRecognised) {
    EXPECT_TRUE(gl::is_software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
    EXPECT_TRUE(gl::is_software_renderer("softpipe"));
    EXPECT_TRUE(gl::is_software_renderer("Google SwiftShader"));
    EXPECT_FALSE(gl::is_software_renderer("NVIDIA GeForce RTX 4090/PCIe/SSE2"));
    EXPECT_FALSE(gl::is_software_renderer("AMD Radeon RX 7900 XTX (radeonsi, navi31)"));
}

TEST(SampleStats, MedianQuartilesAndExtremes) {
    const gl::SampleStats s = gl::sample_stats({5.0, 1.0, 4.0, 2.0, 3.0});
    EXPECT_EQ(s.count, 5);
    EXPECT_DOUBLE_EQ(s.median, 3.0);
    EXPECT_DOUBLE_EQ(s.p25, 2.0);
    EXPECT_DOUBLE_EQ(s.p75, 4.0);
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 5.0);
    EXPECT_DOUBLE_EQ(s.mean, 3.0);
    const gl::SampleStats even = gl::sample_stats({4.0, 1.0, 2.0, 3.0});
    EXPECT_DOUBLE_EQ(even.median, 2.5);
    EXPECT_DOUBLE_EQ(even.p25, 1.75);
    EXPECT_EQ(gl::sample_stats({}).count, 0);
}

class Timers : public GlTest {
  protected:
    void SetUp() override {
        renderer_ = std::make_unique<gl::Renderer>(context());
        renderer_->set_mesh(scene::make_scene_mesh("sphere"));
        renderer_->set_lean_map(make_bumps_map(64));
        target_ = gl::create_framebuffer();
        color_ = gl::create_renderbuffer();
        depth_ = gl::create_renderbuffer();
        glNamedRenderbufferStorage(color_.get(), GL_RGBA8, kSize, kSize);
        glNamedRenderbufferStorage(depth_.get(), GL_DEPTH_COMPONENT24, kSize, kSize);
        glNamedFramebufferRenderbuffer(target_.get(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                       color_.get());
        glNamedFramebufferRenderbuffer(target_.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                       depth_.get());
    }
    void TearDown() override {
        target_.reset();
        color_.reset();
        depth_.reset();
        renderer_.reset();
        GlTest::TearDown();
    }
    // `count` frames of LEAN with the sphere filling most of the framebuffer.
    void draw_frames(int count) {
        gl::RenderRequest r;
        r.technique = gl::Technique::Lean;
        r.width = kSize;
        r.height = kSize;
        r.view = gl::view_at_distance(1.8f);
        const float black[4] = {0, 0, 0, 0};
        const float one = 1.0f;
        for (int i = 0; i < count; ++i) {
            glClearNamedFramebufferfv(target_.get(), GL_COLOR, 0, black);
            glClearNamedFramebufferfv(target_.get(), GL_DEPTH, 0, &one);
            renderer_->draw(r, target_.get());
        }
    }
    static constexpr int kSize = 192;
    std::unique_ptr<gl::Renderer> renderer_;
    gl::Framebuffer target_;
    gl::Renderbuffer color_, depth_;
};

TEST_F(Timers, AutoPicksCpuTimingOnSoftwareRenderers) {
    const gl::TimingChoice choice = gl::choose_timing(gl::TimingMethod::Auto, context());
    if (gl::is_software_renderer(context().renderer())) {
        EXPECT_EQ(choice.method, gl::TimingMethod::Cpu);
        EXPECT_NE(choice.description.find("glFinish"), std::string::npos) << choice.description;
        EXPECT_NE(choice.description.find("under-report"), std::string::npos) << choice.description;
    } else if (gl::time_elapsed_counter_bits() > 0) {
        EXPECT_EQ(choice.method, gl::TimingMethod::Gpu);
    }
    EXPECT_EQ(gl::choose_timing(gl::TimingMethod::Cpu, context()).method, gl::TimingMethod::Cpu);
    EXPECT_EQ(gl::choose_timing(gl::TimingMethod::CpuTime, context()).method,
              gl::TimingMethod::CpuTime);
}

// Forcing GPU timing runs the GL_TIME_ELAPSED path on any driver with counter bits; on llvmpipe
// the numbers under-report but must be finite and non-negative, one per interval, in order.
TEST_F(Timers, ForcedGpuTimingGivesFiniteNumbers) {
    if (gl::time_elapsed_counter_bits() <= 0) {
        EXPECT_THROW(gl::choose_timing(gl::TimingMethod::Gpu, context()), Error);
        return;
    }
    const gl::TimingChoice choice = gl::choose_timing(gl::TimingMethod::Gpu, context());
    ASSERT_EQ(choice.method, gl::TimingMethod::Gpu);
    gl::IntervalTimer timer(choice.method);
    for (int round = 0; round < 2; ++round) {  // the query pool is reused
        for (int i = 0; i < 3; ++i) {
            timer.begin();
            draw_frames(1);
            timer.end();
        }
        const std::vector<double> ms = timer.collect();
        ASSERT_EQ(ms.size(), 3u);
        for (double v : ms) {
            EXPECT_TRUE(std::isfinite(v));
            EXPECT_GE(v, 0.0);
        }
    }
    EXPECT_TRUE(timer.collect().empty());
}

// The CPU methods' numbers are positive and ordered sensibly: five frames take longer than one
// (by the clock, and in CPU time: on llvmpipe the frames are rasterised by this process).
TEST_F(Timers, CpuTimingIsPositiveAndGrowsWithTheWork) {
    draw_frames(1);  // compile and warm up
    for (gl::TimingMethod method : {gl::TimingMethod::Cpu, gl::TimingMethod::CpuTime}) {
        SCOPED_TRACE(gl::to_string(method));
        gl::IntervalTimer timer(method);
        for (int i = 0; i < 3; ++i) {
            timer.begin();
            draw_frames(1);
            timer.end();
            timer.begin();
            draw_frames(5);
            timer.end();
        }
        const std::vector<double> ms = timer.collect();
        ASSERT_EQ(ms.size(), 6u);
        std::vector<double> one, five;
        for (std::size_t i = 0; i < ms.size(); ++i) {
            EXPECT_GT(ms[i], 0.0);
            (i % 2 == 0 ? one : five).push_back(ms[i]);
        }
        if (method == gl::TimingMethod::CpuTime && !gl::is_software_renderer(context().renderer()))
            continue;  // a GPU's work is not this process's CPU time
        EXPECT_GT(gl::sample_stats(five).median, gl::sample_stats(one).median)
            << "one frame " << gl::sample_stats(one).median << " ms, five "
            << gl::sample_stats(five).median << " ms";
    }
}

TEST_F(Timers, MisuseIsAnError) {
    EXPECT_THROW(gl::IntervalTimer(gl::TimingMethod::Auto), Error);
    gl::IntervalTimer timer(gl::TimingMethod::Cpu);
    EXPECT_THROW(timer.end(), Error);
    timer.begin();
    EXPECT_THROW(timer.begin(), Error);
    EXPECT_THROW(timer.collect(), Error);
    timer.end();
    EXPECT_EQ(timer.collect().size(), 1u);
}

}  // namespace
}  // namespace leanfade::test
