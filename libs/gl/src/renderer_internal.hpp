#pragma once
// What the renderer's source files share (not installed): renderer.cpp (programs, layers,
// drawing), renderer_camera.cpp (views), renderer_upload.cpp (meshes, LEAN maps, layers and
// surface maps on the GPU) and renderer_reference.cpp (the supersampled reference).
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"

namespace leanfade::gl {

namespace detail {

// glGetIntegerv of one value.
GLint gl_integer(GLenum name);

// A surface map of `kind` (scene::Scene::maps: a MIP chain of float images, rows top first) as a
// repeating, trilinear GL_TEXTURE_2D in the kind's format (renderer_upload.cpp).
Texture upload_surface_map(const scene::MapKindInfo& kind, const std::vector<Image>& chain);

}  // namespace detail

// A float colour target (RGBA32F texture) with a depth buffer; optionally multisampled, then
// resolved into `color` by resolve().
struct Renderer::Target {
    int width = 0, height = 0;
    Texture color;
    Framebuffer framebuffer;  // single-sample, color + depth (when not multisampled)
    Renderbuffer depth;
    Framebuffer ms_framebuffer;
    Renderbuffer ms_color;
    Renderbuffer ms_depth;
    int samples = 1;

    Target(int w, int h, int sample_count) : width(w), height(h), samples(sample_count) {
        color = create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(color.get(), 1, GL_RGBA32F, w, h);
        glTextureParameteri(color.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(color.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        framebuffer = create_framebuffer();
        glNamedFramebufferTexture(framebuffer.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
        depth = create_renderbuffer();
        glNamedRenderbufferStorage(depth.get(), GL_DEPTH_COMPONENT32F, w, h);
        glNamedFramebufferRenderbuffer(framebuffer.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                       depth.get());
        check_complete(framebuffer.get());
        if (samples > 1) {
            ms_framebuffer = create_framebuffer();
            ms_color = create_renderbuffer();
            glNamedRenderbufferStorageMultisample(ms_color.get(), samples, GL_RGBA32F, w, h);
            ms_depth = create_renderbuffer();
            glNamedRenderbufferStorageMultisample(ms_depth.get(), samples, GL_DEPTH_COMPONENT32F, w,
                                                  h);
            glNamedFramebufferRenderbuffer(ms_framebuffer.get(), GL_COLOR_ATTACHMENT0,
                                           GL_RENDERBUFFER, ms_color.get());
            glNamedFramebufferRenderbuffer(ms_framebuffer.get(), GL_DEPTH_ATTACHMENT,
                                           GL_RENDERBUFFER, ms_depth.get());
            check_complete(ms_framebuffer.get());
        }
    }

    static void check_complete(GLuint fbo) {
        const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            throw Error("GL",
                        "float render target incomplete (status " + std::to_string(status) + ")");
    }

    GLuint draw_framebuffer() const {
        return samples > 1 ? ms_framebuffer.get() : framebuffer.get();
    }

    void resolve() const {
        if (samples > 1)
            glBlitNamedFramebuffer(ms_framebuffer.get(), framebuffer.get(), 0, 0, width, height, 0,
                                   0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }

    Image read() const {
        std::vector<float> rgba(std::size_t(width) * std::size_t(height) * 4);
        glGetTextureImage(color.get(), 0, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)),
                          rgba.data());
        Image image(width, height, 3);
        for (int y = 0; y < height; ++y) {
            const float* src = rgba.data() + std::size_t(height - 1 - y) * std::size_t(width) * 4;
            float* dst = image.row(y);
            for (int x = 0; x < width; ++x)
                for (int c = 0; c < 3; ++c) dst[x * 3 + c] = src[x * 4 + c];
        }
        return image;
    }
};

}  // namespace leanfade::gl
