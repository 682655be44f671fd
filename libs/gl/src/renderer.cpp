// Offscreen rendering of every technique into float render targets.
#include "leanfade/gl/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/gl/shading_block.hpp"

namespace leanfade::gl {
namespace {

// Largest side of a supersampled reference tile, in samples: 2048 x 2048 RGBA32F is 64 MiB, which
// bounds the reference's memory whatever the output size and k.
constexpr int kMaxReferenceTileSamples = 2048;
constexpr int kMaxReferenceSamples = 16;

GLint location(GLuint program, const char* name) {
    return glGetUniformLocation(program, name);
}

void set(GLuint p, const char* name, int v) {
    glProgramUniform1i(p, location(p, name), v);
}
void set(GLuint p, const char* name, const glm::ivec2& v) {
    glProgramUniform2iv(p, location(p, name), 1, glm::value_ptr(v));
}

// velocity * time modulo 1 (uv units, velocity in uv per second, time in seconds), in double
// precision.
float wrapped_offset(float velocity, float time) {
    const double offset = double(velocity) * double(time);
    return float(offset - std::floor(offset));
}

GLint gl_integer(GLenum name) {
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}

struct StorageFormat {
    GLenum internal_format;
    GLenum type;
};

StorageFormat storage_format(Storage storage) {
    switch (storage) {
        case Storage::Unorm8:
            return {GL_RGBA8, GL_UNSIGNED_BYTE};
        case Storage::Unorm16:
            return {GL_RGBA16, GL_UNSIGNED_SHORT};
        case Storage::Float16:
            return {GL_RGBA16F, GL_HALF_FLOAT};
        case Storage::Float32:
            return {GL_RGBA32F, GL_FLOAT};
    }
    return {GL_RGBA16, GL_UNSIGNED_SHORT};
}

// Rows bottom first for glTextureSubImage (OpenGL's first row is v = 0; core images are top first).
std::vector<std::uint8_t> flipped(const std::vector<std::uint8_t>& bytes, std::size_t row_bytes,
                                  int rows) {
    std::vector<std::uint8_t> out(bytes.size());
    for (int y = 0; y < rows; ++y)
        std::copy_n(bytes.begin() + std::ptrdiff_t(std::size_t(y) * row_bytes), row_bytes,
                    out.begin() + std::ptrdiff_t(std::size_t(rows - 1 - y) * row_bytes));
    return out;
}

// The program that draws `request`: for the colour output without fog, the technique's plain
// variant when there is one (the same image without the output and fog branches, which llvmpipe
// executes for every pixel; docs/perf.md). Fading with its defaults while it is on takes the fast
// variant (shader_library.hpp).
VariantKey variant_for(const RenderRequest& request) {
    const ShadingSettings& s = request.settings;
    VariantKey key = VariantKey::scene(request.technique, scene_variant_flags(request.technique, s));
    if (request.output == OutputMode::Color && s.fog == FogMode::None &&
        has_variant(VariantKey::scene(request.technique, kPlainColor)))
        key = key.with(kPlainColor);
    if (info(request.technique).fades && s.fade_exponent == 2.0f &&
        s.fade_distance == FadeDistance::TangentZ && s.fade > 0.0f && s.pmax > 1.0f &&
        has_variant(key.with(kFadeFast)))
        key = key.with(kFadeFast);
    return key;
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

glm::mat4 View::view_matrix() const {
    return glm::lookAt(eye, target, up);
}

glm::mat4 View::projection_matrix(float aspect) const {
    return glm::perspective(glm::radians(fov_y_degrees), aspect, near_plane, far_plane);
}

View view_at_distance(float distance, float fov_y_degrees, glm::vec3 direction, glm::vec3 target) {
    if (!(distance > 1.0f) || !std::isfinite(distance))
        throw Error("distances", "camera distances are in bounding radii and must be > 1, got " +
                                       std::to_string(distance));
    if (!(fov_y_degrees > 1.0f && fov_y_degrees < 170.0f))
        throw Error("fov", "must be in (1, 170) degrees, got " + std::to_string(fov_y_degrees));
    if (!(glm::length(direction) > 0.0f) || !std::isfinite(glm::length(direction)))
        throw Error("view_dir", "must be a finite, non-zero vector");
    if (!std::isfinite(target.x) || !std::isfinite(target.y) || !std::isfinite(target.z))
        throw Error("target", "must be finite");
    View v;
    const glm::vec3 unit = glm::normalize(direction);
    v.eye = target + unit * distance;
    v.target = target;
    v.up = std::abs(unit.y) > 0.9999f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    v.fov_y_degrees = fov_y_degrees;
    // Near and far planes enclose the unit sphere about the object's centre (the origin).
    const float centre_distance = target == glm::vec3(0.0f) ? distance : glm::length(v.eye);
    v.near_plane = std::max(0.01f, 0.9f * (centre_distance - 1.0f));
    v.far_plane = 1.1f * (centre_distance + 1.0f);
    return v;
}

float projected_radius_pixels(const View& view, int height) {
    const float d = glm::length(view.eye - view.target);
    const float tangent = 1.0f / std::sqrt(std::max(d * d - 1.0f, 1e-6f));  // tan(asin(1/d))
    return tangent / std::tan(glm::radians(view.fov_y_degrees) * 0.5f) * 0.5f * float(height);
}

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

namespace {

// Object -> world for a box: centre to the origin, bounding radius to 1.
glm::mat4 unit_sphere_matrix(const scene::Bounds& bounds, const std::string& name) {
    const float radius = bounds.radius();
    if (!(radius > 0.0f) || !std::isfinite(radius))
        throw Error(name, "the mesh's bounding radius is zero");
    return glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / radius)) *
           glm::translate(glm::mat4(1.0f), -bounds.center());
}

void check_triangles(const scene::Mesh& mesh) {
    if (mesh.vertices.empty() || mesh.indices.empty() || mesh.indices.size() % 3 != 0)
        throw Error(mesh.name, "the mesh has no triangles");
    for (std::uint32_t i : mesh.indices)
        if (i >= mesh.vertices.size()) throw Error(mesh.name, "a triangle index is out of range");
}

}  // namespace

Renderer::GpuObject Renderer::upload_object(const scene::Mesh& mesh, int material,
                                            const glm::mat4& transform) {
    GpuObject object;
    object.material = material;
    object.transform = transform;
    object.vertices = create_buffer();
    glNamedBufferStorage(object.vertices.get(),
                         GLsizeiptr(mesh.vertices.size() * sizeof(scene::Vertex)),
                         mesh.vertices.data(), 0);
    object.indices = create_buffer();
    glNamedBufferStorage(object.indices.get(),
                         GLsizeiptr(mesh.indices.size() * sizeof(std::uint32_t)),
                         mesh.indices.data(), 0);
    object.index_count = GLsizei(mesh.indices.size());

    object.vertex_array = create_vertex_array();
    const GLuint vao = object.vertex_array.get();
    glVertexArrayVertexBuffer(vao, 0, object.vertices.get(), 0, sizeof(scene::Vertex));
    glVertexArrayElementBuffer(vao, object.indices.get());
    const struct {
        GLuint location;
        GLint size;
        std::size_t offset;
    } attributes[] = {{0, 3, offsetof(scene::Vertex, position)},
                      {1, 3, offsetof(scene::Vertex, normal)},
                      {2, 2, offsetof(scene::Vertex, uv)},
                      {3, 4, offsetof(scene::Vertex, tangent)}};
    for (const auto& a : attributes) {
        glEnableVertexArrayAttrib(vao, a.location);
        glVertexArrayAttribFormat(vao, a.location, a.size, GL_FLOAT, GL_FALSE, GLuint(a.offset));
        glVertexArrayAttribBinding(vao, a.location, 0);
    }
    context_.check("uploading mesh " + mesh.name);
    return object;
}

void Renderer::set_mesh(const scene::Mesh& mesh) {
    check_triangles(mesh);
    const glm::mat4 model = unit_sphere_matrix(mesh.bounds, mesh.name);
    std::vector<GpuObject> objects;
    objects.push_back(upload_object(mesh, 0, glm::mat4(1.0f)));
    context_.check("uploading mesh " + mesh.name);
    model_ = model;
    objects_ = std::move(objects);
    materials_ = {scene::Material{"default", 0, {}, {}, {}, {}}};
    material_layers_.clear();
    material_layers_.resize(1);
    for (std::vector<Texture>& textures : surface_maps_) textures.clear();
}

namespace {

// A float texture's level from an image (rows top first): rows bottom first as GL wants them.
std::vector<float> flipped_rows(const Image& image) {
    std::vector<float> out(image.pixels.size());
    const std::size_t row = std::size_t(image.width) * std::size_t(image.channels);
    for (int y = 0; y < image.height; ++y)
        std::copy_n(image.pixels.begin() + std::ptrdiff_t(std::size_t(y) * row), row,
                    out.begin() + std::ptrdiff_t(std::size_t(image.height - 1 - y) * row));
    return out;
}

void set_repeat_trilinear(GLuint texture, int levels) {
    glTextureParameteri(texture, GL_TEXTURE_BASE_LEVEL, 0);
    glTextureParameteri(texture, GL_TEXTURE_MAX_LEVEL, levels - 1);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER,
                        levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(texture, GL_TEXTURE_WRAP_T, GL_REPEAT);
}

GLenum gl_internal_format(scene::MapFormat format) {
    switch (format) {
        case scene::MapFormat::Rgba16f: return GL_RGBA16F;
        case scene::MapFormat::R32f: return GL_R32F;
    }
    return GL_NONE;
}

GLenum gl_pixel_format(int channels) {
    switch (channels) {
        case 1: return GL_RED;
        case 2: return GL_RG;
        case 3: return GL_RGB;
        default: return GL_RGBA;
    }
}

// A surface map of `kind` (scene::Scene::maps, a MIP chain of float images, rows top first) as a
// GL_TEXTURE_2D in the kind's format, rows flipped so that +v is up, repeating, trilinear: every
// level uploaded from the chain (MapMips::Given) or level 0 and the GPU's box filter
// (MapMips::Generated). The roughness map is R32F, not R16F: alpha0^2 = r^4 reaches 1e-8 at
// r = 0.01, below half floats' normal range (6e-5), where a 16-bit float would lose it.
Texture upload_surface_map(const scene::MapKindInfo& kind, const std::vector<Image>& chain) {
    const Image& top = chain.front();
    if (top.width > gl_integer(GL_MAX_TEXTURE_SIZE) || top.height > gl_integer(GL_MAX_TEXTURE_SIZE))
        throw Error(kind.setting.empty() ? std::string(kind.name) : std::string(kind.setting),
                    "larger than GL_MAX_TEXTURE_SIZE (" +
                        std::to_string(gl_integer(GL_MAX_TEXTURE_SIZE)) + ")");
    Texture texture = create_texture(GL_TEXTURE_2D);
    const bool generated = kind.mips == scene::MapMips::Generated;
    const GLsizei levels =
        generated ? GLsizei(mip_level_count(top.width, top.height)) : GLsizei(chain.size());
    glTextureStorage2D(texture.get(), levels, gl_internal_format(kind.format), top.width,
                       top.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (std::size_t level = 0; level < (generated ? 1 : chain.size()); ++level) {
        const Image& image = chain[level];
        const std::vector<float> rows = flipped_rows(image);
        glTextureSubImage2D(texture.get(), GLint(level), 0, 0, image.width, image.height,
                            gl_pixel_format(image.channels), GL_FLOAT, rows.data());
    }
    if (generated) glGenerateTextureMipmap(texture.get());
    set_repeat_trilinear(texture.get(), levels);
    return texture;
}

}  // namespace

void Renderer::set_scene(const scene::Scene& scene) {
    scene::validate(scene);
    for (const scene::Object& o : scene.objects) check_triangles(o.mesh);
    const glm::mat4 model = unit_sphere_matrix(scene::scene_bounds(scene), "scene");
    std::vector<GpuMap> maps;
    for (const PackedLeanMap& map : scene.lean_maps) maps.push_back(upload_map(map));
    for (const scene::Material& m : scene.materials)
        for (const scene::MaterialLayer& layer : m.layered.layers)
            if (scene.lean_maps[std::size_t(layer.lean_map)].roughness_baked)
                throw Error("scene", "material '" + m.name +
                                         "': a bump layer's map has roughness baked in; the base "
                                         "roughness is added once, after mixing");
    std::vector<GpuLayers> layers;
    for (const scene::Material& m : scene.materials) layers.push_back(upload_layers(scene, m));
    std::array<std::vector<Texture>, scene::kMapKindCount> surface_maps;
    for (const scene::MapKindInfo& kind : scene::kMapKinds)
        for (const std::vector<Image>& chain : scene.maps_of(kind.kind))
            surface_maps[std::size_t(kind.kind)].push_back(upload_surface_map(kind, chain));
    std::vector<GpuObject> objects;
    for (const scene::Object& o : scene.objects)
        objects.push_back(upload_object(o.mesh, o.material, o.transform));
    context_.check("uploading the scene");
    model_ = model;
    objects_ = std::move(objects);
    maps_ = std::move(maps);
    materials_ = scene.materials;
    material_layers_ = std::move(layers);
    surface_maps_ = std::move(surface_maps);
}

Renderer::GpuLayers Renderer::upload_layers(const scene::Scene& scene,
                                            const scene::Material& material) {
    GpuLayers result;
    const scene::MaterialLayers& l = material.layered;
    if (l.layers.empty()) return result;
    const int max_size = gl_integer(GL_MAX_TEXTURE_SIZE);
    if (l.mixing == LayerMixing::Textures && !l.cross_terms.empty()) {
        const std::vector<Image>& first = scene.cross_terms[std::size_t(l.cross_terms.front())];
        const int width = first.front().width, height = first.front().height;
        const GLsizei levels = GLsizei(first.size());
        if (width > max_size || height > max_size || levels > mip_level_count(width, height))
            throw Error("scene", "material '" + material.name +
                                     "': a cross-term texture is too large or has too many levels");
        result.cross_terms = create_texture(GL_TEXTURE_2D_ARRAY);
        const GLuint texture = result.cross_terms.get();
        glTextureStorage3D(texture, levels, GL_RGBA32F, width, height,
                           GLsizei(l.cross_terms.size()));
        for (std::size_t pair = 0; pair < l.cross_terms.size(); ++pair) {
            const std::vector<Image>& chain = scene.cross_terms[std::size_t(l.cross_terms[pair])];
            if (GLsizei(chain.size()) != levels)
                throw Error("scene", "material '" + material.name +
                                         "': its cross-term textures differ in size");
            int w = width, h = height;
            for (GLsizei level = 0; level < levels; ++level) {
                const Image& image = chain[std::size_t(level)];
                if (image.width != w || image.height != h || image.channels != 4)
                    throw Error("scene", "material '" + material.name +
                                             "': its cross-term textures differ in size");
                const std::vector<float> rows = flipped_rows(image);
                glTextureSubImage3D(texture, level, 0, 0, GLint(pair), w, h, 1, GL_RGBA, GL_FLOAT,
                                    rows.data());
                w = std::max(1, w / 2);
                h = std::max(1, h / 2);
            }
        }
        set_repeat_trilinear(texture, levels);
    }
    if (l.mixing == LayerMixing::Height) {
        // One map over the surface's uv square, as fine as the finest layer x its tiling.
        float bound = 0.0f;
        Storage storage = Storage::Unorm8;
        for (std::size_t i = 0; i < l.layers.size(); ++i) {
            const PackedLeanMap& map = scene.lean_maps[std::size_t(l.layers[i].lean_map)];
            // |sum t_i k_i B_i| <= sum |t_i k_i| sc_i per axis: the mixed map's sc.
            const float weight = l.weight_map >= 0 ? 1.0f : l.weights[i];
            bound += weight * std::abs(l.layers[i].strength) * map.scale;
            // The widest of the layers' storages: float when one keeps slopes beyond its sc.
            storage = std::max(storage, map.storage);
        }
        const glm::ivec2 size = scene::mixed_map_size(scene, material);
        result.mixer = std::make_unique<LeanGenerator>(context_, sources_);
        result.mixer->set_layer_source(size.x, size.y);
        result.mixed.scale = bound > 0.0f ? bound : 1.0f;
        result.mixed.storage = storage;
    }
    if (l.weight_map >= 0) {
        const Image& image = scene.weight_maps[std::size_t(l.weight_map)];
        if (image.width > max_size || image.height > max_size)
            throw Error("layer-weight-map", "larger than GL_MAX_TEXTURE_SIZE");
        const int levels = mip_level_count(image.width, image.height);
        result.weights = create_texture(GL_TEXTURE_2D);
        glTextureStorage2D(result.weights.get(), levels, GL_RGBA32F, image.width, image.height);
        const std::vector<float> rows = flipped_rows(image);
        glTextureSubImage2D(result.weights.get(), 0, 0, 0, image.width, image.height, GL_RGBA,
                            GL_FLOAT, rows.data());
        // Box-filtered weights still sum to 1 per texel: the mix stays a convex combination.
        glGenerateTextureMipmap(result.weights.get());
        set_repeat_trilinear(result.weights.get(), levels);
    }
    context_.check("uploading the bump layers of material " + material.name);
    return result;
}

Renderer::GpuMap Renderer::upload_map(const PackedLeanMap& map) {
    if (map.levels.empty()) throw Error("LEAN map", "the map has no levels");
    const int width = map.levels[0].width, height = map.levels[0].height;
    if (width < 1 || height < 1) throw Error("LEAN map", "the top level is empty");
    if (width > gl_integer(GL_MAX_TEXTURE_SIZE) || height > gl_integer(GL_MAX_TEXTURE_SIZE))
        throw Error("LEAN map", "the map is larger than GL_MAX_TEXTURE_SIZE (" +
                                    std::to_string(gl_integer(GL_MAX_TEXTURE_SIZE)) + ")");
    if (int(map.levels.size()) > mip_level_count(width, height))
        throw Error("LEAN map", "more MIP levels than the top level's size allows");
    const std::size_t texel_bytes = std::size_t(bytes_per_texel(map.storage));
    int w = width, h = height;
    for (std::size_t i = 0; i < map.levels.size(); ++i) {
        const PackedLevel& level = map.levels[i];
        const std::size_t bytes = std::size_t(w) * std::size_t(h) * texel_bytes;
        if (level.width != w || level.height != h || level.lean1.size() != bytes ||
            level.lean2.size() != bytes)
            throw Error("LEAN map", "level " + std::to_string(i) + " has the wrong size");
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }

    const StorageFormat format = storage_format(map.storage);
    Texture texture = create_texture(GL_TEXTURE_2D_ARRAY);
    const GLsizei levels = GLsizei(map.levels.size());
    glTextureStorage3D(texture.get(), levels, format.internal_format, width, height, 2);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (GLsizei i = 0; i < levels; ++i) {
        const PackedLevel& level = map.levels[std::size_t(i)];
        const std::size_t row_bytes = std::size_t(level.width) * texel_bytes;
        const std::vector<std::uint8_t>* slices[2] = {&level.lean1, &level.lean2};
        for (int slice = 0; slice < 2; ++slice) {
            const std::vector<std::uint8_t> rows = flipped(*slices[slice], row_bytes, level.height);
            glTextureSubImage3D(texture.get(), i, 0, 0, slice, level.width, level.height, 1,
                                GL_RGBA, format.type, rows.data());
        }
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    // A map whose chain stops early is still complete: trilinear uses the levels it has.
    set_repeat_trilinear(texture.get(), levels);
    context_.check("uploading the LEAN map");

    GpuMap result;
    result.texture = std::move(texture);
    result.info.width = width;
    result.info.height = height;
    result.info.levels = levels;
    result.info.storage = map.storage;
    result.info.scale = map.scale;
    result.info.roughness_baked = map.roughness_baked;
    return result;
}

void Renderer::set_lean_map(const PackedLeanMap& map) {
    GpuMap uploaded = upload_map(map);
    maps_.clear();
    maps_.push_back(std::move(uploaded));
    for (scene::Material& m : materials_) {
        m.lean_map = 0;
        m.layered = {};
    }
    material_layers_.clear();
    material_layers_.resize(materials_.size());
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
    if (!std::isfinite(time)) throw Error("time", "must be a finite number of seconds");
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
    for (const GpuObject& object : objects_) {
        const scene::Material& material = materials_[std::size_t(object.material)];
        const GpuMap& map = maps_[std::size_t(material.lean_map)];
        // The "height" method draws its generated map (update_mixed_layers) like a single map.
        const GpuLayers& material_layers = material_layers_[std::size_t(object.material)];
        const LeanGenerator* mixer = material_layers.mixer.get();
        const GLuint map_texture = mixer != nullptr ? mixer->texture() : map.texture.get();
        const float map_scale = mixer != nullptr ? material_layers.mixed.scale : map.info.scale;
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
        LfShadingUniforms block{};
        // A layered material's maps have no baked roughness: 1/s is added once, after mixing.
        block.params =
            to_lf_params(s, !layered && mixer == nullptr && map.info.roughness_baked);
        block.scale = map_scale;
        block.output_mode = output_constant(request.output);
        block.fog_mode = to_shader_constant(s.fog);
        block.fog_start = s.fog_start;
        block.fog_color = s.fog_color;
        block.fog_end = s.fog_end;
        block.fog_density = s.fog_density;
        // The material's surface maps: each on its unit with its bit in the block's mask, or the
        // kind's fallback (docs/math.md §9: Cook-Torrance's base roughness per texel).
        block.maps = 0;
        for (const scene::MapKindInfo& kind : scene::kMapKinds) {
            const int slot = material.map(kind.kind);
            const bool read = slot >= 0 && (!kind.cook_torrance_only || s.brdf == Brdf::CookTorrance);
            if (read) block.maps |= kind.mask_bit;
            GLuint texture = 0;
            if (read) {
                texture = surface_maps_[std::size_t(kind.kind)][std::size_t(slot)].get();
            } else if (kind.fallback == scene::MapFallback::White) {
                if (white_.get() == 0)
                    white_ = upload_surface_map(scene::info(scene::MapKind::BaseColor),
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
    if (!std::isfinite(request.time)) throw Error("time", "must be a finite number of seconds");
    const int max_size =
        std::min(gl_integer(GL_MAX_TEXTURE_SIZE), gl_integer(GL_MAX_RENDERBUFFER_SIZE));
    if (request.width < 1 || request.height < 1 || request.width > max_size ||
        request.height > max_size)
        throw Error("size", "image size must be 1.." + std::to_string(max_size) +
                                  " pixels, got " + std::to_string(request.width) + "x" +
                                  std::to_string(request.height));
    if (request.technique == Technique::Reference &&
        (request.reference_samples < 1 || request.reference_samples > kMaxReferenceSamples))
        throw Error("ref_samples", "must be in [1, " + std::to_string(kMaxReferenceSamples) +
                                         "], got " + std::to_string(request.reference_samples));
    const ShadingSettings& s = request.settings;
    int samples = request.technique == Technique::Reference ? 1 : s.msaa;
    if (samples > gl_integer(GL_MAX_SAMPLES))
        throw Error("msaa", std::to_string(samples) +
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
        throw Error("aniso", "anisotropic filtering is not supported by " + context_.renderer());
    std::vector<GLuint> textures;
    for (const GpuMap& map : maps_) textures.push_back(map.texture.get());
    for (const GpuLayers& layers : material_layers_) {
        for (const Texture* t : {&layers.cross_terms, &layers.weights})
            if (t->get() != 0) textures.push_back(t->get());
        if (layers.mixer && layers.mixer->texture() != 0)
            textures.push_back(layers.mixer->texture());
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
        throw Error("size", "the viewport must be at least 1x1 pixels");
    validate(request.settings);
    if (!std::isfinite(request.time)) throw Error("time", "must be a finite number of seconds");
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
