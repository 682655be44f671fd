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
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <tiny_obj_loader.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/obj_loader.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

std::string read_file(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        throw Error(path, "file not found");
    }
    if (std::filesystem::is_directory(status)) {
        throw Error(path, "is a directory, not an OBJ file");
    }
    if (!std::filesystem::is_regular_file(status)) {  // a FIFO would block the read forever
        throw Error(path, "is not a regular file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw Error(path, "cannot open for reading");
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) {
        throw Error(path, "read error");
    }
    return text.str();
}

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

// A token quoted for an error message, without letting binary junk through.
std::string quoted(std::string_view token) {
    std::string out(1, '\'');
    for (char c : token.substr(0, 32)) {
        out.push_back(std::isprint(static_cast<unsigned char>(c)) ? c : '?');
    }
    out.append(token.size() > 32 ? "...'" : "'");
    return out;
}

// Checks every number on v / vt / vn lines and every index on f lines (Error(path, ...) with the
// line number) and returns the text tinyobjloader parses: only the v, vt, vn and f lines (every
// other line becomes empty, so line numbers stay), without comments ('#' to the end of a line,
// which tinyobjloader only understands at the start of a line), each number rewritten as the
// value checked here ("%.9g": 9 significant digits, enough for a float). tinyobjloader's own
// number parser mis-reads forms strtod accepts ("0x10" becomes 0; the exponent of
// "0e2147483649" overflows an int) and its parsers of lines leanfade ignores (vw, l, p, s, ...)
// have undefined behaviour on hostile values (found by fuzz_obj, docs/robustness.md): they
// never see the file's own text.
std::string precheck(const std::string& path, const std::string& text) {
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
            for (std::size_t k = 1; k < tokens.size(); ++k) {
                std::string_view rest = tokens[k];
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
                }
                if (!rest.empty()) {
                    fail("malformed face vertex " + quoted(tokens[k]));  // "1/2/3/4"
                }
            }
            for (const std::string_view token : tokens) {
                clean.append(token);
                clean.push_back(' ');
            }
            clean.back() = '\n';
        } else {
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

struct KeyHash {
    std::size_t operator()(const std::array<long long, 3>& k) const {
        std::size_t h = std::hash<long long>{}(k[0]);
        h ^= std::hash<long long>{}(k[1]) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        h ^= std::hash<long long>{}(k[2]) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        return h;
    }
};

}  // namespace

Mesh load_obj(const std::string& path) {
    return load_obj_from_memory(read_file(path), path);
}

Mesh load_obj_from_memory(const std::string& file_text, const std::string& path) {
    const std::string text = precheck(path, file_text);

    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
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
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        std::size_t offset = 0;
        for (const unsigned int face_size : shape.mesh.num_face_vertices) {
            if (offset + face_size > shape.mesh.indices.size()) {
                throw Error(path, "parse failure: face list inconsistent");
            }
            // Triangulation is on; any remaining polygon is split as a fan.
            for (unsigned int k = 1; k + 1 < face_size; ++k) {
                for (unsigned int c : {0u, k, k + 1}) {
                    const tinyobj::index_t& idx = shape.mesh.indices[offset + c];
                    if (idx.vertex_index < 0 || idx.vertex_index >= position_count ||
                        idx.normal_index >= normal_count || idx.texcoord_index >= uv_count) {
                        throw Error(path, "face index out of range");
                    }
                    long long n = idx.normal_index;
                    if (n >= 0) {
                        const glm::dvec3 vn(attrib.normals[std::size_t(3 * n)],
                                            attrib.normals[std::size_t(3 * n + 1)],
                                            attrib.normals[std::size_t(3 * n + 2)]);
                        if (!(glm::length(vn) > 1e-20)) {
                            n = -1;  // a zero normal is as good as none
                        }
                    }
                    corners.push_back({idx.vertex_index, n, std::max(idx.texcoord_index, -1)});
                }
            }
            offset += face_size;
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

}  // namespace leanfade::scene
