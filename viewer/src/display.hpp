#pragma once
// GL pieces of the viewer's window: the per-pane canvases the renderer draws into, the pass that
// shows them (linear radiance -> sRGB, scaled to the pane), and the frame timers.
#include <array>
#include <optional>
#include <string>

#include "leanfade/gl/detail/objects.hpp"

namespace leanfade::viewer {

// A linear float image (RGBA16F) of one pane at the internal resolution, with what it shows.
class Canvas {
  public:
    // Reallocates when the size changes (the contents are then lost: key() is cleared).
    void ensure(int width, int height);
    GLuint framebuffer() const { return framebuffer_.get(); }
    GLuint texture() const { return color_.get(); }
    int width() const { return width_; }
    int height() const { return height_; }

    // Description of the parameters the contents were rendered with ("" = nothing valid).
    std::string key;

  private:
    gl::Texture color_;
    gl::Framebuffer framebuffer_;
    int width_ = 0, height_ = 0;
};

// Draws a canvas into a rectangle of the bound framebuffer, sRGB-encoded, bilinearly scaled.
class Presenter {
  public:
    Presenter();  // compiles its program; throws leanfade::Error on a compile error
    // (x, y, width, height): the destination in GL window coordinates (lower-left origin); the
    // scissor rectangle limits what is drawn (the split view's halves).
    void draw(const Canvas& canvas, int x, int y, int width, int height, int scissor_x,
              int scissor_width) const;

  private:
    gl::Program program_;
    gl::VertexArray vertex_array_;
};

// Time of one pane's rendering: GPU timer queries (GL_TIME_ELAPSED, read a few frames later,
// never stalling) or CPU time bracketed by glFinish (software renderers, where timer queries
// under-report). Smoothed over recent frames.
class PaneTimer {
  public:
    enum class Mode { Gpu, Cpu };
    void begin(Mode mode);
    void end();
    // Milliseconds, smoothed; empty before the first result.
    std::optional<double> milliseconds() const { return smoothed_; }
    // Forgets the measurements; the next one is dropped too (it may include shader compilation).
    void reset() {
        smoothed_.reset();
        skip_ = 1;
    }
    // Collects the GPU results that have arrived (call once a frame).
    void poll();

  private:
    void add(double ms);

    static constexpr int kQueries = 4;
    std::array<gl::Query, kQueries> queries_;
    std::array<bool, kQueries> pending_{};
    int current_ = -1;  // query of the running measurement, -1 when none
    int next_ = 0;
    Mode mode_ = Mode::Gpu;
    double cpu_start_ = 0.0;
    std::optional<double> smoothed_;
    int skip_ = 1;  // measurements still to drop
};

// Monotonic seconds.
double now_seconds();

}  // namespace leanfade::viewer
