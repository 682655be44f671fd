// Canvases, the sRGB display pass and the frame timers of the viewer.
#include "display.hpp"

#include <chrono>
#include <string>

#include "leanfade/core/error.hpp"

namespace leanfade::viewer {
namespace {

// A triangle covering the viewport; v_uv spans [0, 1] over it.
constexpr const char* kVertexShader = R"(#version 450 core
out vec2 v_uv;
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    v_uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// Linear radiance -> display: clamped to [0, 1], sRGB transfer function (as gl::encode_srgb).
constexpr const char* kFragmentShader = R"(#version 450 core
layout(binding = 0) uniform sampler2D u_image;
in vec2 v_uv;
out vec4 o_color;
float encode(float x) {
    x = clamp(x, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}
void main() {
    vec3 c = texture(u_image, v_uv).rgb;
    o_color = vec4(encode(c.r), encode(c.g), encode(c.b), 1.0);
}
)";

gl::Shader compile(GLenum stage, const char* source, const char* name) {
    gl::Shader shader(glCreateShader(stage));
    glShaderSource(shader.get(), 1, &source, nullptr);
    glCompileShader(shader.get());
    GLint ok = 0;
    glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader.get(), GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(length > 0 ? length : 1), '\0');
        glGetShaderInfoLog(shader.get(), GLsizei(log.size()), nullptr, log.data());
        throw Error(name, "does not compile: " + log);
    }
    return shader;
}

}  // namespace

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

void Canvas::ensure(int width, int height) {
    if (color_ && width == width_ && height == height_) return;
    color_ = gl::create_texture(GL_TEXTURE_2D);
    glTextureStorage2D(color_.get(), 1, GL_RGBA16F, width, height);
    glTextureParameteri(color_.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(color_.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(color_.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(color_.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    framebuffer_ = gl::create_framebuffer();
    glNamedFramebufferTexture(framebuffer_.get(), GL_COLOR_ATTACHMENT0, color_.get(), 0);
    const float clear[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    glClearNamedFramebufferfv(framebuffer_.get(), GL_COLOR, 0, clear);
    width_ = width;
    height_ = height;
    key.clear();
}

Presenter::Presenter() {
    const gl::Shader vertex = compile(GL_VERTEX_SHADER, kVertexShader, "viewer display.vert");
    const gl::Shader fragment = compile(GL_FRAGMENT_SHADER, kFragmentShader, "viewer display.frag");
    program_ = gl::Program(glCreateProgram());
    glAttachShader(program_.get(), vertex.get());
    glAttachShader(program_.get(), fragment.get());
    glLinkProgram(program_.get());
    GLint ok = 0;
    glGetProgramiv(program_.get(), GL_LINK_STATUS, &ok);
    if (!ok) throw Error("viewer display program", "does not link");
    vertex_array_ = gl::create_vertex_array();
}

void Presenter::draw(const Canvas& canvas, int x, int y, int width, int height, int scissor_x,
                     int scissor_width) const {
    if (canvas.texture() == 0 || width < 1 || height < 1 || scissor_width < 1) return;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_SCISSOR_TEST);
    glScissor(scissor_x, y, scissor_width, height);
    glViewport(x, y, width, height);
    glUseProgram(program_.get());
    glBindTextureUnit(0, canvas.texture());
    glBindVertexArray(vertex_array_.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_SCISSOR_TEST);
}

void PaneTimer::begin(Mode mode) {
    mode_ = mode;
    if (mode == Mode::Cpu) {
        glFinish();  // earlier work is not this pane's
        cpu_start_ = now_seconds();
        return;
    }
    poll();
    current_ = -1;
    if (pending_[std::size_t(next_)]) return;  // every query still in flight: skip this frame
    auto& query = queries_[std::size_t(next_)];
    if (!query) query = gl::create_query(GL_TIME_ELAPSED);
    glBeginQuery(GL_TIME_ELAPSED, query.get());
    current_ = next_;
    next_ = (next_ + 1) % kQueries;
}

void PaneTimer::end() {
    if (mode_ == Mode::Cpu) {
        glFinish();
        add((now_seconds() - cpu_start_) * 1000.0);
        return;
    }
    if (current_ < 0) return;
    glEndQuery(GL_TIME_ELAPSED);
    pending_[std::size_t(current_)] = true;
    current_ = -1;
}

void PaneTimer::poll() {
    for (int i = 0; i < kQueries; ++i) {
        if (!pending_[std::size_t(i)]) continue;
        const GLuint query = queries_[std::size_t(i)].get();
        GLint available = 0;
        glGetQueryObjectiv(query, GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available) continue;
        GLuint64 nanoseconds = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &nanoseconds);
        pending_[std::size_t(i)] = false;
        add(double(nanoseconds) * 1e-6);
    }
}

void PaneTimer::add(double ms) {
    if (skip_ > 0) {
        --skip_;
        return;
    }
    smoothed_ = smoothed_ ? 0.8 * *smoothed_ + 0.2 * ms : ms;
}

}  // namespace leanfade::viewer
