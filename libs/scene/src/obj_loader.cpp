// OBJ loading through tinyobjloader, with a strict pre-check of numbers and indices (tinyobjloader
// silently reads a malformed number as 0 and does not range-check face indices).
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <tiny_obj_loader.h>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/scene/detail/obj_loader.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

std::vector<std::string_view> split_whitespace(std::string_view line) {
    std::vector<std::string_view> tokens;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) {
            ++i;
        }
        const std::size_t start = i;
        while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) {
            ++i;
        }
        if (i > start) {
            tokens.push_back(line.substr(start, i - start));
        }
    }
    return tokens;
}

// A token quoted for an error message, escaped (text of the file).
std::string quoted(std::string_view token) {
    std::string out(1, '\'');
    out += escape_text(token, 32);
    out += '\'';
    return out;
}

// Faces of up to this many vertices are ear-clipped (time up to cubic in the vertex count), larger
// ones are fans (linear time): see triangulate_polygon.
constexpr std::size_t kMaxEarClippedFaceVertices = 64;

// A face corner: 0-based position, texture coordinate and normal indices (-1: absent).
struct FaceCorner {
    long long v, t, n;
};
// A face: `count` corners from `first` in the corner list, and the line it is on.
struct Face {
    std::size_t first, count, line;
    int material = -1;  // index into ObjMaterialUse::names (usemtl), -1: none
};

// The material statements of an OBJ file: mtllib file names and usemtl names, in file order.
struct ObjMaterialUse {
    std::vector<std::string> libraries;
    std::vector<std::string> names;
};

// The rest of a statement's line after its keyword, trimmed (names and paths may hold spaces).
std::string statement_argument(std::string_view data, std::string_view keyword) {
    std::string_view rest = data.substr(data.find(keyword) + keyword.size());
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.front())))
        rest.remove_prefix(1);
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.back())))
        rest.remove_suffix(1);
    return std::string(rest);
}

// Checks every number on v / vt / vn lines and every index on f lines (Error(path, ...) with the
// line number) and returns the text tinyobjloader parses: only the v, vt and vn lines (every
// other line becomes empty, so line numbers stay), without comments ('#' to the end of a line,
// which tinyobjloader only understands at the start of a line), each number rewritten as the
// value checked here ("%.9g": 9 significant digits, enough for a float). tinyobjloader's own
// number parser mis-reads forms strtod accepts ("0x10" becomes 0; the exponent of
// "0e2147483649" overflows an int) and its parsers of lines leanfade ignores (vw, l, p, s, ...)
// have undefined behaviour on hostile values (found by fuzz_obj, docs/robustness.md): they
// never see the file's own text.
// Also returns every face (`faces`, `corners`), its indices checked and resolved, in file order.
// The faces do not reach tinyobjloader: it stores a face's vertex count in 8 bits when it does not
// triangulate, and triangulates in quadratic time when it does (triangulate_polygon).
std::string precheck(const std::string& path, const std::string& text,
                     std::vector<FaceCorner>& corners, std::vector<Face>& faces,
                     ObjMaterialUse* materials) {
    int current_material = -1;
    std::string clean;
    clean.reserve(text.size());
    long long counts[3] = {0, 0, 0};  // positions, texture coordinates, normals
    const char* kinds[3] = {"positions", "texture coordinates", "normals"};
    std::size_t line_number = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) {
            end = text.size();
        }
        const std::string_view line(text.data() + pos, end - pos);
        pos = end + 1;
        ++line_number;
        const auto fail = [&](const std::string& cause) {
            throw Error(path, "line " + std::to_string(line_number) + ": " + cause);
        };
        const std::string_view data = line.substr(0, line.find('#'));
        const auto tokens = split_whitespace(data);
        if (tokens.empty()) {
            clean.push_back('\n');
            continue;
        }
        const std::string_view keyword = tokens[0];
        if (keyword == "v" || keyword == "vt" || keyword == "vn") {
            const int kind = keyword == "v" ? 0 : (keyword == "vt" ? 1 : 2);
            const std::size_t needed = kind == 1 ? 1 : 3;
            if (tokens.size() < needed + 1) {
                fail(std::string(keyword) + " needs at least " + std::to_string(needed) +
                     " numbers");
            }
            clean.append(keyword);
            for (std::size_t k = 1; k < tokens.size(); ++k) {
                const std::string token(tokens[k]);
                char* parsed_end = nullptr;
                const double value = std::strtod(token.c_str(), &parsed_end);
                if (parsed_end != token.c_str() + token.size()) {
                    fail(quoted(tokens[k]) + " is not a number");
                }
                if (!std::isfinite(value) || std::abs(value) > std::numeric_limits<float>::max()) {
                    fail("non-finite coordinate " + quoted(tokens[k]));
                }
                char number[32];
                std::snprintf(number, sizeof number, " %.9g", value);
                clean.append(number);
            }
            clean.push_back('\n');
            ++counts[kind];
        } else if (keyword == "f") {
            if (tokens.size() < 4) {
                fail("a face needs at least 3 vertices");
            }
            faces.push_back({corners.size(), tokens.size() - 1, line_number, current_material});
            for (std::size_t k = 1; k < tokens.size(); ++k) {
                std::string_view rest = tokens[k];
                long long resolved[3] = {-1, -1, -1};
                for (int kind = 0; kind < 3 && !rest.empty(); ++kind) {
                    const std::size_t slash = rest.find('/');
                    const std::string_view part = rest.substr(0, slash);
                    rest = slash == std::string_view::npos ? std::string_view{}
                                                           : rest.substr(slash + 1);
                    if (part.empty() && kind > 0) {
                        continue;  // "1//3": no texture coordinate
                    }
                    long long index = 0;
                    const auto [ptr, ec] =
                        std::from_chars(part.data(), part.data() + part.size(), index);
                    if (ec != std::errc{} || ptr != part.data() + part.size() || index == 0) {
                        fail("malformed face vertex " + quoted(tokens[k]));
                    }
                    if (index > counts[kind] || index < -counts[kind]) {
                        fail("face index " + std::to_string(index) + " out of range (" +
                             std::to_string(counts[kind]) + " " + kinds[kind] + " defined)");
                    }
                    resolved[kind] = index > 0 ? index - 1 : counts[kind] + index;
                }
                if (!rest.empty()) {
                    fail("malformed face vertex " + quoted(tokens[k]));  // "1/2/3/4"
                }
                corners.push_back({resolved[0], resolved[1], resolved[2]});
            }
            clean.push_back('\n');
        } else {
            if (materials != nullptr && (keyword == "usemtl" || keyword == "mtllib")) {
                const std::string argument = statement_argument(data, keyword);
                if (argument.empty()) fail(std::string(keyword) + " needs a name");
                if (keyword == "mtllib") {
                    materials->libraries.push_back(argument);
                } else {
                    auto found = std::find(materials->names.begin(), materials->names.end(),
                                           argument);
                    current_material = int(found - materials->names.begin());
                    if (found == materials->names.end()) materials->names.push_back(argument);
                }
            }
            clean.push_back('\n');
        }
    }
    return clean;
}

// Box projection axis of a triangle from its geometric normal: 0 +x, 1 -x, 2 +y, 3 -y, 4 +z, 5 -z.
int projection_axis(const glm::dvec3& n) {
    const glm::dvec3 a = glm::abs(n);
    int axis = 2;
    double sign = n.y;
    if (a.x >= a.y && a.x >= a.z && a.x > 0.0) {
        axis = 0;
        sign = n.x;
    } else if (a.z > a.y && a.z >= a.x) {
        axis = 4;
        sign = n.z;
    }
    return sign < 0.0 ? axis + 1 : axis;
}

// Box-projected UV: (+u, +v, axis direction) is right-handed; E = largest extent of the box.
glm::vec2 box_uv(const glm::dvec3& p, int axis, const glm::dvec3& lo, const glm::dvec3& hi,
                 double extent) {
    glm::dvec2 uv(0.0);
    switch (axis) {
        case 0:
            uv = {hi.z - p.z, p.y - lo.y};
            break;
        case 1:
            uv = {p.z - lo.z, p.y - lo.y};
            break;
        case 2:
            uv = {p.x - lo.x, hi.z - p.z};
            break;
        case 3:
            uv = {p.x - lo.x, p.z - lo.z};
            break;
        case 4:
            uv = {p.x - lo.x, p.y - lo.y};
            break;
        default:
            uv = {hi.x - p.x, p.y - lo.y};
            break;
    }
    return glm::vec2(uv / extent);
}

// Triangles of a polygon (indices of its corners, three per triangle, in the polygon's winding),
// in time linear in the vertex count of the face for large faces. tinyobjloader's own
// triangulation takes time quadratic in the vertex count (a face of 100 000 vertices took more
// than 30 s), so it is off and faces are split here: a triangle as it is; a quad along its
// shorter diagonal (tinyobjloader's rule, so quads split as before); a polygon of up to
// kMaxEarClippedFaceVertices by ear clipping in its plane (right for non-convex polygons too); a
// larger one as a fan from its first vertex (right for convex polygons, which the large faces of
// real models are: discs, caps, sections).
void triangulate_polygon(const std::vector<glm::dvec3>& p, std::vector<std::uint32_t>& out) {
    out.clear();
    const std::size_t n = p.size();
    if (n == 3) {
        out = {0, 1, 2};
        return;
    }
    if (n == 4) {
        const glm::dvec3 d02 = p[2] - p[0], d13 = p[3] - p[1];
        if (glm::dot(d02, d02) < glm::dot(d13, d13)) {
            out = {0, 1, 2, 0, 2, 3};
        } else {
            out = {0, 1, 3, 1, 2, 3};
        }
        return;
    }
    glm::dvec3 normal(0.0);  // Newell's
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3& a = p[i];
        const glm::dvec3& b = p[(i + 1) % n];
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                             (a.x - b.x) * (a.y + b.y));
    }
    if (n > kMaxEarClippedFaceVertices) {
        for (std::uint32_t k = 1; k + 1 < n; ++k) out.insert(out.end(), {0u, k, k + 1});
        return;
    }

    // Ear clipping in the plane of the largest normal component, counter-clockwise there.
    const glm::dvec3 a = glm::abs(normal);
    const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    const double sign = normal[drop] < 0.0 ? -1.0 : 1.0;
    std::vector<glm::dvec2> q(n);
    for (std::size_t i = 0; i < n; ++i) {
        q[i] = glm::dvec2(sign * p[i][(drop + 1) % 3], p[i][(drop + 2) % 3]);
    }
    const auto turn = [&](std::size_t i, std::size_t j, std::size_t k) {
        const glm::dvec2 u = q[j] - q[i], v = q[k] - q[j];
        return u.x * v.y - u.y * v.x;
    };
    std::vector<std::uint32_t> previous(n), next(n);
    for (std::size_t i = 0; i < n; ++i) {
        previous[i] = std::uint32_t((i + n - 1) % n);
        next[i] = std::uint32_t((i + 1) % n);
    }
    const auto is_ear = [&](std::uint32_t i) {
        const std::uint32_t before = previous[i], after = next[i];
        if (!(turn(before, i, after) > 0.0)) return false;
        for (std::uint32_t j = next[after]; j != before; j = next[j]) {
            if (q[j] == q[before] || q[j] == q[i] || q[j] == q[after]) continue;
            if (turn(before, i, j) >= 0.0 && turn(i, after, j) >= 0.0 &&
                turn(after, before, j) >= 0.0) {
                return false;  // j inside or on the candidate triangle
            }
        }
        return true;
    };
    std::uint32_t i = 0;
    std::size_t remaining = n, misses = 0;
    while (remaining > 3) {
        if (is_ear(i)) {
            out.insert(out.end(), {previous[i], i, next[i]});
            next[previous[i]] = next[i];
            previous[next[i]] = previous[i];
            i = next[i];
            --remaining;
            misses = 0;
        } else if (++misses > remaining) {
            break;  // no ear left (a self-intersecting or degenerate polygon): fan the rest
        } else {
            i = next[i];
        }
    }
    for (std::uint32_t j = next[i]; next[j] != i; j = next[j]) {
        out.insert(out.end(), {i, j, next[j]});
    }
}

struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const {
        std::size_t h = std::hash<long long>{}(k[0]);
        h ^= std::hash<long long>{}(k[1]) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        h ^= std::hash<long long>{}(k[2]) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        return h;
    }
};

// The mesh of every face, and with `materials` the usemtl index of each triangle
// (`triangle_materials`).
Mesh build_obj_mesh(const std::string& file_text, const std::string& path,
                    ObjMaterialUse* materials, std::vector<int>* triangle_materials) {
    std::vector<FaceCorner> face_corners;
    std::vector<Face> faces;
    const std::string text = precheck(path, file_text, face_corners, faces, materials);

    tinyobj::ObjReaderConfig config;
    config.triangulate = false;  // no faces reach it (precheck)
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    // From the string: materials are ignored, so no .mtl lookup (and no warnings about one).
    if (!reader.ParseFromString(text, "", config)) {
        std::string cause = reader.Error();
        cause = cause.substr(0, cause.find('\n'));
        throw Error(path, cause.empty() ? "parse failure" : "parse failure: " + cause);
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const auto position_count = static_cast<long long>(attrib.vertices.size() / 3);
    const auto normal_count = static_cast<long long>(attrib.normals.size() / 3);
    const auto uv_count = static_cast<long long>(attrib.texcoords.size() / 2);
    const auto position = [&](long long i) {
        return glm::dvec3(attrib.vertices[std::size_t(3 * i)],
                          attrib.vertices[std::size_t(3 * i + 1)],
                          attrib.vertices[std::size_t(3 * i + 2)]);
    };

    // Triangles as (position, normal, uv) index triples; -1 = absent or unusable.
    struct Corner {
        long long v, n, t;
    };
    std::vector<Corner> corners;
    std::vector<glm::dvec3> polygon;
    std::vector<std::uint32_t> triangles;
    for (const Face& face : faces) {
        polygon.clear();
        for (std::size_t c = 0; c < face.count; ++c) {
            const FaceCorner& corner = face_corners[face.first + c];
            if (corner.v < 0 || corner.v >= position_count || corner.t >= uv_count ||
                corner.n >= normal_count) {
                throw Error(path,
                            "line " + std::to_string(face.line) + ": face index out of range");
            }
            polygon.push_back(position(corner.v));
        }
        triangulate_polygon(polygon, triangles);
        if (triangle_materials != nullptr)
            triangle_materials->insert(triangle_materials->end(), triangles.size() / 3,
                                       face.material);
        for (const std::uint32_t c : triangles) {
            const FaceCorner& corner = face_corners[face.first + c];
            long long n = corner.n;
            if (n >= 0) {
                const glm::dvec3 vn(attrib.normals[std::size_t(3 * n)],
                                    attrib.normals[std::size_t(3 * n + 1)],
                                    attrib.normals[std::size_t(3 * n + 2)]);
                if (!(glm::length(vn) > 1e-20)) {
                    n = -1;  // a zero normal is as good as none
                }
            }
            corners.push_back({corner.v, n, corner.t});
        }
    }
    if (corners.empty()) {
        throw Error(path, "no triangles");
    }
    if (corners.size() / 3 > std::numeric_limits<std::uint32_t>::max() / 3) {
        throw Error(path, "too many triangles");
    }

    // Bounds of the referenced positions, for the box projection.
    glm::dvec3 lo(std::numeric_limits<double>::max());
    glm::dvec3 hi(std::numeric_limits<double>::lowest());
    for (const Corner& c : corners) {
        lo = glm::min(lo, position(c.v));
        hi = glm::max(hi, position(c.v));
    }
    const glm::dvec3 size = hi - lo;
    double extent = std::max({size.x, size.y, size.z});
    if (!(extent > 0.0)) {
        extent = 1.0;
    }

    Mesh mesh;
    mesh.name = std::filesystem::path(path).stem().string();
    std::vector<glm::dvec3> smooth(std::size_t(position_count), glm::dvec3(0.0));
    std::vector<long long> vertex_position;  // per output vertex: its position index
    std::vector<bool> needs_normal;
    std::unordered_map<std::array<long long, 3>, std::uint32_t, KeyHash> lookup;
    mesh.indices.reserve(corners.size());
    for (std::size_t t = 0; t < corners.size(); t += 3) {
        const glm::dvec3 p0 = position(corners[t].v);
        const glm::dvec3 face = glm::cross(position(corners[t + 1].v) - p0,
                                           position(corners[t + 2].v) - p0);  // 2 * area
        const int axis = projection_axis(face);
        for (std::size_t k = t; k < t + 3; ++k) {
            const Corner& c = corners[k];
            smooth[std::size_t(c.v)] += face;
            // Missing UVs: the projection axis becomes part of the key (a vertex on a box edge
            // is split between the two projections).
            const std::array<long long, 3> key = {c.v, c.n, c.t >= 0 ? c.t : -1 - axis};
            const auto [it, inserted] =
                lookup.try_emplace(key, std::uint32_t(mesh.vertices.size()));
            if (inserted) {
                Vertex v{};
                const glm::dvec3 p = position(c.v);
                v.position = glm::vec3(p);
                if (c.n >= 0) {
                    v.normal = glm::vec3(
                        glm::normalize(glm::dvec3(attrib.normals[std::size_t(3 * c.n)],
                                                  attrib.normals[std::size_t(3 * c.n + 1)],
                                                  attrib.normals[std::size_t(3 * c.n + 2)])));
                }
                if (c.t >= 0) {
                    v.uv = glm::vec2(attrib.texcoords[std::size_t(2 * c.t)],
                                     attrib.texcoords[std::size_t(2 * c.t + 1)]);
                } else {
                    v.uv = box_uv(p, axis, lo, hi, extent);
                }
                mesh.vertices.push_back(v);
                vertex_position.push_back(c.v);
                needs_normal.push_back(c.n < 0);
            }
            mesh.indices.push_back(it->second);
        }
    }
    // Area-weighted smooth normals where the file has none.
    for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
        if (needs_normal[k]) {
            const glm::dvec3 n = smooth[std::size_t(vertex_position[k])];
            const double len = glm::length(n);
            mesh.vertices[k].normal = len > 0.0 ? glm::vec3(n / len) : glm::vec3(0.0f, 1.0f, 0.0f);
        }
    }
    detail::finish(mesh);
    return mesh;
}

}  // namespace

Mesh load_obj(const std::string& path) {
    return load_obj_from_memory(read_regular_file(path, kMaxObjFileBytes, "an OBJ file"), path);
}

Mesh load_obj_from_memory(const std::string& file_text, const std::string& path) {
    return build_obj_mesh(file_text, path, nullptr, nullptr);
}

ObjModel load_obj_model(const std::string& path) {
    const std::string text = read_regular_file(path, kMaxObjFileBytes, "an OBJ file");
    ObjMaterialUse use;
    std::vector<int> triangle_materials;
    const Mesh mesh = build_obj_mesh(text, path, &use, &triangle_materials);
    ObjModel model;
    model.path = path;
    model.libraries = use.libraries;
    model.material_names = use.names;
    // One material (or none): the mesh as load_obj makes it.
    if (std::adjacent_find(triangle_materials.begin(), triangle_materials.end(),
                           std::not_equal_to<>()) == triangle_materials.end()) {
        model.part_materials.push_back(triangle_materials.empty() ? -1
                                                                  : triangle_materials.front());
        model.parts.push_back(mesh);
        return model;
    }
    // One mesh per material, its triangles in file order, the vertices they use (with the
    // tangents of the whole mesh, so that no seam appears between the parts).
    for (int group = -1; group < int(use.names.size()); ++group) {
        Mesh part;
        part.name = mesh.name;
        std::vector<std::uint32_t> remap(mesh.vertices.size(), UINT32_MAX);
        for (std::size_t t = 0; t < triangle_materials.size(); ++t) {
            if (triangle_materials[t] != group) continue;
            for (std::size_t k = 3 * t; k < 3 * t + 3; ++k) {
                const std::uint32_t v = mesh.indices[k];
                if (remap[v] == UINT32_MAX) {
                    remap[v] = std::uint32_t(part.vertices.size());
                    part.vertices.push_back(mesh.vertices[v]);
                }
                part.indices.push_back(remap[v]);
            }
        }
        if (part.indices.empty()) continue;
        compute_bounds(part);
        model.parts.push_back(std::move(part));
        model.part_materials.push_back(group);
    }
    return model;
}

namespace {

// A number of an MTL statement (finite, as strtod reads it whole), or an Error naming the line.
float mtl_number(std::string_view token, const std::function<void(const std::string&)>& fail) {
    const std::string text(token);
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size()) fail(quoted(token) + " is not a number");
    if (!std::isfinite(value) || std::abs(value) > std::numeric_limits<float>::max())
        fail("non-finite value " + quoted(token));
    return float(value);
}

bool is_number(std::string_view token) {
    const std::string text(token);
    char* end = nullptr;
    std::strtod(text.c_str(), &end);
    return !text.empty() && end == text.c_str() + text.size();
}

}  // namespace

std::vector<MtlMaterial> parse_mtl(const std::string& text, const std::string& path) {
    std::vector<MtlMaterial> materials;
    std::size_t line_number = 0, pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        const std::string_view line(text.data() + pos, end - pos);
        pos = end + 1;
        ++line_number;
        const std::function<void(const std::string&)> fail = [&](const std::string& cause) {
            throw Error(path, "line " + std::to_string(line_number) + ": " + cause);
        };
        const std::string_view data = line.substr(0, line.find('#'));
        const auto tokens = split_whitespace(data);
        if (tokens.empty()) continue;
        const std::string_view keyword = tokens[0];
        if (keyword == "newmtl") {
            MtlMaterial material;
            material.name = statement_argument(data, keyword);
            if (material.name.empty()) fail("newmtl needs a name");
            materials.push_back(std::move(material));
            continue;
        }
        const bool known = keyword == "Kd" || keyword == "Ks" || keyword == "Ns" ||
                           keyword == "Pr" || keyword == "map_Kd" || keyword == "map_Pr" ||
                           keyword == "map_Bump" || keyword == "map_bump" || keyword == "bump" ||
                           keyword == "norm" || keyword == "map_Norm";
        if (!known) continue;  // Ka, Ke, d, illum, map_Ks, ...: not used
        if (materials.empty()) fail(std::string(keyword) + " before any newmtl");
        MtlMaterial& m = materials.back();
        if (keyword == "Kd" || keyword == "Ks") {
            if (tokens.size() < 2) fail(std::string(keyword) + " needs a colour");
            if (tokens[1] == "spectral" || tokens[1] == "xyz")
                continue;  // colour forms leanfade does not read
            glm::vec3 colour;
            for (int c = 0; c < 3; ++c) {
                // "Kd r" alone means r = g = b.
                const std::size_t k = tokens.size() >= 4 ? std::size_t(1 + c) : 1;
                colour[c] = mtl_number(tokens[k], fail);
                if (colour[c] < 0.0f) fail(std::string(keyword) + " must not be negative");
            }
            (keyword == "Kd" ? m.kd : m.ks) = colour;
        } else if (keyword == "Ns" || keyword == "Pr") {
            if (tokens.size() < 2) fail(std::string(keyword) + " needs a value");
            const float value = mtl_number(tokens[1], fail);
            if (keyword == "Ns") {
                if (value < 0.0f) fail("Ns must not be negative");
                if (value > 0.0f) m.ns = value;
            } else {
                if (value < 0.0f || value > 1.0f) fail("Pr must be in [0, 1]");
                m.roughness = value;
            }
        } else {
            // A texture: options, then the file name (which may hold spaces).
            float multiplier = 1.0f;
            std::size_t k = 1;
            while (k < tokens.size() && tokens[k].size() > 1 && tokens[k][0] == '-' &&
                   !is_number(tokens[k])) {
                const std::string_view option = tokens[k++];
                std::size_t values = 1;
                if (option == "-o" || option == "-s" || option == "-t") values = 3;
                if (option == "-mm") values = 2;
                if (option == "-bm") {
                    if (k >= tokens.size()) fail("-bm needs a value");
                    multiplier = mtl_number(tokens[k++], fail);
                    continue;
                }
                for (std::size_t v = 0; v < values && k < tokens.size(); ++v) {
                    if (values == 3 && !is_number(tokens[k])) break;  // -o u [v [w]]
                    ++k;
                }
            }
            if (k >= tokens.size()) fail(std::string(keyword) + " needs a file name");
            std::string file(tokens[k]);
            for (++k; k < tokens.size(); ++k) {
                file.push_back(' ');
                file.append(tokens[k]);
            }
            std::replace(file.begin(), file.end(), '\\', '/');
            if (keyword == "map_Kd") {
                m.kd_map = file;
            } else if (keyword == "map_Pr") {
                m.roughness_map = file;
            } else if (keyword == "norm" || keyword == "map_Norm") {
                m.normal_map = file;
                m.bump_multiplier = multiplier;
            } else {
                m.bump_map = file;
                m.bump_multiplier = multiplier;
            }
        }
    }
    return materials;
}

std::vector<MtlMaterial> load_mtl(const std::string& path) {
    return parse_mtl(read_regular_file(path, kMaxObjFileBytes, "an MTL file"), path);
}

}  // namespace leanfade::scene
