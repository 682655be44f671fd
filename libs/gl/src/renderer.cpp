// Offscreen rendering of every technique into float render targets: programs, bump layers,
// drawing and reading back (uploads: renderer_upload.cpp; views: renderer_camera.cpp; the
// supersampled reference: renderer_reference.cpp).
#include "leanfade/gl/renderer.hpp"

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

GLint detail::gl_integer(GLenum name) {
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}

namespace {

using detail::gl_integer;


// velocity * time modulo 1 (uv units, velocity in uv per second, time in seconds), in double
// precision.
float wrapped_offset(float velocity, float time) {
    const double offset = double(velocity) * double(time);
    return float(offset - std::floor(offset));
}

int output_constant(OutputMode mode) {
    switch (mode) {
        case OutputMode::Color:
            return 0;
        case OutputMode::Diffuse:
            return 1;
        case OutputMode::Specular:
            return 2;
        case OutputMode::FadeTerms:
            return 3;
    }
    return 0;
}

}  // namespace

// The program that draws `request`: for the colour output without fog, the technique's plain
// variant when there is one (the same image without the output and fog branches, which llvmpipe
// executes for every pixel; docs/perf.md). Fading with its defaults while it is on takes the fast
// variant (shader_library.hpp).
VariantKey variant_for(const RenderRequest& request) {
    const ShadingSettings& s = request.settings;
    VariantKey key =
        VariantKey::scene(request.technique, scene_variant_flags(request.technique, s));
    if (request.output == OutputMode::Color && s.fog == FogMode::None &&
        has_variant(VariantKey::scene(request.technique, kPlainColor)))
        key = key.with(kPlainColor);
    if (info(request.technique).fades && s.fade_exponent == 2.0f &&
        s.fade_distance == FadeDistance::TangentZ && s.fade > 0.0f && s.pmax > 1.0f &&
        has_variant(key.with(kFadeFast)))
        key = key.with(kFadeFast);
    return key;
}

LfShadingUniforms shading_uniforms(const ShadingSettings& s, bool roughness_baked, float map_scale,
                                   float map_offset, OutputMode output) {
    // The defaults (shaders/lean_shading.glsl: identity uv transforms of set 0, opaque, one-sided,
    // no surface maps or glTF factors) and what the settings and the map set (docs/integration.md).
    LfShadingUniforms block;
    block.params = to_lf_params(s, roughness_baked);
    block.scale = map_scale;
    block.lean_offset = map_offset;
    block.output_mode = output_constant(output);
    block.fog_mode = to_shader_constant(s.fog);
    block.fog_start = s.fog_start;
    block.fog_color = s.fog_color;
    block.fog_end = s.fog_end;
    block.fog_density = s.fog_density;
    block.geometric_aa_kappa = s.geometric_aa_kappa;
    return block;
}


Renderer::Renderer(Context& context, ShaderSources sources)
    : context_(context), sources_(std::move(sources)) {
    empty_vertex_array_ = create_vertex_array();
    shading_block_ = create_buffer();
    glNamedBufferStorage(shading_block_.get(), GLsizeiptr(kShadingBlockStd140Size), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    object_block_ = create_buffer();
    glNamedBufferStorage(object_block_.get(), GLsizeiptr(sizeof(LfObjectUniforms)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    layer_block_ = create_buffer();
    glNamedBufferStorage(layer_block_.get(), GLsizeiptr(sizeof(LfLayerUniforms)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
}

Renderer::~Renderer() = default;

void Renderer::rebuild_shaders() {
    std::map<VariantKey, Program> rebuilt;
    for (const auto& entry : programs_)
        rebuilt.emplace(entry.first, build_program(sources_, shader_variant(entry.first)));
    programs_ = std::move(rebuilt);
}

GLuint Renderer::program(const VariantKey& key) {
    auto it = programs_.find(key);
    if (it == programs_.end())
        it = programs_.emplace(key, build_program(sources_, shader_variant(key))).first;
    return it->second.get();
}

void Renderer::update_mixed_layers(float time) {
    for (std::size_t m = 0; m < materials_.size() && m < material_layers_.size(); ++m) {
        GpuLayers& layers = material_layers_[m];
        if (!layers.mixer) continue;
        const scene::Material& material = materials_[m];
        bool moving = false;
        for (const scene::MaterialLayer& layer : material.layered.layers)
            moving = moving || layer.velocity != glm::vec2(0.0f);
        if (layers.mixed_time && (!moving || *layers.mixed_time == time)) continue;
        bind_layers(material, layers, time);
        layers.mixer->generate(layers.mixed);
        layers.mixed_time = time;
    }
    context_.check("generating the mixed LEAN maps");
}

PackedLeanMap Renderer::mixed_lean_map(int material, float time) {
    if (material < 0 || material >= int(material_layers_.size()) ||
        !material_layers_[std::size_t(material)].mixer)
        throw Error("scene", "material " + std::to_string(material) +
                                 " has no map generated by the height method");
    if (!std::isfinite(time)) throw Error::setting("time", "must be a finite number of seconds");
    update_mixed_layers(time);
    return material_layers_[std::size_t(material)].mixer->read_back();
}

void Renderer::bind_layers(const scene::Material& material, const GpuLayers& layers, float time) {
    const scene::MaterialLayers& l = material.layered;
    LfLayerUniforms block{};
    block.count = int(l.layers.size());
    block.mixing = info(l.mixing).shader_mixing;
    block.weight_map = layers.weights.get() != 0 ? 1 : 0;
    for (std::size_t i = 0; i < l.layers.size() && i < std::size_t(kMaxLayers); ++i) {
        const scene::MaterialLayer& layer = l.layers[i];
        const GpuMap& map = maps_[std::size_t(layer.lean_map)];
        const int c = int(i);
        block.weights[c] = l.weights[i];
        block.strengths[c] = layer.strength;
        block.scales[c] = map.info.scale;
        block.lean_offsets[c] = map.info.lean_offset;
        block.tilings[c] = layer.tiling;
        // A moving layer: its texture coordinates slide by velocity * time (uv units), taken
        // modulo 1 in double precision (the layers repeat) so that late times keep their texels.
        const glm::vec2 offset(wrapped_offset(layer.velocity.x, time),
                               wrapped_offset(layer.velocity.y, time));
        block.offsets[i / 2][int(i % 2) * 2] = offset.x;
        block.offsets[i / 2][int(i % 2) * 2 + 1] = offset.y;
        glBindTextureUnit(GLuint(bindings::LF_BINDING_LAYER_MAPS + c), map.texture.get());
    }
    if (layers.cross_terms.get() != 0)
        glBindTextureUnit(GLuint(bindings::LF_BINDING_CROSS_TERMS), layers.cross_terms.get());
    if (layers.weights.get() != 0)
        glBindTextureUnit(GLuint(bindings::LF_BINDING_LAYER_WEIGHTS), layers.weights.get());
    glNamedBufferSubData(layer_block_.get(), 0, sizeof(block), &block);
    glBindBufferBase(GL_UNIFORM_BUFFER, GLuint(bindings::LF_BINDING_LAYER_BLOCK),
                     layer_block_.get());
}

const LeanTextureInfo& Renderer::lean_texture() const {
    static const LeanTextureInfo none;
    return maps_.empty() ? none : maps_.front().info;
}

void Renderer::draw_scene(const VariantKey& variant, const RenderRequest& request,
                          const glm::mat4& clip) {
    const GLuint p = program(variant);
    // Layered materials draw with the variant's layered twin (a scene variant: not the floor).
    const bool layerable = variant.is_scene();
    const ShadingSettings& frame = request.settings;
    const glm::mat4 view = request.view.view_matrix();
    LfObjectUniforms object_block{};
    object_block.view = view;
    object_block.clip = clip;
    object_block.eye_world = request.view.eye;
    object_block.light_world = glm::normalize(frame.light_direction);
    object_block.tiling = frame.tiling;
    // The opaque objects first, in order; then the blended ones (glTF alphaMode BLEND) from the
    // farthest to the nearest (by their bounds' centre in eye space), over what is drawn, with
    // depth tested but not written (straight alpha: RGB by alpha over 1 - alpha).
    std::vector<std::pair<float, std::size_t>> blended;
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < objects_.size(); ++i) {
        if (!materials_[std::size_t(objects_[i].material)].blend) {
            order.push_back(i);
            continue;
        }
        const glm::vec4 eye = view * (model_ * objects_[i].transform) * glm::vec4(objects_[i].centre, 1.0f);
        blended.emplace_back(eye.z, i);  // more negative: farther
    }
    std::stable_sort(blended.begin(), blended.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    const std::size_t opaque_count = order.size();
    for (const auto& [depth, i] : blended) order.push_back(i);
    for (std::size_t n = 0; n < order.size(); ++n) {
        const GpuObject& object = objects_[order[n]];
        if (n == opaque_count) {
            glEnable(GL_BLEND);
            glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
            glDepthMask(GL_FALSE);
        }
        const scene::Material& material = materials_[std::size_t(object.material)];
        const GpuMap& map = maps_[std::size_t(material.lean_map)];
        // The "height" method draws its generated map (update_mixed_layers) like a single map.
        const GpuLayers& material_layers = material_layers_[std::size_t(object.material)];
        const LeanGenerator* mixer = material_layers.mixer.get();
        const GLuint map_texture = mixer != nullptr ? mixer->texture() : map.texture.get();
        const float map_scale = mixer != nullptr ? material_layers.mixed.scale : map.info.scale;
        const float map_offset = mixer != nullptr
                                     ? lean_offset(default_encoding(material_layers.mixed.storage))
                                     : map.info.lean_offset;
        const bool layered = layerable && !material.layered.layers.empty() && mixer == nullptr;
        glUseProgram(layered ? program(variant.with(kLayered)) : p);
        if (layered) bind_layers(material, material_layers, request.time);
        object_block.model = model_ * object.transform;
        const glm::mat3 normal_matrix(glm::transpose(glm::inverse(object_block.model)));
        for (int c = 0; c < 3; ++c)
            object_block.normal_matrix[c] = glm::vec4(normal_matrix[c], 0.0f);
        glNamedBufferSubData(object_block_.get(), 0, sizeof(object_block), &object_block);
        glBindBufferBase(GL_UNIFORM_BUFFER, GLuint(bindings::LF_BINDING_OBJECT_BLOCK),
                         object_block_.get());

        ShadingSettings s = frame;
        if (material.diffuse) s.kd = *material.diffuse;
        if (material.specular) s.ks = *material.specular;
        if (material.shininess) s.shininess = *material.shininess;
        // A glTF material's metalness replaces the frame's and is applied per texel, with the
        // base colour texture, by the shader (lf_surface_params).
        if (material.metallic) s.metallic = 0.0f;
        // A layered material's maps have no baked roughness: 1/s is added once, after mixing.
        LfShadingUniforms block =
            shading_uniforms(s, !layered && mixer == nullptr && map.info.roughness_baked, map_scale,
                             map_offset, request.output);
        if (material.alpha_cutoff) block.alpha_cutoff = *material.alpha_cutoff;
        block.base_alpha = material.base_alpha;
        block.blend = material.blend ? 1.0f : 0.0f;
        block.double_sided = material.double_sided.value_or(false) ? 1.0f : 0.0f;
        // Row 0's w: the texture coordinate set (0 or 1) the map samples (map_uv, scene.frag).
        const auto set_uv_transform = [&](int slot, const scene::UvTransform& t) {
            block.uv_transforms[2 * slot] = glm::vec4(t.row0, float(t.set));
            block.uv_transforms[2 * slot + 1] = glm::vec4(t.row1, 0.0f);
        };
        set_uv_transform(shading::LF_UV_LEAN_MAP, material.lean_uv);
        for (const scene::MapKindInfo& kind : scene::kMapKinds)
            if (kind.uv_transform != shading::LF_UV_LEAN_MAP)
                set_uv_transform(kind.uv_transform, material.map_uv[std::size_t(kind.kind)]);
        block.material.metallic = material.metallic.value_or(0.0f);
        block.material.occlusion_strength =
            material.map(scene::MapKind::Occlusion) >= 0 ? material.occlusion_strength : 0.0f;
        block.material.emissive = material.emissive;
        block.material.anisotropy_strength = material.anisotropy_strength;
        block.material.anisotropy_rotation = glm::vec2(std::cos(material.anisotropy_rotation),
                                                       std::sin(material.anisotropy_rotation));
        // A single-sided glTF material's back faces are culled (counter-clockwise front faces).
        if (material.double_sided.has_value() && !*material.double_sided) {
            glEnable(GL_CULL_FACE);
            glCullFace(GL_BACK);
            glFrontFace(GL_CCW);
        } else {
            glDisable(GL_CULL_FACE);
        }
        // The material's surface maps: each on its unit with its bit in the block's mask, or the
        // kind's fallback (docs/math.md §9: Cook-Torrance's base roughness per texel).
        block.maps = 0;
        for (const scene::MapKindInfo& kind : scene::kMapKinds) {
            const int slot = material.map(kind.kind);
            // The "height" method's generated map brings its own plateau layer.
            const GLuint generated_plateau =
                kind.kind == scene::MapKind::Plateau && mixer != nullptr ? mixer->plateau_texture()
                                                                         : 0;
            const bool read = generated_plateau != 0 ||
                              (slot >= 0 && (!kind.cook_torrance_only || s.brdf == Brdf::CookTorrance));
            if (read) block.maps |= kind.mask_bit;
            GLuint texture = 0;
            if (generated_plateau != 0) {
                texture = generated_plateau;
            } else if (read) {
                texture = surface_maps_[std::size_t(kind.kind)][std::size_t(slot)].get();
            } else if (kind.fallback == scene::MapFallback::White) {
                if (white_.get() == 0)
                    white_ = detail::upload_surface_map(scene::info(scene::MapKind::BaseColor),
                                                        {Image(1, 1, 4, 1.0f)});
                texture = white_.get();
            }
            glBindTextureUnit(GLuint(kind.binding), texture);
        }
        glNamedBufferSubData(shading_block_.get(), 0, sizeof(block), &block);
        glBindBufferBase(GL_UNIFORM_BUFFER, GLuint(bindings::LF_BINDING_SHADING_BLOCK),
                         shading_block_.get());
        glBindTextureUnit(GLuint(bindings::LF_BINDING_LEAN_MAP), map_texture);
        glBindVertexArray(object.vertex_array.get());
        glDrawElements(GL_TRIANGLES, object.index_count, GL_UNSIGNED_INT, nullptr);
    }
    if (order.size() > opaque_count) {
        glDisable(GL_BLEND);
        glDepthMask(GL_TRUE);
    }
    glDisable(GL_CULL_FACE);
    glBindVertexArray(0);
}

namespace {

// A render is linear radiance: a NaN or an infinity (from parameters that leave the float range)
// is an error naming the technique and the first such pixel, never a black or white pixel.
void require_finite_pixels(const Image& image, Technique technique) {
    const std::size_t channels = std::size_t(std::max(1, image.channels));
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        if (!std::isfinite(image.pixels[i])) {
            const std::size_t texel = i / channels;
            throw Error("render", std::string(to_string(technique)) + " gave " +
                                      (std::isnan(image.pixels[i]) ? "NaN" : "an infinity") +
                                      " at pixel (" +
                                      std::to_string(texel % std::size_t(image.width)) + ", " +
                                      std::to_string(texel / std::size_t(image.width)) +
                                      "): the shading parameters leave the float range");
        }
}

}  // namespace

Image Renderer::render(const RenderRequest& request) {
    Target& target = render_target(request);
    Image image = target.read();
    context_.check(std::string("rendering ") + to_string(request.technique));
    require_finite_pixels(image, request.technique);
    return image;
}

void Renderer::render_to(const RenderRequest& request, GLuint framebuffer, int x, int y) {
    Target& target = render_target(request);
    glBlitNamedFramebuffer(target.framebuffer.get(), framebuffer, 0, 0, target.width, target.height,
                           x, y, x + target.width, y + target.height, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
    context_.check(std::string("rendering ") + to_string(request.technique) +
                   " into a framebuffer");
}

Renderer::Target& Renderer::render_target(const RenderRequest& request) {
    if (objects_.empty()) throw Error("render", "no mesh was set");
    if (maps_.empty()) throw Error("render", "no LEAN map was set");
    validate(request.settings);
    if (!std::isfinite(request.time))
        throw Error::setting("time", "must be a finite number of seconds");
    const int max_size =
        std::min(gl_integer(GL_MAX_TEXTURE_SIZE), gl_integer(GL_MAX_RENDERBUFFER_SIZE));
    if (request.width < 1 || request.height < 1 || request.width > max_size ||
        request.height > max_size)
        throw Error::setting("size", "image size must be 1.." + std::to_string(max_size) +
                                         " pixels, got " + std::to_string(request.width) + "x" +
                                         std::to_string(request.height));
    if (request.technique == Technique::Reference &&
        (request.reference_samples < 1 || request.reference_samples > kMaxReferenceSamples))
        throw Error::setting("ref_samples", "must be in [1, " +
                                                std::to_string(kMaxReferenceSamples) + "], got " +
                                                std::to_string(request.reference_samples));
    const ShadingSettings& s = request.settings;
    int samples = request.technique == Technique::Reference ? 1 : s.msaa;
    if (samples > gl_integer(GL_MAX_SAMPLES))
        throw Error::setting("msaa", std::to_string(samples) +
                                         " samples requested, the GL driver allows " +
                                         std::to_string(gl_integer(GL_MAX_SAMPLES)));

    update_mixed_layers(request.time);
    apply_sampler_state(s);

    if (!target_ || target_->width != request.width || target_->height != request.height ||
        target_->samples != samples)
        target_ = std::make_unique<Target>(request.width, request.height, samples);
    Target& target = *target_;
    const glm::vec3 clear =
        request.output == OutputMode::Color ? request.background : glm::vec3(0.0f);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_FRAMEBUFFER_SRGB);
    if (request.technique == Technique::Reference) {
        render_reference(request, target);
    } else {
        if (samples > 1) glEnable(GL_MULTISAMPLE);
        const GLuint fbo = target.draw_framebuffer();
        const float clear_color[4] = {clear.r, clear.g, clear.b, 1.0f};
        const float clear_depth = 1.0f;
        glClearNamedFramebufferfv(fbo, GL_COLOR, 0, clear_color);
        glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &clear_depth);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, request.width, request.height);
        const float aspect = float(request.width) / float(request.height);
        const glm::mat4 clip = request.view.projection_matrix(aspect) * request.view.view_matrix();
        draw_scene(variant_for(request), request, clip);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        target.resolve();
    }
    return target;
}

void Renderer::apply_sampler_state(const ShadingSettings& s) {
    const float max_aniso = context_.max_anisotropy();
    if (s.anisotropy > 1 && max_aniso <= 1.0f)
        throw Error::setting("aniso",
                             "anisotropic filtering is not supported by " + context_.renderer());
    std::vector<GLuint> textures;
    for (const GpuMap& map : maps_) textures.push_back(map.texture.get());
    for (const GpuLayers& layers : material_layers_) {
        for (const Texture* t : {&layers.cross_terms, &layers.weights})
            if (t->get() != 0) textures.push_back(t->get());
        if (layers.mixer && layers.mixer->texture() != 0)
            textures.push_back(layers.mixer->texture());
        if (layers.mixer && layers.mixer->plateau_texture() != 0)
            textures.push_back(layers.mixer->plateau_texture());
    }
    for (const scene::MapKindInfo& kind : scene::kMapKinds)
        if (kind.lean_sampler_state)
            for (const Texture& map : surface_maps_[std::size_t(kind.kind)])
                textures.push_back(map.get());
    for (const GLuint texture : textures) {
        glTextureParameterf(texture, GL_TEXTURE_LOD_BIAS, s.mip_bias);
        if (s.anisotropy > 1)
            glTextureParameterf(texture, GL_TEXTURE_MAX_ANISOTROPY,
                                std::min(float(s.anisotropy), max_aniso));
        else if (max_aniso > 1.0f)
            glTextureParameterf(texture, GL_TEXTURE_MAX_ANISOTROPY, 1.0f);
    }
}

void Renderer::draw(const RenderRequest& request, GLuint framebuffer,
                    std::optional<VariantKey> variant) {
    if (objects_.empty()) throw Error("render", "no mesh was set");
    if (maps_.empty()) throw Error("render", "no LEAN map was set");
    if (!variant && request.technique == Technique::Reference)
        throw Error("render", "the reference is supersampled in several passes: use render()");
    if (request.width < 1 || request.height < 1)
        throw Error::setting("size", "the viewport must be at least 1x1 pixels");
    validate(request.settings);
    if (!std::isfinite(request.time))
        throw Error::setting("time", "must be a finite number of seconds");
    const VariantKey key = variant.value_or(variant_for(request));
    program(key);  // built (or its error thrown) before any state changes
    update_mixed_layers(request.time);
    apply_sampler_state(request.settings);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, request.width, request.height);
    const float aspect = float(request.width) / float(request.height);
    draw_scene(key, request, request.view.projection_matrix(aspect) * request.view.view_matrix());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace leanfade::gl
