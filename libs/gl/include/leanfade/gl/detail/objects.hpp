#pragma once
// RAII owners of OpenGL objects, created with direct state access (glCreate*). Each owns one name,
// is movable, not copyable, and deletes its object when destroyed; a context must be current on
// the thread for construction and destruction.
#include <epoxy/gl.h>

#include <string>
#include <utility>

namespace leanfade::gl {

// A GL name plus the function that deletes it.
template <void (*Delete)(GLuint)>
class Object {
  public:
    Object() = default;
    explicit Object(GLuint name) : name_(name) {}
    ~Object() { reset(); }
    Object(Object&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
    Object& operator=(Object&& other) noexcept {
        if (this != &other) {
            reset();
            name_ = std::exchange(other.name_, 0);
        }
        return *this;
    }
    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;

    GLuint get() const { return name_; }
    explicit operator bool() const { return name_ != 0; }
    void reset() {
        if (name_ != 0) Delete(name_);
        name_ = 0;
    }

  private:
    GLuint name_ = 0;
};

namespace detail {
inline void delete_buffer(GLuint n) {
    glDeleteBuffers(1, &n);
}
inline void delete_texture(GLuint n) {
    glDeleteTextures(1, &n);
}
inline void delete_framebuffer(GLuint n) {
    glDeleteFramebuffers(1, &n);
}
inline void delete_renderbuffer(GLuint n) {
    glDeleteRenderbuffers(1, &n);
}
inline void delete_vertex_array(GLuint n) {
    glDeleteVertexArrays(1, &n);
}
inline void delete_query(GLuint n) {
    glDeleteQueries(1, &n);
}
inline void delete_program(GLuint n) {
    glDeleteProgram(n);
}
inline void delete_shader(GLuint n) {
    glDeleteShader(n);
}
}  // namespace detail

using Buffer = Object<detail::delete_buffer>;
using Texture = Object<detail::delete_texture>;
using Framebuffer = Object<detail::delete_framebuffer>;
using Renderbuffer = Object<detail::delete_renderbuffer>;
using VertexArray = Object<detail::delete_vertex_array>;
using Query = Object<detail::delete_query>;
using Program = Object<detail::delete_program>;
using Shader = Object<detail::delete_shader>;

inline Buffer create_buffer() {
    GLuint n = 0;
    glCreateBuffers(1, &n);
    return Buffer(n);
}
// target: GL_TEXTURE_2D, GL_TEXTURE_2D_ARRAY, ...
inline Texture create_texture(GLenum target) {
    GLuint n = 0;
    glCreateTextures(target, 1, &n);
    return Texture(n);
}
// A texture of `levels` MIP levels sampled trilinearly (bilinearly with one level), repeating:
// how the renderer samples its maps.
inline void set_repeat_trilinear(GLuint texture, int levels) {
    glTextureParameteri(texture, GL_TEXTURE_BASE_LEVEL, 0);
    glTextureParameteri(texture, GL_TEXTURE_MAX_LEVEL, levels - 1);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER,
                        levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_REPEAT);
}
inline Framebuffer create_framebuffer() {
    GLuint n = 0;
    glCreateFramebuffers(1, &n);
    return Framebuffer(n);
}
inline Renderbuffer create_renderbuffer() {
    GLuint n = 0;
    glCreateRenderbuffers(1, &n);
    return Renderbuffer(n);
}
inline VertexArray create_vertex_array() {
    GLuint n = 0;
    glCreateVertexArrays(1, &n);
    return VertexArray(n);
}
// target: GL_TIME_ELAPSED, GL_SAMPLES_PASSED, ...
inline Query create_query(GLenum target) {
    GLuint n = 0;
    glCreateQueries(target, 1, &n);
    return Query(n);
}

}  // namespace leanfade::gl
