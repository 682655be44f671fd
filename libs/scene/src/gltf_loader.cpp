// glTF 2.0 loading (leanfade/scene/gltf.hpp): tinygltf parses the JSON and the GLB container;
// everything it hands over is checked here before use (indices, accessor and buffer-view ranges,
// finite values, the node tree), and the files it may read are confined to the glTF's folder.
//
// tinygltf is compiled without its image decoder and without its file system access: images are
// kept encoded (decoded later by the project's readers) and external files are read through
// read_confined(), which refuses paths outside the folder, non-regular files and large files.
// tinygltf's implementation is gltf_tinygltf.cpp and the JSON pre-checks gltf_checks.cpp
// (gltf_internal.hpp). The POSIX and JSON headers come first: tiny_gltf.h includes
// nlohmann/json.hpp under `#pragma GCC visibility push(hidden)`, which would hide libc functions
// first declared there.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "gltf_internal.hpp"
#include "leanfade/scene/gltf.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using gltf_detail::check_json;
using gltf_detail::check_json_depth;
using gltf_detail::glb_json_chunk;
using gltf_detail::images_used_by_materials;

// tinygltf takes 32-bit sizes.
constexpr std::uint64_t kLargestFile = std::numeric_limits<std::uint32_t>::max() - 1;

// The first line of `text`, without trailing spaces: tinygltf's messages end with newlines.
std::string first_line(const std::string& text) {
    std::string line = text.substr(0, text.find('\n'));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    return line;
}

// Reads a whole regular file of at most `max_bytes` without blocking on a FIFO or a device.
// Returns an empty string on success, else the cause.
std::string read_file(const std::string& path, std::uint64_t max_bytes,
                      std::vector<std::uint8_t>& bytes) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return std::strerror(errno);
    struct FdCloser {
        int fd;
        ~FdCloser() { ::close(fd); }
    } closer{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0) return std::strerror(errno);
    if (S_ISDIR(info.st_mode)) return "is a folder";
    if (!S_ISREG(info.st_mode)) return "is not a regular file";
    if (const std::string output = claimed_output(info.st_dev, info.st_ino); !output.empty())
        return claimed_output_cause(output);
    const std::uint64_t size = std::uint64_t(info.st_size);
    if (size > max_bytes)
        return "is " + std::to_string(size) + " bytes, more than the limit of " +
               std::to_string(max_bytes);
    bytes.resize(std::size_t(size));
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t got = ::read(fd, bytes.data() + done, bytes.size() - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) return std::strerror(errno);
        if (got == 0) return "was truncated while it was read";
        done += std::size_t(got);
    }
    return {};
}

}  // namespace

UvTransform leanfade_uv_transform(const GltfTextureTransform& t) {
    // glTF's M = T R S (R = [cos sin; -sin cos]), conjugated by the flip F(u, v) = (u, 1 - v):
    // uv'_leanfade = F(M F(uv)).
    const double c = std::cos(double(t.rotation)), s = std::sin(double(t.rotation));
    const glm::dmat3 translation(1, 0, 0, 0, 1, 0, t.offset.x, t.offset.y, 1);  // columns
    const glm::dmat3 rotation(c, -s, 0, s, c, 0, 0, 0, 1);
    const glm::dmat3 scale(t.scale.x, 0, 0, 0, t.scale.y, 0, 0, 0, 1);
    const glm::dmat3 flip(1, 0, 0, 0, -1, 0, 0, 1, 1);
    const glm::dmat3 m = flip * translation * rotation * scale * flip;
    UvTransform out;
    out.row0 = glm::vec3(float(m[0][0]), float(m[1][0]), float(m[2][0]));
    out.row1 = glm::vec3(float(m[0][1]), float(m[1][1]), float(m[2][1]));
    out.set = t.tex_coord;
    return out;
}

std::string gltf_uri_path(const std::string& uri) {
    std::string out;  // percent-decoded: invalid escapes stay as they are
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// Why an external URI may not be read ("" when it may): leanfade reads only files inside the
// glTF's folder, named by relative paths.
std::string gltf_detail::uri_refusal(const std::string& uri, bool external_allowed) {
    if (uri.rfind("data:", 0) == 0) return {};
    if (!external_allowed) return "refers to an external file, which is not read here";
    const std::string path = gltf_uri_path(uri);
    if (path.empty()) return "is empty";
    if (path.find('\0') != std::string::npos) return "contains a NUL character";
    if (path.front() == '/' || path.front() == '\\') return "is an absolute path";
    const std::size_t colon = path.find(':');
    if (colon != std::string::npos && path.find_first_of("/\\") > colon)
        return "has a scheme or drive letter (only relative file paths are read)";
    std::size_t start = 0;
    while (start <= path.size()) {
        const std::size_t end = std::min(path.find_first_of("/\\", start), path.size());
        if (path.compare(start, end - start, "..") == 0 && end - start == 2)
            return "leaves the glTF's folder ('..')";
        start = end + 1;
    }
    return {};
}

namespace {

using gltf_detail::uri_refusal;

// A glTF colour factor of `count` values (baseColorFactor, emissiveFactor; glTF 2.0 §5.19), each
// finite and >= 0, into out[0 .. count - 1]; `what` names it in the errors.
void read_color_factor(const std::vector<double>& factor, std::size_t count,
                       const std::string& what, float* out) {
    if (factor.size() != count)
        throw std::runtime_error(what + " has " + std::to_string(factor.size()) +
                                 " values (expected " + std::to_string(count) + ")");
    for (std::size_t c = 0; c < count; ++c) {
        if (!std::isfinite(factor[c]) || factor[c] < 0.0)
            throw std::runtime_error(what + " is not finite and >= 0");
        out[c] = float(factor[c]);
    }
}

// What tinygltf may read: files in `folder` only (its file system callbacks below).
struct FileAccess {
    bool external_allowed = false;
    fs::path folder;  // absolute, lexically normal
    std::uint64_t max_bytes = 0;
    std::string refused;  // the first refusal's message
};

// The path tinygltf asks for, if it lies inside the folder; else empty. Checked on the name and
// then on the resolved path (symbolic links followed): a link inside the folder that points out
// of it is outside.
std::string confined(const std::string& requested, FileAccess& access) {
    if (!access.external_allowed) return {};
    const fs::path path = fs::path(requested).lexically_normal();
    if (!path.is_absolute()) return {};  // tinygltf's second try, relative to the working folder
    const fs::path relative = path.lexically_relative(access.folder);
    if (relative.empty() || *relative.begin() == "..") return {};
    std::error_code error;
    const fs::path folder = fs::weakly_canonical(access.folder, error);
    if (error) return {};
    const fs::path resolved = fs::weakly_canonical(path, error);
    if (error) return {};
    const fs::path inside = resolved.lexically_relative(folder);
    if (inside.empty() || *inside.begin() == "..") return {};
    return resolved.string();
}

bool file_exists(const std::string& path, void* user) {
    FileAccess& access = *static_cast<FileAccess*>(user);
    if (!access.external_allowed) return false;
    // By its name only: a link out of the folder is then refused by read_whole_file, naming it.
    const fs::path normal = fs::path(path).lexically_normal();
    if (!normal.is_absolute()) return false;
    const fs::path relative = normal.lexically_relative(access.folder);
    if (relative.empty() || *relative.begin() == "..") return false;
    std::error_code error;
    return fs::exists(normal, error);
}

std::string expand_file_path(const std::string& path, void*) {
    return path;  // no ~ or variable expansion
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* user) {
    FileAccess& access = *static_cast<FileAccess*>(user);
    const std::string inside = confined(path, access);
    std::string cause = inside.empty() ? "lies outside the glTF's folder"
                                       : read_file(inside, access.max_bytes, *out);
    if (cause.empty()) return true;
    const std::string name = fs::path(path).lexically_normal().lexically_relative(access.folder);
    if (access.refused.empty()) access.refused = escape_text(name) + ": " + cause;
    if (err != nullptr) *err += escape_text(name) + ": " + cause + "\n";
    return false;
}

// The images tinygltf hands to its image callback: only those a material references are kept,
// and their bytes together within a budget, counted before each copy.
struct ImageKeeping {
    std::vector<bool> used;    // by glTF image index
    std::uint64_t limit = 0;   // bytes in all
    std::uint64_t budget = 0;  // bytes left
    std::string refused;       // the first refusal's message
};

// tinygltf's image callback: keep the encoded bytes (decoded later by the project's readers) of
// the images a material uses; the others stay empty.
bool keep_encoded_image(tinygltf::Image* image, const int index, std::string* err, std::string*,
                        int, int, const unsigned char* bytes, int size, void* user) {
    ImageKeeping& keeping = *static_cast<ImageKeeping*>(user);
    image->width = image->height = -1;  // not decoded
    if (index < 0 || std::size_t(index) >= keeping.used.size() || !keeping.used[std::size_t(index)])
        return true;
    const auto count = std::uint64_t(std::max(size, 0));
    if (count > keeping.budget) {
        if (keeping.refused.empty())
            keeping.refused = "image " + std::to_string(index) + ": the images the materials " +
                              "use exceed the limit of " + std::to_string(keeping.limit) +
                              " bytes of encoded data";
        if (err != nullptr) *err += keeping.refused + "\n";
        return false;
    }
    keeping.budget -= count;
    image->image.assign(bytes, bytes + count);
    return true;
}

// ---------------------------------------------------------------------------------------------
// Accessors.

struct AccessorData {
    const std::uint8_t* data = nullptr;
    std::size_t count = 0;
    std::size_t stride = 0;
    int component_type = 0;
    int components = 0;
    bool normalized = false;
};

int component_bytes(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

int component_count(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;
    }
}

// A texture reference's texCoord, checked: glTF 2.0's textureInfo.texCoord is an integer >= 0.
int checked_tex_coord(int tex_coord, const std::string& where) {
    if (tex_coord < 0)
        throw std::runtime_error(where + ": texCoord is not a texture coordinate set");
    return tex_coord;
}

// Where a texture reference samples: its KHR_texture_transform `e` (offset, rotation, scale,
// checked finite) and its set, the extension's texCoord when it has one (it overrides the
// reference's, KHR_texture_transform), else the reference's `tex_coord`. Any set >= 0 is kept
// here; Converter::supported_set reads the sets above 1 as 0.
GltfTextureTransform texture_transform_of(const tinygltf::Value& e, int tex_coord,
                                          const std::string& where) {
    GltfTextureTransform t;
    t.tex_coord = checked_tex_coord(tex_coord, where);
    if (!e.IsObject()) throw std::runtime_error(where + ": KHR_texture_transform is not an object");
    const auto number = [&](const tinygltf::Value& v, const char* what) {
        if (!v.IsNumber()) throw std::runtime_error(where + ": KHR_texture_transform " + what + " is not a number");
        const double d = v.GetNumberAsDouble();
        if (!std::isfinite(d)) throw std::runtime_error(where + ": KHR_texture_transform " + what + " is not finite");
        return float(d);
    };
    const auto pair = [&](const char* key, glm::vec2& out) {
        if (!e.Has(key)) return;
        const tinygltf::Value& v = e.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2)
            throw std::runtime_error(where + ": KHR_texture_transform " + key + " is not 2 numbers");
        out = glm::vec2(number(v.Get(0), key), number(v.Get(1), key));
    };
    pair("offset", t.offset);
    pair("scale", t.scale);
    if (e.Has("rotation")) t.rotation = number(e.Get("rotation"), "rotation");
    if (e.Has("texCoord")) {
        const tinygltf::Value& set = e.Get("texCoord");
        if (!set.IsInt() || set.Get<int>() < 0)
            throw std::runtime_error(where +
                                     ": KHR_texture_transform texCoord is not a texture "
                                     "coordinate set");
        t.tex_coord = set.Get<int>();
    }
    return t;
}

// A textureInfo's transform and set (texture_transform_of), from its extensions and texCoord.
GltfTextureTransform texture_transform(const tinygltf::ExtensionMap& extensions, int tex_coord,
                                       const std::string& where) {
    const auto found = extensions.find("KHR_texture_transform");
    if (found == extensions.end()) {
        GltfTextureTransform t;
        t.tex_coord = checked_tex_coord(tex_coord, where);
        return t;
    }
    return texture_transform_of(found->second, tex_coord, where);
}

// A texture reference inside an extension's object (tinygltf leaves those as JSON values): its
// texture index (-1: none), and its KHR_texture_transform with its set (texture_transform_of).
struct ExtensionTextureInfo {
    int index = -1;
    GltfTextureTransform transform;
};

ExtensionTextureInfo extension_texture_info(const tinygltf::Value& info, const std::string& where) {
    ExtensionTextureInfo out;
    if (!info.IsObject()) throw std::runtime_error(where + " is not an object");
    const tinygltf::Value& index = info.Get("index");
    if (!index.IsInt() || index.Get<int>() < 0)
        throw std::runtime_error(where + ": index is not a texture index");
    out.index = index.Get<int>();
    int tex_coord = 0;
    if (info.Has("texCoord")) {
        const tinygltf::Value& set = info.Get("texCoord");
        if (!set.IsInt() || set.Get<int>() < 0)
            throw std::runtime_error(where + ": texCoord is not a texture coordinate set");
        tex_coord = set.Get<int>();
    }
    out.transform.tex_coord = tex_coord;
    const tinygltf::Value& extensions = info.Get("extensions");
    if (extensions.IsObject() && extensions.Has("KHR_texture_transform"))
        out.transform =
            texture_transform_of(extensions.Get("KHR_texture_transform"), tex_coord, where);
    return out;
}

class Converter {
  public:
    // The encoded images move out of `model` into the scene.
    Converter(tinygltf::Model& model, const GltfLoadOptions& options, GltfScene& out,
              FileAccess& access)
        : model_(model), options_(options), out_(out), access_(access) {}

    void run();

  private:
    AccessorData accessor(int index, const std::string& what) const;
    Mesh primitive_mesh(int mesh_index, int primitive_index, const GltfMaterial& material);
    int material_index(int gltf_material);
    int image_of_texture(int texture, const std::string& where);
    glm::dmat4 local_matrix(const tinygltf::Node& node, int index) const;

    tinygltf::Model& model_;
    const GltfLoadOptions& options_;
    GltfScene& out_;
    FileAccess& access_;  // where external files may be read
    std::map<std::pair<int, int>, Mesh> meshes_;  // converted (mesh, primitive)
    std::map<int, int> materials_;                // glTF material (-1: default) -> ours
    std::map<int, int> images_;                   // glTF image -> ours
    std::size_t vertices_ = 0;
    std::size_t indices_ = 0;
};

AccessorData Converter::accessor(int index, const std::string& what) const {
    const std::string where = what + " (accessor " + std::to_string(index) + ")";
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
        throw std::runtime_error(where + " does not exist (" +
                                 std::to_string(model_.accessors.size()) + " accessors)");
    const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
    if (a.sparse.isSparse) throw std::runtime_error(where + ": sparse accessors are not supported");
    if (a.bufferView < 0 || std::size_t(a.bufferView) >= model_.bufferViews.size())
        throw std::runtime_error(where + ": no valid buffer view");
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(a.bufferView)];
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
        throw std::runtime_error(where + ": buffer view " + std::to_string(a.bufferView) +
                                 " has no valid buffer");
    const std::vector<unsigned char>& buffer = model_.buffers[std::size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        throw std::runtime_error(where + ": buffer view " + std::to_string(a.bufferView) +
                                 " lies outside its buffer");
    AccessorData d;
    d.component_type = a.componentType;
    d.components = component_count(a.type);
    d.normalized = a.normalized;
    d.count = a.count;
    const std::size_t element = std::size_t(component_bytes(a.componentType)) *
                                std::size_t(d.components);
    if (element == 0) throw std::runtime_error(where + ": unknown component or element type");
    d.stride = view.byteStride != 0 ? view.byteStride : element;
    if (d.stride < element)
        throw std::runtime_error(where + ": byte stride " + std::to_string(d.stride) +
                                 " is smaller than an element");
    if (d.count > 0) {
        const std::size_t length = view.byteLength;
        if (a.byteOffset > length || element > length - a.byteOffset ||
            d.count - 1 > (length - a.byteOffset - element) / d.stride)
            throw std::runtime_error(where + ": " + std::to_string(d.count) +
                                     " elements do not fit in buffer view " +
                                     std::to_string(a.bufferView) + " (" +
                                     std::to_string(length) + " bytes)");
    }
    d.data = buffer.data() + view.byteOffset + a.byteOffset;
    return d;
}

// Element i of a float accessor (or normalised unsigned integers), `n` components.
void read_float_element(const AccessorData& d, std::size_t i, int n, float* out) {
    const std::uint8_t* p = d.data + i * d.stride;
    for (int c = 0; c < n; ++c) {
        switch (d.component_type) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&out[c], p + 4 * c, 4); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out[c] = float(p[c]) / 255.0f; break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t v = 0;
                std::memcpy(&v, p + 2 * c, 2);
                out[c] = float(v) / 65535.0f;
                break;
            }
            default: out[c] = 0.0f;
        }
    }
}

void require_float(const AccessorData& d, int components, const std::string& what,
                   bool normalized_unsigned_allowed = false) {
    const bool is_float = d.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool is_unorm = d.normalized &&
                          (d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                           d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    if (d.components != components || !(is_float || (normalized_unsigned_allowed && is_unorm)))
        throw std::runtime_error(what + ": expected " + std::to_string(components) +
                                 (normalized_unsigned_allowed
                                      ? " float or normalised unsigned components"
                                      : " float components"));
}

glm::vec3 face_normal(const Mesh& mesh, const std::uint32_t* corner) {
    const glm::dvec3 p0(mesh.vertices[corner[0]].position);
    const glm::dvec3 n = glm::cross(glm::dvec3(mesh.vertices[corner[1]].position) - p0,
                                    glm::dvec3(mesh.vertices[corner[2]].position) - p0);
    return glm::vec3(n);  // length = twice the area: the area weight
}

// The (image, where it samples) pairs of a material's textures; image -1: none. The normal
// texture's stands for the LEAN map too (a LEANFADE_lean_map file is sampled as it would be).
std::array<std::pair<int, const GltfTextureTransform*>, 6> material_textures(
    const GltfMaterial& m) {
    const int normal =
        m.normal_image >= 0 || !m.lean_map_file.empty() || !m.lean_map_bytes.empty() ? 0 : -1;
    return {{{normal, &m.normal_transform},
             {m.base_color_image, &m.base_color_transform},
             {m.metallic_roughness_image, &m.metallic_roughness_transform},
             {m.occlusion_image, &m.occlusion_transform},
             {m.emissive_image, &m.emissive_transform},
             {m.anisotropy_image, &m.anisotropy_transform}}};
}

// The set a primitive's generated tangents follow: the normal texture's, whose slopes are in
// that frame (glTF 2.0 §3.7.2.1: tangents a file lacks are computed with MikkTSpace from "the
// texture coordinates associated with the normal texture"); without one the anisotropy
// texture's, whose directions are in the same tangent frame (KHR_materials_anisotropy); else
// TEXCOORD_0.
int tangent_set(const GltfMaterial& m) {
    if (m.normal_image >= 0 || !m.lean_map_file.empty() || !m.lean_map_bytes.empty())
        return m.normal_transform.tex_coord;
    if (m.anisotropy_image >= 0) return m.anisotropy_transform.tex_coord;
    return 0;
}

Mesh Converter::primitive_mesh(int mesh_index, int primitive_index, const GltfMaterial& material) {
    const tinygltf::Mesh& gm = model_.meshes[std::size_t(mesh_index)];
    const tinygltf::Primitive& prim = gm.primitives[std::size_t(primitive_index)];
    Mesh mesh;
    mesh.name = gm.name.empty() ? "mesh " + std::to_string(mesh_index) : gm.name;
    if (gm.primitives.size() > 1) mesh.name += " primitive " + std::to_string(primitive_index);
    const std::string where = "mesh '" + escape_text(mesh.name, 64) + "'";

    const auto attribute = [&](const char* name) {
        const auto it = prim.attributes.find(name);
        return it == prim.attributes.end() ? -1 : it->second;
    };
    const int position_accessor = attribute("POSITION");
    if (position_accessor < 0) throw std::runtime_error(where + " has no POSITION");
    const AccessorData positions = accessor(position_accessor, where + " POSITION");
    require_float(positions, 3, where + " POSITION");
    const std::size_t n = positions.count;
    if (n > options_.max_vertices - std::min(vertices_, options_.max_vertices))
        throw std::runtime_error(where + ": more than " + std::to_string(options_.max_vertices) +
                                 " vertices in the scene");
    mesh.vertices.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        float p[3];
        read_float_element(positions, i, 3, p);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw std::runtime_error(where + ": POSITION " + std::to_string(i) +
                                     " is not finite");
        mesh.vertices[i].position = glm::vec3(p[0], p[1], p[2]);
    }

    // Indices, as a triangle list.
    std::vector<std::uint32_t> order;
    if (prim.indices >= 0) {
        const AccessorData idx = accessor(prim.indices, where + " indices");
        const bool integer = idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                             idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                             idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        if (idx.components != 1 || !integer)
            throw std::runtime_error(where + " indices: expected unsigned integer scalars");
        order.resize(idx.count);
        for (std::size_t i = 0; i < idx.count; ++i) {
            const std::uint8_t* p = idx.data + i * idx.stride;
            std::uint32_t v = 0;
            if (idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                v = p[0];
            } else if (idx.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
                std::uint16_t s = 0;
                std::memcpy(&s, p, 2);
                v = s;
            } else {
                std::memcpy(&v, p, 4);
            }
            if (v >= n)
                throw std::runtime_error(where + ": index " + std::to_string(v) +
                                         " out of range (" + std::to_string(n) + " vertices)");
            order[i] = v;
        }
    } else {
        if (n > std::numeric_limits<std::uint32_t>::max())
            throw std::runtime_error(where + ": too many vertices");
        order.resize(n);
        for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(i);
    }
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (order.size() % 3 != 0)
            throw std::runtime_error(where + ": " + std::to_string(order.size()) +
                                     " indices are not a whole number of triangles");
        mesh.indices = std::move(order);
    } else {
        for (std::size_t i = 2; i < order.size(); ++i) {
            std::uint32_t a = order[i - 2], b = order[i - 1], c = order[i];
            if (mode == TINYGLTF_MODE_TRIANGLE_FAN) a = order[0];
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP && (i % 2) == 1) std::swap(a, b);
            mesh.indices.insert(mesh.indices.end(), {a, b, c});
        }
    }
    if (mesh.indices.empty()) throw std::runtime_error(where + " has no triangles");

    // Texture coordinates, flipped to v up: TEXCOORD_0 in uv, TEXCOORD_1 in uv1 (a copy of uv
    // when the primitive has no TEXCOORD_1).
    const auto read_uvs = [&](const char* name, glm::vec2 Vertex::*member) {
        const int uv_accessor = attribute(name);
        if (uv_accessor < 0) return false;
        const AccessorData uvs = accessor(uv_accessor, where + " " + name);
        require_float(uvs, 2, where + " " + name, true);
        if (uvs.count != n)
            throw std::runtime_error(where + ": " + name + " has " + std::to_string(uvs.count) +
                                     " elements for " + std::to_string(n) + " positions");
        for (std::size_t i = 0; i < n; ++i) {
            float t[2];
            read_float_element(uvs, i, 2, t);
            if (!std::isfinite(t[0]) || !std::isfinite(t[1]))
                throw std::runtime_error(where + ": " + name + " " + std::to_string(i) +
                                         " is not finite");
            mesh.vertices[i].*member = glm::vec2(t[0], 1.0f - t[1]);
        }
        return true;
    };
    read_uvs("TEXCOORD_0", &Vertex::uv);
    if (!read_uvs("TEXCOORD_1", &Vertex::uv1)) {
        for (Vertex& v : mesh.vertices) v.uv1 = v.uv;
        for (const auto& [image, transform] : material_textures(material))
            if (image >= 0 && transform->tex_coord == 1) {
                out_.warnings.push_back(where + ": material '" + escape_text(material.name, 64) +
                                        "' samples TEXCOORD_1, which the primitive lacks; "
                                        "TEXCOORD_0 is used");
                break;
            }
    }

    // Normals: from the file (renormalised; zero ones from the faces around them), else flat.
    const int normal_accessor = attribute("NORMAL");
    bool tangents_from_file = false;
    if (normal_accessor >= 0) {
        const AccessorData normals = accessor(normal_accessor, where + " NORMAL");
        require_float(normals, 3, where + " NORMAL");
        if (normals.count != n)
            throw std::runtime_error(where + ": NORMAL has " + std::to_string(normals.count) +
                                     " elements for " + std::to_string(n) + " positions");
        std::vector<bool> missing(n, false);
        bool any_missing = false;
        for (std::size_t i = 0; i < n; ++i) {
            float v[3];
            read_float_element(normals, i, 3, v);
            const glm::vec3 normal(v[0], v[1], v[2]);
            if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
                throw std::runtime_error(where + ": NORMAL " + std::to_string(i) +
                                         " is not finite");
            const float length = glm::length(normal);
            if (length > 1e-12f && std::isfinite(length)) {
                mesh.vertices[i].normal = normal / length;
            } else {
                missing[i] = any_missing = true;
            }
        }
        if (any_missing) {
            std::vector<glm::vec3> sums(n, glm::vec3(0.0f));
            for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
                const glm::vec3 face = face_normal(mesh, &mesh.indices[t]);
                for (int c = 0; c < 3; ++c) sums[mesh.indices[t + std::size_t(c)]] += face;
            }
            for (std::size_t i = 0; i < n; ++i) {
                if (!missing[i]) continue;
                const float length = glm::length(sums[i]);
                mesh.vertices[i].normal = length > 0.0f && std::isfinite(length)
                                              ? sums[i] / length
                                              : glm::vec3(0.0f, 0.0f, 1.0f);
            }
        }
        // Tangents from the file, made orthogonal to the normals.
        const int tangent_accessor = attribute("TANGENT");
        if (tangent_accessor >= 0) {
            const AccessorData tangents = accessor(tangent_accessor, where + " TANGENT");
            require_float(tangents, 4, where + " TANGENT");
            if (tangents.count != n)
                throw std::runtime_error(where + ": TANGENT has " +
                                         std::to_string(tangents.count) + " elements for " +
                                         std::to_string(n) + " positions");
            tangents_from_file = true;
            for (std::size_t i = 0; i < n && tangents_from_file; ++i) {
                float v[4];
                read_float_element(tangents, i, 4, v);
                for (float c : v)
                    if (!std::isfinite(c))
                        throw std::runtime_error(where + ": TANGENT " + std::to_string(i) +
                                                 " is not finite");
                const glm::vec3 nrm = mesh.vertices[i].normal;
                glm::vec3 t(v[0], v[1], v[2]);
                t -= nrm * glm::dot(nrm, t);  // Gram-Schmidt (docs/math.md §1)
                const float length = glm::length(t);
                if (!(length > 1e-6f)) {
                    tangents_from_file = false;  // parallel to the normal: recompute all
                    break;
                }
                mesh.vertices[i].tangent = glm::vec4(t / length, v[3] < 0.0f ? -1.0f : 1.0f);
            }
            if (!tangents_from_file)
                out_.warnings.push_back(where + ": a TANGENT is parallel to its normal; "
                                                "tangents recomputed (MikkTSpace)");
        }
    } else {
        // Flat normals (glTF 2.0 §3.7.2.1): every triangle gets its own three vertices; a file's
        // tangents are then ignored, as the specification asks.
        std::vector<Vertex> flat;
        flat.reserve(mesh.indices.size());
        for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
            const glm::vec3 face = face_normal(mesh, &mesh.indices[t]);
            const float length = glm::length(face);
            const glm::vec3 normal =
                length > 0.0f && std::isfinite(length) ? face / length : glm::vec3(0, 0, 1);
            for (int c = 0; c < 3; ++c) {
                Vertex v = mesh.vertices[mesh.indices[t + std::size_t(c)]];
                v.normal = normal;
                flat.push_back(v);
                mesh.indices[t + std::size_t(c)] = std::uint32_t(flat.size() - 1);
            }
        }
        if (flat.size() > options_.max_vertices - std::min(vertices_, options_.max_vertices))
            throw std::runtime_error(where + ": more than " +
                                     std::to_string(options_.max_vertices) +
                                     " vertices in the scene");
        mesh.vertices = std::move(flat);
    }
    if (tangents_from_file) {
        ++out_.primitives_with_tangents;
    } else {
        generate_mikktspace_tangents(mesh, tangent_set(material));
        ++out_.primitives_generated_tangents;
    }
    try {
        measure_normal_linearity(mesh);
        compute_bounds(mesh);
    } catch (const Error& e) {
        throw std::runtime_error(where + ": " + e.cause());
    }
    return mesh;
}

int Converter::image_of_texture(int texture, const std::string& where) {
    if (texture < 0 || std::size_t(texture) >= model_.textures.size())
        throw std::runtime_error(where + ": texture " + std::to_string(texture) +
                                 " does not exist");
    const int source = model_.textures[std::size_t(texture)].source;
    if (source < 0) {
        out_.warnings.push_back(where + ": texture " + std::to_string(texture) +
                                " has no image leanfade can read; ignored");
        return -1;
    }
    if (std::size_t(source) >= model_.images.size())
        throw std::runtime_error(where + ": image " + std::to_string(source) + " does not exist");
    const auto found = images_.find(source);
    if (found != images_.end()) return found->second;
    tinygltf::Image& image = model_.images[std::size_t(source)];
    GltfImage ours;
    ours.name = "image " + std::to_string(source);
    const std::string label = !image.uri.empty() && image.uri.rfind("data:", 0) != 0
                                  ? image.uri
                                  : image.name;
    if (!label.empty()) ours.name += " (" + escape_text(label) + ")";
    if (image.image.empty())
        throw std::runtime_error(ours.name + ": the file could not be read");
    ours.bytes = std::move(image.image);
    out_.images.push_back(std::move(ours));
    images_[source] = int(out_.images.size()) - 1;
    return int(out_.images.size()) - 1;
}

int Converter::material_index(int gltf_material) {
    const auto found = materials_.find(gltf_material);
    if (found != materials_.end()) return found->second;
    GltfMaterial m;
    if (gltf_material < 0) {
        m.name = "default";
    } else {
        if (std::size_t(gltf_material) >= model_.materials.size())
            throw std::runtime_error("material " + std::to_string(gltf_material) +
                                     " does not exist (" +
                                     std::to_string(model_.materials.size()) + " materials)");
        const tinygltf::Material& gm = model_.materials[std::size_t(gltf_material)];
        m.name = gm.name.empty() ? "material " + std::to_string(gltf_material) : gm.name;
        m.gltf_index = gltf_material;
        const std::string where = "material '" + escape_text(m.name, 64) + "'";
        // The sets a texture reference may sample: TEXCOORD_0 and TEXCOORD_1 (Vertex::uv, uv1);
        // one that names another is drawn with TEXCOORD_0, with a warning.
        const auto supported_set = [&](const std::string& what, GltfTextureTransform& t) {
            if (t.tex_coord < kUvSetCount) return;
            out_.warnings.push_back(what + " uses TEXCOORD_" + std::to_string(t.tex_coord) +
                                    "; leanfade reads TEXCOORD_0 and TEXCOORD_1, so it samples "
                                    "TEXCOORD_0");
            t.tex_coord = 0;
        };
        if (gm.alphaMode == "MASK") {
            if (!(gm.alphaCutoff >= 0.0) || !std::isfinite(gm.alphaCutoff))
                throw std::runtime_error(where + ": alphaCutoff is not finite and >= 0");
            m.alpha_cutoff = float(gm.alphaCutoff);
        } else if (gm.alphaMode == "BLEND") {
            m.blend = true;
        }
        m.double_sided = gm.doubleSided;
        const tinygltf::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
        m.normal_transform = texture_transform(gm.normalTexture.extensions,
                                               gm.normalTexture.texCoord, where + " normalTexture");
        m.base_color_transform =
            texture_transform(pbr.baseColorTexture.extensions, pbr.baseColorTexture.texCoord,
                              where + " baseColorTexture");
        m.metallic_roughness_transform = texture_transform(pbr.metallicRoughnessTexture.extensions,
                                                           pbr.metallicRoughnessTexture.texCoord,
                                                           where + " metallicRoughnessTexture");
        for (const auto& [value, name, out] :
             {std::tuple{pbr.metallicFactor, "metallicFactor", &m.metallic_factor},
              std::tuple{pbr.roughnessFactor, "roughnessFactor", &m.roughness_factor}}) {
            if (!(value >= 0.0 && value <= 1.0))
                throw std::runtime_error(where + ": " + name + " is not in [0, 1]");
            *out = float(value);
        }
        if (pbr.metallicRoughnessTexture.index >= 0) {
            m.metallic_roughness_image =
                image_of_texture(pbr.metallicRoughnessTexture.index, where + " metallicRoughnessTexture");
            supported_set(where + ": metallicRoughnessTexture", m.metallic_roughness_transform);
        }
        if (const auto ext = gm.extensions.find(kGltfLeanMapExtension);
            ext != gm.extensions.end() && ext->second.Has("bufferView")) {
            // In the binary chunk of a .glb (or any buffer): the view's bytes, checked as an
            // accessor's view is.
            const tinygltf::Value& index = ext->second.Get("bufferView");
            const std::string named = where + ": " + kGltfLeanMapExtension + " bufferView";
            if (!index.IsInt() || index.Get<int>() < 0 ||
                std::size_t(index.Get<int>()) >= model_.bufferViews.size())
                throw std::runtime_error(named + " is not a buffer view of the file");
            const tinygltf::BufferView& view = model_.bufferViews[std::size_t(index.Get<int>())];
            if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
                throw std::runtime_error(named + " names no buffer");
            const std::vector<unsigned char>& data = model_.buffers[std::size_t(view.buffer)].data;
            if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset ||
                view.byteLength == 0)
                throw std::runtime_error(named + " runs past its buffer");
            m.lean_map_bytes.assign(data.begin() + std::ptrdiff_t(view.byteOffset),
                                    data.begin() + std::ptrdiff_t(view.byteOffset + view.byteLength));
            m.lean_map_view = index.Get<int>();
        } else if (ext != gm.extensions.end()) {
            const tinygltf::Value& uri = ext->second.Get("uri");
            if (!uri.IsString())
                throw std::runtime_error(where + ": " + kGltfLeanMapExtension + " has no uri");
            const std::string& text = uri.Get<std::string>();
            const std::string named =
                where + ": " + kGltfLeanMapExtension + " uri '" + escape_text(text, 80) + "'";
            std::string refusal = uri_refusal(text, access_.external_allowed);
            if (refusal.empty() && text.rfind("data:", 0) == 0)
                refusal = "embeds the map (it must name a KTX2 file beside the glTF)";
            if (!refusal.empty()) throw std::runtime_error(named + " " + refusal);
            m.lean_map_file = confined((access_.folder / gltf_uri_path(text)).string(), access_);
            if (m.lean_map_file.empty())
                throw std::runtime_error(named + " leaves the glTF's folder");
        }
        read_color_factor(gm.pbrMetallicRoughness.baseColorFactor, 4,
                          where + ": baseColorFactor", &m.base_color_factor[0]);
        const tinygltf::TextureInfo& base = gm.pbrMetallicRoughness.baseColorTexture;
        if (base.index >= 0) {
            m.base_color_image = image_of_texture(base.index, where + " baseColorTexture");
            supported_set(where + ": baseColorTexture", m.base_color_transform);
        }
        // glTF 2.0 §3.9.4: occlusionTexture's R with its strength.
        const tinygltf::OcclusionTextureInfo& occlusion = gm.occlusionTexture;
        if (occlusion.index >= 0) {
            if (!(occlusion.strength >= 0.0 && occlusion.strength <= 1.0))
                throw std::runtime_error(where + ": occlusionTexture strength is not in [0, 1]");
            m.occlusion_image = image_of_texture(occlusion.index, where + " occlusionTexture");
            m.occlusion_strength = float(occlusion.strength);
            m.occlusion_transform = texture_transform(occlusion.extensions, occlusion.texCoord,
                                                      where + " occlusionTexture");
            supported_set(where + ": occlusionTexture", m.occlusion_transform);
        }
        // glTF 2.0 §3.9.5: emissiveFactor times emissiveTexture (sRGB).
        read_color_factor(gm.emissiveFactor, 3, where + ": emissiveFactor",
                          &m.emissive_factor[0]);
        if (gm.emissiveTexture.index >= 0) {
            m.emissive_image =
                image_of_texture(gm.emissiveTexture.index, where + " emissiveTexture");
            m.emissive_transform =
                texture_transform(gm.emissiveTexture.extensions, gm.emissiveTexture.texCoord,
                                  where + " emissiveTexture");
            supported_set(where + ": emissiveTexture", m.emissive_transform);
        }
        if (const auto ext = gm.extensions.find(kGltfAnisotropyExtension);
            ext != gm.extensions.end()) {
            const std::string named = where + ": " + kGltfAnisotropyExtension;
            const tinygltf::Value& e = ext->second;
            if (!e.IsObject()) throw std::runtime_error(named + " is not an object");
            const auto number = [&](const char* key, float fallback) {
                if (!e.Has(key)) return fallback;
                const tinygltf::Value& v = e.Get(key);
                if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
                    throw std::runtime_error(named + " " + key + " is not a finite number");
                return float(v.GetNumberAsDouble());
            };
            m.anisotropy_strength = number("anisotropyStrength", 0.0f);
            if (!(m.anisotropy_strength >= 0.0f && m.anisotropy_strength <= 1.0f))
                throw std::runtime_error(named + " anisotropyStrength is not in [0, 1]");
            m.anisotropy_rotation = number("anisotropyRotation", 0.0f);
            if (e.Has("anisotropyTexture")) {
                const ExtensionTextureInfo info = extension_texture_info(
                    e.Get("anisotropyTexture"), named + " anisotropyTexture");
                m.anisotropy_image = image_of_texture(info.index, named + " anisotropyTexture");
                m.anisotropy_transform = info.transform;
                supported_set(named + " anisotropyTexture", m.anisotropy_transform);
            }
        }
        const tinygltf::NormalTextureInfo& normal = gm.normalTexture;
        if (normal.index >= 0) {
            if (!std::isfinite(normal.scale))
                throw std::runtime_error(where + ": normalTexture scale is not finite");
            m.normal_image = image_of_texture(normal.index, where + " normalTexture");
            m.normal_scale = float(normal.scale);
            supported_set(where + ": normalTexture", m.normal_transform);
        }
    }
    out_.materials.push_back(std::move(m));
    materials_[gltf_material] = int(out_.materials.size()) - 1;
    return int(out_.materials.size()) - 1;
}

glm::dmat4 Converter::local_matrix(const tinygltf::Node& node, int index) const {
    const std::string where = "node " + std::to_string(index);
    auto finite = [&](const std::vector<double>& values, std::size_t count, const char* what) {
        if (values.empty()) return false;
        if (values.size() != count)
            throw std::runtime_error(where + ": " + what + " has " +
                                     std::to_string(values.size()) + " values");
        for (double v : values)
            if (!std::isfinite(v)) throw std::runtime_error(where + ": " + what + " is not finite");
        return true;
    };
    if (finite(node.matrix, 16, "matrix")) return glm::make_mat4(node.matrix.data());
    glm::dmat4 m(1.0);
    if (finite(node.translation, 3, "translation"))
        m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1],
                                         node.translation[2]));
    if (finite(node.rotation, 4, "rotation")) {
        // glTF stores (x, y, z, w); glm's constructor takes (w, x, y, z).
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        const double length = glm::length(q);
        if (!(length > 0.0)) throw std::runtime_error(where + ": rotation is a zero quaternion");
        m = m * glm::mat4_cast(q / length);
    }
    if (finite(node.scale, 3, "scale"))
        m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return m;
}

void Converter::run() {
    // The nodes to draw: the default scene, else scene 0, else every node no other node has as
    // a child.
    std::vector<int> roots;
    const int scene = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (!model_.scenes.empty()) {
        if (std::size_t(scene) >= model_.scenes.size())
            throw std::runtime_error("scene " + std::to_string(scene) + " does not exist");
        roots = model_.scenes[std::size_t(scene)].nodes;
    } else {
        std::vector<bool> child(model_.nodes.size(), false);
        for (const tinygltf::Node& node : model_.nodes)
            for (int c : node.children)
                if (c >= 0 && std::size_t(c) < child.size()) child[std::size_t(c)] = true;
        for (std::size_t i = 0; i < child.size(); ++i)
            if (!child[i]) roots.push_back(int(i));
    }
    // Depth first with an explicit stack (no recursion on hostile depths); a node reached twice
    // (a cycle, or two parents) is refused: glTF nodes form disjoint trees.
    std::vector<bool> visited(model_.nodes.size(), false);
    std::vector<std::pair<int, glm::dmat4>> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it)
        stack.emplace_back(*it, glm::dmat4(1.0));
    bool skins = false;
    while (!stack.empty()) {
        const auto [index, parent] = stack.back();
        stack.pop_back();
        if (index < 0 || std::size_t(index) >= model_.nodes.size())
            throw std::runtime_error("node " + std::to_string(index) + " does not exist");
        if (visited[std::size_t(index)])
            throw std::runtime_error("node " + std::to_string(index) +
                                     " is reached twice (the node hierarchy is not a tree)");
        visited[std::size_t(index)] = true;
        const tinygltf::Node& node = model_.nodes[std::size_t(index)];
        const glm::dmat4 world = parent * local_matrix(node, index);
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
            stack.emplace_back(*c, world);
        if (node.skin >= 0) skins = true;
        if (node.mesh < 0) continue;
        if (std::size_t(node.mesh) >= model_.meshes.size())
            throw std::runtime_error("node " + std::to_string(index) + ": mesh " +
                                     std::to_string(node.mesh) + " does not exist");
        const glm::mat4 transform(world);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (!std::isfinite(transform[c][r]))
                    throw std::runtime_error("node " + std::to_string(index) +
                                             ": its world matrix is not finite");
        const bool mirrored = glm::determinant(world) < 0.0;
        const tinygltf::Mesh& gm = model_.meshes[std::size_t(node.mesh)];
        for (std::size_t p = 0; p < gm.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = gm.primitives[p];
            const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
                mode != TINYGLTF_MODE_TRIANGLE_FAN) {
                out_.warnings.push_back("mesh " + std::to_string(node.mesh) + " primitive " +
                                        std::to_string(p) + ": points and lines are not drawn");
                continue;
            }
            if (out_.objects.size() >= options_.max_objects)
                throw std::runtime_error("more than " + std::to_string(options_.max_objects) +
                                         " objects in the scene");
            // The material first: its textures' sets decide the primitive's tangents.
            const int material = material_index(prim.material);
            const auto key = std::make_pair(node.mesh, int(p));
            auto found = meshes_.find(key);
            if (found == meshes_.end())
                found = meshes_
                            .emplace(key, primitive_mesh(node.mesh, int(p),
                                                         out_.materials[std::size_t(material)]))
                            .first;
            const Mesh& mesh = found->second;
            if (mesh.vertices.size() > options_.max_vertices - vertices_)
                throw std::runtime_error("more than " + std::to_string(options_.max_vertices) +
                                         " vertices in the scene");
            vertices_ += mesh.vertices.size();
            if (mesh.indices.size() > options_.max_indices - indices_)
                throw std::runtime_error("more than " + std::to_string(options_.max_indices) +
                                         " triangle indices in the scene (each instance of a "
                                         "mesh counts)");
            indices_ += mesh.indices.size();
            GltfObject object;
            object.mesh = mesh;
            object.transform = transform;
            object.material = material;
            if (mirrored) {
                for (std::size_t t = 0; t < object.mesh.indices.size(); t += 3)
                    std::swap(object.mesh.indices[t + 1], object.mesh.indices[t + 2]);
                for (Vertex& v : object.mesh.vertices) v.tangent.w = -v.tangent.w;
            }
            out_.objects.push_back(std::move(object));
        }
    }
    // Each (normal image, scale) pair is a bake of its own, held and cached: bounded per image.
    std::map<int, std::vector<float>> scales;
    for (const GltfMaterial& m : out_.materials) {
        if (m.normal_image < 0) continue;
        std::vector<float>& of_image = scales[m.normal_image];
        if (std::find(of_image.begin(), of_image.end(), m.normal_scale) != of_image.end()) continue;
        of_image.push_back(m.normal_scale);
        if (of_image.size() > kMaxGltfScalesPerImage)
            throw std::runtime_error(
                out_.images[std::size_t(m.normal_image)].name + ": normal texture of " +
                std::to_string(of_image.size()) + " different scales, more than the limit of " +
                std::to_string(kMaxGltfScalesPerImage) + " bakes of one image");
    }
    if (skins) out_.warnings.push_back("skins are ignored: meshes are drawn in their bind pose");
    if (!model_.animations.empty()) out_.warnings.push_back("animations are ignored");
    if (out_.objects.empty()) throw std::runtime_error("the scene has no triangle mesh to draw");
}

GltfScene load(const std::vector<std::uint8_t>& bytes, const std::string& name,
               FileAccess& access, const GltfLoadOptions& options) {
    GltfScene scene;
    scene.path = name;
    try {
        const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
        const std::string text =
            binary ? glb_json_chunk(bytes)
                   : std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        check_json_depth(text);
        json root;
        try {
            root = json::parse(text);
        } catch (const json::exception& e) {
            std::string message = e.what();
            const std::size_t bracket = message.find("] ");
            if (message.rfind("[json", 0) == 0 && bracket != std::string::npos)
                message = message.substr(bracket + 2);
            throw std::runtime_error("not valid glTF JSON: " + first_line(message));
        }
        check_json(root, access.external_allowed);
        ImageKeeping keeping;
        keeping.used = images_used_by_materials(root);
        keeping.limit = keeping.budget = options.max_image_bytes;
        root = json();  // free it before tinygltf parses its own copy

        tinygltf::TinyGLTF loader;
        loader.SetImageLoader(keep_encoded_image, &keeping);
        loader.SetFsCallbacks(tinygltf::FsCallbacks{file_exists, expand_file_path, read_whole_file,
                                                    nullptr, &access});
        tinygltf::Model model;
        std::string error, warning;
        const std::string folder = access.folder.string();
        const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning,
                                                             bytes.data(),
                                                             unsigned(bytes.size()), folder)
                               : loader.LoadASCIIFromString(&model, &error, &warning,
                                                            text.data(), unsigned(text.size()),
                                                            folder);
        if (!access.refused.empty()) throw std::runtime_error(access.refused);
        if (!keeping.refused.empty()) throw std::runtime_error(keeping.refused);
        if (!ok)
            throw std::runtime_error(first_line(error.empty() ? "not a valid glTF file" : error));
        Converter(model, options, scene, access).run();
    } catch (const Error& e) {
        throw Error(name, e.file() + ": " + e.cause());
    } catch (const std::bad_alloc&) {
        throw Error(name, "out of memory while reading the scene");
    } catch (const std::exception& e) {
        throw Error(name, first_line(e.what()));
    }
    return scene;
}

}  // namespace

GltfScene load_gltf(const std::string& path, const GltfLoadOptions& options) {
    FileAccess access;
    access.external_allowed = true;
    access.max_bytes = std::min(options.max_file_bytes, kLargestFile);
    std::error_code error;
    access.folder = fs::absolute(fs::path(path), error).parent_path().lexically_normal();
    if (error) throw Error(path, error.message());
    std::vector<std::uint8_t> bytes;
    const std::string cause = read_file(path, access.max_bytes, bytes);
    if (!cause.empty()) throw Error(path, cause);
    return load(bytes, path, access, options);
}

std::vector<std::string> gltf_referenced_files(const std::string& path,
                                               const GltfLoadOptions& options) {
    std::vector<std::string> files;
    try {
        // The JSON only: of a GLB, its first chunk (the binary chunk is not read).
        std::string text;
        {
            const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
            if (fd < 0) return files;
            struct FdCloser {
                int fd;
                ~FdCloser() { ::close(fd); }
            } closer{fd};
            struct stat info {};
            if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) return files;
            const std::uint64_t size = std::uint64_t(info.st_size);
            if (size > std::min(options.max_file_bytes, kLargestFile)) return files;
            const auto read_at = [&](std::uint64_t offset, std::uint64_t length) {
                std::string part(std::size_t(length), '\0');
                return ::pread(fd, part.data(), part.size(), off_t(offset)) == ssize_t(length)
                           ? part
                           : std::string();
            };
            const std::string head = size >= 20 ? read_at(0, 20) : std::string();
            if (head.size() == 20 && head.compare(0, 4, "glTF") == 0) {
                const auto byte = [&](int i) { return std::uint64_t(std::uint8_t(head[i])); };
                const std::uint64_t length =
                    byte(12) | byte(13) << 8 | byte(14) << 16 | byte(15) << 24;
                if (length > size - 20) return files;
                text = read_at(20, length);
            } else {
                text = read_at(0, size);
            }
        }
        check_json_depth(text);
        const json root = json::parse(text);
        const fs::path folder = fs::path(path).parent_path();
        for (const char* key : {"buffers", "images"}) {
            const auto array = root.find(key);
            if (array == root.end() || !array->is_array()) continue;
            for (const json& entry : *array) {
                if (!entry.is_object()) continue;
                const auto uri = entry.find("uri");
                if (uri == entry.end() || !uri->is_string()) continue;
                const std::string name = uri->get<std::string>();
                if (name.rfind("data:", 0) == 0 || !uri_refusal(name, true).empty()) continue;
                files.push_back((folder / gltf_uri_path(name)).string());
            }
        }
        // The LEAN map a material names (LEANFADE_lean_map): read by the run as well.
        if (const auto materials = root.find("materials");
            materials != root.end() && materials->is_array()) {
            for (const json& material : *materials) {
                if (!material.is_object()) continue;
                const auto extensions = material.find("extensions");
                if (extensions == material.end() || !extensions->is_object()) continue;
                const auto lean = extensions->find(kGltfLeanMapExtension);
                if (lean == extensions->end() || !lean->is_object()) continue;
                const auto uri = lean->find("uri");
                if (uri == lean->end() || !uri->is_string()) continue;
                const std::string name = uri->get<std::string>();
                if (name.rfind("data:", 0) == 0 || !uri_refusal(name, true).empty()) continue;
                files.push_back((folder / gltf_uri_path(name)).string());
            }
        }
    } catch (const std::exception&) {
        // A file that does not parse names no file: load_gltf reports why.
    }
    return files;
}

GltfScene load_gltf_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name,
                                const GltfLoadOptions& options) {
    FileAccess access;
    access.external_allowed = false;
    access.max_bytes = std::min(options.max_file_bytes, kLargestFile);
    if (bytes.size() > access.max_bytes)
        throw Error(name, "is " + std::to_string(bytes.size()) +
                              " bytes, more than the limit of " + std::to_string(access.max_bytes));
    return load(bytes, name, access, options);
}

}  // namespace leanfade::scene
