// EGL context creation, GL error recording and the RAII wrappers.
#include <epoxy/gl.h>

#include <cstdlib>
#include <string>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/objects.hpp"

namespace leanfade::test {
namespace {

class GlContext : public GlTest {};

TEST_F(GlContext, IsOpenGl45CoreWithDebugOutput) {
    EXPECT_GE(epoxy_gl_version(), 45);
    EXPECT_TRUE(epoxy_is_desktop_gl());
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
    EXPECT_TRUE(glIsEnabled(GL_DEBUG_OUTPUT));
    EXPECT_FALSE(context().renderer().empty());
    EXPECT_NE(context().description().find("EGL"), std::string::npos);
}

TEST_F(GlContext, RecordsGlErrorsAndCheckThrows) {
    glEnable(GLenum(0x7FFF));  // not a capability: GL_INVALID_ENUM
    const std::vector<std::string> errors = context().take_errors();
    ASSERT_FALSE(errors.empty());
    EXPECT_TRUE(context().take_errors().empty()) << "take_errors() must clear the record";

    glBindTexture(GL_TEXTURE_2D, 0xFFFFFF);  // not a texture name: GL_INVALID_OPERATION
    try {
        context().check("binding a bad name");
        FAIL() << "check() must throw on a GL error";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "GL");
        EXPECT_NE(e.cause().find("binding a bad name"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(context().take_errors().empty());
}

TEST_F(GlContext, UnknownEglDeviceIsAnEglError) {
    gl::ContextOptions options;
    options.device = 9999;
    try {
        gl::Context other(options);
        FAIL() << "device 9999 cannot exist";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "EGL");
        EXPECT_NE(e.cause().find("9999"), std::string::npos) << e.what();
    }
    context().make_current();
}

TEST_F(GlContext, BadEglDeviceVariableIsAnEglError) {
    ::setenv("LEANFADE_EGL_DEVICE", "first", 1);
    try {
        gl::Context other;
        ::unsetenv("LEANFADE_EGL_DEVICE");
        FAIL() << "LEANFADE_EGL_DEVICE=first must be refused";
    } catch (const Error& e) {
        ::unsetenv("LEANFADE_EGL_DEVICE");
        EXPECT_EQ(e.file(), "EGL");
        EXPECT_NE(e.cause().find("LEANFADE_EGL_DEVICE"), std::string::npos) << e.what();
    }
    context().make_current();
}

TEST_F(GlContext, ObjectsAreDeletedAndMoved) {
    gl::Texture texture = gl::create_texture(GL_TEXTURE_2D);
    const GLuint name = texture.get();
    ASSERT_NE(name, 0u);
    EXPECT_TRUE(glIsTexture(name));
    gl::Texture moved = std::move(texture);
    EXPECT_EQ(texture.get(), 0u);
    EXPECT_EQ(moved.get(), name);
    moved.reset();
    EXPECT_FALSE(glIsTexture(name));

    gl::Buffer buffer = gl::create_buffer();
    gl::Framebuffer framebuffer = gl::create_framebuffer();
    gl::Renderbuffer renderbuffer = gl::create_renderbuffer();
    gl::VertexArray vertex_array = gl::create_vertex_array();
    gl::Query query = gl::create_query(GL_TIME_ELAPSED);
    EXPECT_TRUE(glIsBuffer(buffer.get()));
    EXPECT_TRUE(glIsFramebuffer(framebuffer.get()));
    EXPECT_TRUE(glIsRenderbuffer(renderbuffer.get()));
    EXPECT_TRUE(glIsVertexArray(vertex_array.get()));
    EXPECT_TRUE(glIsQuery(query.get()));
}

}  // namespace
}  // namespace leanfade::test
