// The supersampled reference of the renderer (docs/math.md §7).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/shading_block.hpp"
#include "renderer_internal.hpp"

namespace leanfade::gl {
namespace {

// Largest side of a supersampled reference tile, in samples: 2048 x 2048 RGBA32F is 64 MiB, which
// bounds the reference's memory whatever the output size and k.
constexpr int kMaxReferenceTileSamples = 2048;

GLint location(GLuint program, const char* name) {
    return glGetUniformLocation(program, name);
}

void set(GLuint p, const char* name, int v) {
    glProgramUniform1i(p, location(p, name), v);
}
void set(GLuint p, const char* name, const glm::ivec2& v) {
    glProgramUniform2iv(p, location(p, name), 1, glm::value_ptr(v));
}

}  // namespace

// docs/math.md §7: k x k samples per pixel at LOD 0, shaded with the baseline, box-filtered. The
// supersampled image is drawn in tiles of at most kMaxReferenceTileSamples squared samples, each
// with the projection narrowed to its pixels, then reduced into the output.
void Renderer::render_reference(const RenderRequest& request, Target& output) {
    const int k = request.reference_samples;
    const int tile = std::max(1, kMaxReferenceTileSamples / k);  // output pixels per tile side
    Target samples(std::min(tile, request.width) * k, std::min(tile, request.height) * k, 1);
    const VariantKey scene_program = VariantKey::scene(
        Technique::Reference, scene_variant_flags(Technique::Reference, request.settings));
    const GLuint filter_program = program(VariantKey::box_filter());
    const float aspect = float(request.width) / float(request.height);
    const glm::mat4 projection = request.view.projection_matrix(aspect);
    const glm::mat4 view = request.view.view_matrix();
    const glm::vec3 clear =
        request.output == OutputMode::Color ? request.background : glm::vec3(0.0f);
    const float clear_color[4] = {clear.r, clear.g, clear.b, 1.0f};
    const float clear_depth = 1.0f;

    for (int y0 = 0; y0 < request.height; y0 += tile) {
        for (int x0 = 0; x0 < request.width; x0 += tile) {
            const int tw = std::min(tile, request.width - x0);
            const int th = std::min(tile, request.height - y0);
            // Clip-space window of this tile: NDC [ax, bx] x [ay, by] mapped onto [-1, 1]^2.
            const float ax = -1.0f + 2.0f * float(x0) / float(request.width);
            const float bx = -1.0f + 2.0f * float(x0 + tw) / float(request.width);
            const float ay = -1.0f + 2.0f * float(y0) / float(request.height);
            const float by = -1.0f + 2.0f * float(y0 + th) / float(request.height);
            glm::mat4 window(1.0f);
            window[0][0] = 2.0f / (bx - ax);
            window[1][1] = 2.0f / (by - ay);
            window[3][0] = -(bx + ax) / (bx - ax);
            window[3][1] = -(by + ay) / (by - ay);

            glClearNamedFramebufferfv(samples.framebuffer.get(), GL_COLOR, 0, clear_color);
            glClearNamedFramebufferfv(samples.framebuffer.get(), GL_DEPTH, 0, &clear_depth);
            glBindFramebuffer(GL_FRAMEBUFFER, samples.framebuffer.get());
            glViewport(0, 0, tw * k, th * k);
            glEnable(GL_DEPTH_TEST);
            draw_scene(scene_program, request, window * projection * view);

            // Reduce into the output's pixels [x0, x0 + tw) x [y0, y0 + th) (GL window coords).
            glBindFramebuffer(GL_FRAMEBUFFER, output.framebuffer.get());
            glViewport(x0, y0, tw, th);
            glDisable(GL_DEPTH_TEST);
            set(filter_program, "u_factor", k);
            set(filter_program, "u_tile_origin", glm::ivec2(x0, y0));
            glUseProgram(filter_program);
            glBindTextureUnit(0, samples.color.get());
            glBindVertexArray(empty_vertex_array_.get());
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindVertexArray(0);
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glEnable(GL_DEPTH_TEST);
}

}  // namespace leanfade::gl
