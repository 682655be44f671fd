// The renderer's GPU copy of a scene: meshes, LEAN maps, bump layers and surface maps.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/shading_block.hpp"
#include "leanfade/scene/detail/vertex_layout.hpp"
#include "renderer_internal.hpp"

namespace leanfade::gl {
namespace {

using detail::gl_integer;

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

// A float texture's level from an image (rows top first): rows bottom first as GL wants them.
std::vector<float> flipped_rows(const Image& image) {
    std::vector<float> out(image.pixels.size());
    const std::size_t row = std::size_t(image.width) * std::size_t(image.channels);
    for (int y = 0; y < image.height; ++y)
        std::copy_n(image.pixels.begin() + std::ptrdiff_t(std::size_t(y) * row), row,
                    out.begin() + std::ptrdiff_t(std::size_t(image.height - 1 - y) * row));
    return out;
}

GLenum gl_internal_format(scene::MapFormat format) {
    switch (format) {
        case scene::MapFormat::Rgba16f:
            return GL_RGBA16F;
        case scene::MapFormat::R32f:
            return GL_R32F;
    }
    return GL_NONE;
}

GLenum gl_pixel_format(int channels) {
    switch (channels) {
        case 1:
            return GL_RED;
        case 2:
            return GL_RG;
        case 3:
            return GL_RGB;
        default:
            return GL_RGBA;
    }
}

// A surface map of `kind` (scene::Scene::maps, a MIP chain of float images, rows top first) as a
// GL_TEXTURE_2D in the kind's format, rows flipped so that +v is up, repeating, trilinear: every
// level uploaded from the chain (MapMips::Given) or level 0 and the GPU's box filter
// (MapMips::Generated). The roughness map is R32F, not R16F: alpha0^2 = r^4 reaches 1e-8 at
// r = 0.01, below half floats' normal range (6e-5), where a 16-bit float would lose it.
}  // namespace

Texture detail::upload_surface_map(const scene::MapKindInfo& kind,
                                   const std::vector<Image>& chain) {
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
    // Half-float kinds are converted here (round to nearest, as the bake's half floats), not by
    // the driver: drivers round float -> half differently (Mesa's llvmpipe toward zero), which
    // moved two-lobe LEAN's spike by 0.5 % between GPUs.
    const bool half = kind.format == scene::MapFormat::Rgba16f;
    glPixelStorei(GL_UNPACK_ALIGNMENT, half ? 2 : 4);
    for (std::size_t level = 0; level < (generated ? 1 : chain.size()); ++level) {
        const Image& image = chain[level];
        const std::vector<float> rows = flipped_rows(image);
        if (half) {
            std::vector<std::uint16_t> halves(rows.size());
            for (std::size_t i = 0; i < rows.size(); ++i) halves[i] = glm::packHalf1x16(rows[i]);
            glTextureSubImage2D(texture.get(), GLint(level), 0, 0, image.width, image.height,
                                gl_pixel_format(image.channels), GL_HALF_FLOAT, halves.data());
        } else {
            glTextureSubImage2D(texture.get(), GLint(level), 0, 0, image.width, image.height,
                                gl_pixel_format(image.channels), GL_FLOAT, rows.data());
        }
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (generated) glGenerateTextureMipmap(texture.get());
    set_repeat_trilinear(texture.get(), levels);
    return texture;
}

Renderer::GpuObject Renderer::upload_object(const scene::Mesh& mesh, int material,
                                            const glm::mat4& transform) {
    GpuObject object;
    object.material = material;
    object.transform = transform;
    object.centre = mesh.bounds.center();
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
    for (const scene::VertexAttribute& a : scene::kVertexAttributes) {
        const GLuint location = GLuint(a.location);
        glEnableVertexArrayAttrib(vao, location);
        glVertexArrayAttribFormat(vao, location, a.components, GL_FLOAT, GL_FALSE,
                                  GLuint(a.offset));
        glVertexArrayAttribBinding(vao, location, 0);
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

// A glTF material's factors in their ranges (glTF 2.0 §3.9.2-3.9.5, KHR_materials_anisotropy):
// metalness, occlusion strength and anisotropy strength in [0, 1], the emission finite and >= 0,
// the rotation finite.
void check_material_factors(const scene::Material& m) {
    const auto in_unit_range = [](float v) { return v >= 0.0f && v <= 1.0f; };
    const auto refuse = [&](const std::string& what) {
        throw Error("scene", "material '" + m.name + "': its " + what);
    };
    if (m.metallic && !in_unit_range(*m.metallic)) refuse("metallic factor is not in [0, 1]");
    if (!in_unit_range(m.occlusion_strength)) refuse("occlusion strength is not in [0, 1]");
    for (int c = 0; c < 3; ++c)
        if (!(std::isfinite(m.emissive[c]) && m.emissive[c] >= 0.0f))
            refuse("emissive factor is not finite and >= 0");
    if (!in_unit_range(m.anisotropy_strength)) refuse("anisotropy strength is not in [0, 1]");
    if (!std::isfinite(m.anisotropy_rotation)) refuse("anisotropy rotation is not finite");
}

}  // namespace

void Renderer::set_scene(const scene::Scene& scene) {
    scene::validate(scene);
    for (const scene::Material& m : scene.materials) check_material_factors(m);
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
            surface_maps[std::size_t(kind.kind)].push_back(detail::upload_surface_map(kind, chain));
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
        result.mixed.scale = bound > 0.0f ? bound : 1.0f;  // (a bound in either encoding)
        result.mixed.storage = storage;
    }
    if (l.weight_map >= 0) {
        const Image& image = scene.weight_maps[std::size_t(l.weight_map)];
        if (image.width > max_size || image.height > max_size)
            throw Error::setting("layer-weight-map", "larger than GL_MAX_TEXTURE_SIZE");
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
        // The layers every map has (lean1, lean2: kLeanLayers' first rows) are the array's
        // slices; the plateau layer becomes its surface map (MapKind::Plateau, decoded).
        for (const LeanLayerInfo& row : kLeanLayers) {
            if (row.optional) continue;
            const std::vector<std::uint8_t> rows =
                flipped(level.slice(row.layer), row_bytes, level.height);
            glTextureSubImage3D(texture.get(), i, 0, 0, GLint(row.layer), level.width, level.height,
                                1, GL_RGBA, format.type, rows.data());
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
    result.info.lean_offset = lean_offset(map.encoding);
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

}  // namespace leanfade::gl
