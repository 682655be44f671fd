// The Utah teapot from its 32 bicubic Bezier patches (data embedded at build time).
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "mesh_internal.hpp"

namespace leanfade::embedded {
const std::map<std::string, std::string_view>& scene_data();
}  // namespace leanfade::embedded

namespace leanfade::scene {
namespace {

constexpr const char* kDataName = "utah_teapot.txt";
constexpr double kScale = 1.0 / 3.0;

using Patch = std::array<std::array<glm::dvec3, 4>, 4>;  // [k][l]: k along u (a), l along v (b)

struct TeapotData {
    std::vector<std::array<int, 16>> patches;
    std::vector<glm::dvec3> points;  // as stored: z up, data units
};

[[noreturn]] void data_error(const std::string& cause) {
    throw Error(std::string(kDataName) + " (embedded)", cause);
}

TeapotData parse(std::string_view text) {
    // Drop '#' comments, then read whitespace-separated tokens.
    std::string clean;
    clean.reserve(text.size());
    bool comment = false;
    for (char c : text) {
        if (c == '#') {
            comment = true;
        } else if (c == '\n') {
            comment = false;
        }
        if (!comment) {
            clean.push_back(c);
        }
    }
    std::istringstream in(clean);
    TeapotData data;
    std::string keyword;
    long long count = 0;
    if (!(in >> keyword >> count) || keyword != "patches" || count <= 0 || count > 4096) {
        data_error("expected 'patches N' with 0 < N <= 4096");
    }
    data.patches.resize(std::size_t(count));
    for (auto& patch : data.patches) {
        for (int& index : patch) {
            if (!(in >> index) || index < 0) {
                data_error("bad control-point index in patch list");
            }
        }
    }
    if (!(in >> keyword >> count) || keyword != "vertices" || count <= 0 || count > 1000000) {
        data_error("expected 'vertices M' after the patches");
    }
    data.points.resize(std::size_t(count));
    for (auto& p : data.points) {
        if (!(in >> p.x >> p.y >> p.z) || !std::isfinite(p.x) || !std::isfinite(p.y) ||
            !std::isfinite(p.z)) {
            data_error("bad control-point coordinates");
        }
    }
    for (const auto& patch : data.patches) {
        for (int index : patch) {
            if (std::size_t(index) >= data.points.size()) {
                data_error("control-point index " + std::to_string(index) + " out of range");
            }
        }
    }
    return data;
}

const TeapotData& teapot_data() {
    static const TeapotData data = [] {
        const auto& files = embedded::scene_data();
        const auto it = files.find(kDataName);
        if (it == files.end()) {
            data_error("missing from the embedded scene data");
        }
        return parse(it->second);
    }();
    return data;
}

// Cubic Bernstein basis and its derivative at t.
std::array<double, 4> bernstein(double t) {
    const double s = 1.0 - t;
    return {s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t};
}
std::array<double, 4> bernstein_derivative(double t) {
    const double s = 1.0 - t;
    return {-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t};
}

struct Sample {
    glm::dvec3 p;    // position
    glm::dvec3 pa;   // dP/da
    glm::dvec3 pb;   // dP/db
    glm::dvec3 pab;  // d2P/da db
};

Sample evaluate(const Patch& c, double a, double b) {
    const auto ba = bernstein(a);
    const auto bb = bernstein(b);
    const auto da = bernstein_derivative(a);
    const auto db = bernstein_derivative(b);
    Sample s{glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
    for (std::size_t k = 0; k < 4; ++k) {
        for (std::size_t l = 0; l < 4; ++l) {
            s.p += (ba[k] * bb[l]) * c[k][l];
            s.pa += (da[k] * bb[l]) * c[k][l];
            s.pb += (ba[k] * db[l]) * c[k][l];
            s.pab += (da[k] * db[l]) * c[k][l];
        }
    }
    return s;
}

bool same_points(const std::array<glm::dvec3, 4>& row) {
    return row[1] == row[0] && row[2] == row[0] && row[3] == row[0];
}

detail::CollapsedEdges collapsed_edges(const Patch& c) {
    detail::CollapsedEdges e;
    e.u0 = same_points(c[0]);  // a = 0: k = 0, all l
    e.u1 = same_points(c[3]);
    e.v0 = same_points({c[0][0], c[1][0], c[2][0], c[3][0]});  // b = 0: l = 0, all k
    e.v1 = same_points({c[0][3], c[1][3], c[2][3], c[3][3]});
    return e;
}

// Unnormalised normal cross(dP/da, dP/db). On a collapsed edge one derivative vanishes and the
// normal is its limit: e.g. at a = 0, dP/db ~ a * d2P/dadb, so N ~ cross(dP/da, d2P/dadb).
glm::dvec3 raw_normal(const Sample& s, const detail::CollapsedEdges& e, double a, double b) {
    if (e.u0 && a <= 0.0) {
        return glm::cross(s.pa, s.pab);
    }
    if (e.u1 && a >= 1.0) {
        return -glm::cross(s.pa, s.pab);
    }
    if (e.v0 && b <= 0.0) {
        return glm::cross(s.pab, s.pb);
    }
    if (e.v1 && b >= 1.0) {
        return -glm::cross(s.pab, s.pb);
    }
    return glm::cross(s.pa, s.pb);
}

glm::dvec3 unit_normal(const Patch& c, const detail::CollapsedEdges& e, double a, double b) {
    const Sample s = evaluate(c, a, b);
    const double scale = glm::length(c[3][3] - c[0][0]) + glm::length(c[3][0] - c[0][3]);
    glm::dvec3 n = raw_normal(s, e, a, b);
    // Any other degenerate point: step toward the patch centre until the normal is defined.
    for (double step = 1e-5; glm::length(n) <= 1e-12 * scale * scale && step < 0.5; step *= 4.0) {
        const double na = a + (0.5 - a) * step;
        const double nb = b + (0.5 - b) * step;
        const Sample near = evaluate(c, na, nb);
        n = glm::cross(near.pa, near.pb);
    }
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) {
        data_error("patch normal undefined");
    }
    return n / len;
}

// Mean arc length of the curves a -> P(a, b) for b in {0, 1/2, 1} (along_a), or of
// b -> P(a, b) for a in {0, 1/2, 1}, leaving out collapsed ones.
double mean_length(const Patch& c, bool along_a) {
    constexpr int kSteps = 64;
    double total = 0.0;
    int curves = 0;
    for (double fixed : {0.0, 0.5, 1.0}) {
        double length = 0.0;
        glm::dvec3 prev = along_a ? evaluate(c, 0.0, fixed).p : evaluate(c, fixed, 0.0).p;
        for (int i = 1; i <= kSteps; ++i) {
            const double x = double(i) / kSteps;
            const glm::dvec3 p = along_a ? evaluate(c, x, fixed).p : evaluate(c, fixed, x).p;
            length += glm::length(p - prev);
            prev = p;
        }
        if (length > 0.0) {
            total += length;
            ++curves;
        }
    }
    return curves > 0 ? total / curves : 0.0;
}

// Rotates the parameter domain by 180 degrees (a -> 1 - a, b -> 1 - b; the orientation, hence
// the normal, is unchanged) where needed so that u runs counter-clockwise about +y seen from
// above at the patch centre. Then u agrees across the seams between the rotational parts (rim,
// body, lid, bottom) and the tiled texture continues across them.
void orient_u_around_y(Patch& c) {
    const Sample s = evaluate(c, 0.5, 0.5);
    if (glm::cross(s.p, s.pa).y >= 0.0) {
        return;
    }
    Patch rotated;
    for (std::size_t k = 0; k < 4; ++k) {
        for (std::size_t l = 0; l < 4; ++l) {
            rotated[k][l] = c[3 - k][3 - l];
        }
    }
    c = rotated;
}

}  // namespace

Mesh make_teapot(int subdivisions) {
    if (subdivisions < 1 || subdivisions > 512) {
        throw Error("teapot",
                    "subdivisions must be in [1, 512], got " + std::to_string(subdivisions));
    }
    const TeapotData& data = teapot_data();
    const int n = subdivisions;
    Mesh mesh;
    mesh.name = "teapot";
    mesh.vertices.reserve(data.patches.size() * std::size_t(n + 1) * std::size_t(n + 1));
    mesh.indices.reserve(data.patches.size() * std::size_t(n) * std::size_t(n) * 6);
    for (const auto& indices : data.patches) {
        // Stored rows i (first parameter) and columns j: cross(dP/di, dP/dj) points into the
        // teapot for every patch of this data set. Using a = 1 - j/3 along u and b = 1 - i/3
        // along v swaps the parameters, so the normal points outward, and makes v run upward on
        // the body; orient_u_around_y() then fixes the sense of u (bottom patches).
        // Axes: stored (x, y, z) with z up becomes (x, z, -y), y up, times kScale.
        Patch c;
        for (std::size_t k = 0; k < 4; ++k) {
            for (std::size_t l = 0; l < 4; ++l) {
                const glm::dvec3 q = data.points[std::size_t(indices[(3 - l) * 4 + (3 - k)])];
                c[k][l] = glm::dvec3(q.x, q.z, -q.y) * kScale;
            }
        }
        orient_u_around_y(c);
        const detail::CollapsedEdges edges = collapsed_edges(c);
        const double tiles_u = std::max(1.0, std::round(mean_length(c, true) / kTileLength));
        const double tiles_v = std::max(1.0, std::round(mean_length(c, false) / kTileLength));
        detail::append_grid(mesh, n, n, edges, [&](double a, double b) {
            const Sample s = evaluate(c, a, b);
            Vertex v{};
            v.position = glm::vec3(s.p);
            // Exact pole position on a collapsed edge (the Bernstein sum only rounds to it).
            if ((edges.u0 && a <= 0.0) || (edges.v0 && b <= 0.0)) {
                v.position = glm::vec3(c[0][0]);
            } else if ((edges.u1 && a >= 1.0) || (edges.v1 && b >= 1.0)) {
                v.position = glm::vec3(c[3][3]);
            }
            v.normal = glm::vec3(unit_normal(c, edges, a, b));
            v.uv = glm::vec2(float(tiles_u * a), float(tiles_v * b));
            return v;
        });
    }
    detail::remove_unused_vertices(mesh);
    detail::center_on_origin(mesh);
    detail::finish(mesh);
    return mesh;
}

}  // namespace leanfade::scene
