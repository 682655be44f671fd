#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <limits>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/mesh.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

// The bounding radii a mesh may have: the renderer scales the object to radius 1 in float, and
// the inverse of that scale's 3x3 matrix (the normal matrix; its determinant is radius^-3) must
// stay in float range. Beyond, renders came out NaN.
constexpr double kMinBoundingRadius = 1e-12;
constexpr double kMaxBoundingRadius = 1e12;

}  // namespace

// In double: the float sum, difference and squares of coordinates near the float maximum
// overflow (compute_bounds refuses boxes whose radius is outside [1e-12, 1e12]).
glm::vec3 Bounds::center() const {
    return glm::vec3(0.5 * (glm::dvec3(min) + glm::dvec3(max)));
}

float Bounds::radius() const {
    return float(0.5 * glm::length(glm::dvec3(max) - glm::dvec3(min)));
}

std::size_t Mesh::triangle_count() const {
    return indices.size() / 3;
}

namespace detail {

void require_triangle_indices(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        throw Error(mesh.name, "index count " + std::to_string(mesh.indices.size()) +
                                   " is not a multiple of 3");
    const std::size_t n = mesh.vertices.size();
    for (const std::uint32_t index : mesh.indices)
        if (index >= n)
            throw Error(mesh.name, "index " + std::to_string(index) + " out of range (" +
                                       std::to_string(n) + " vertices)");
}

}  // namespace detail

void generate_tangents(Mesh& mesh) {
    const std::size_t n = mesh.vertices.size();
    detail::require_triangle_indices(mesh);
    // Accumulate in double: large meshes sum many small contributions.
    std::vector<glm::dvec3> tan_sum(n, glm::dvec3(0.0));
    std::vector<glm::dvec3> bit_sum(n, glm::dvec3(0.0));
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        const std::uint32_t i[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        const Vertex& v0 = mesh.vertices[i[0]];
        const Vertex& v1 = mesh.vertices[i[1]];
        const Vertex& v2 = mesh.vertices[i[2]];
        const glm::dvec3 e1 = glm::dvec3(v1.position) - glm::dvec3(v0.position);
        const glm::dvec3 e2 = glm::dvec3(v2.position) - glm::dvec3(v0.position);
        const glm::dvec2 d1 = glm::dvec2(v1.uv) - glm::dvec2(v0.uv);
        const glm::dvec2 d2 = glm::dvec2(v2.uv) - glm::dvec2(v0.uv);
        const double area = 0.5 * glm::length(glm::cross(e1, e2));
        const double r = d1.x * d2.y - d2.x * d1.y;
        // Zero-area triangles and (near-)collinear UVs give no usable derivative.
        if (!(area > 0.0) || !(std::abs(r) > 1e-12 * glm::length(d1) * glm::length(d2))) {
            continue;
        }
        const glm::dvec3 dpdu = (e1 * d2.y - e2 * d1.y) / r;
        const glm::dvec3 dpdv = (e2 * d1.x - e1 * d2.x) / r;
        const double lu = glm::length(dpdu);
        const double lv = glm::length(dpdv);
        if (!(lu > 0.0) || !(lv > 0.0) || !std::isfinite(lu) || !std::isfinite(lv)) {
            continue;
        }
        for (std::uint32_t k : i) {
            tan_sum[k] += dpdu * (area / lu);
            bit_sum[k] += dpdv * (area / lv);
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        Vertex& v = mesh.vertices[k];
        const glm::dvec3 nrm = glm::dvec3(v.normal);
        const double nlen = glm::length(nrm);
        if (!(nlen > 0.0) || !std::isfinite(nlen)) {
            v.tangent = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);
            continue;
        }
        const glm::dvec3 nn = nrm / nlen;
        const glm::dvec3 ts = tan_sum[k];
        const glm::dvec3 bs = bit_sum[k];
        const glm::dvec3 t_perp = ts - nn * glm::dot(nn, ts);
        const glm::dvec3 b_perp = bs - nn * glm::dot(nn, bs);
        const double t_len = glm::length(t_perp);
        const double b_len = glm::length(b_perp);
        glm::dvec3 tangent;
        double w = 1.0;
        if (t_len > 1e-6 * glm::length(ts) && t_len > 0.0) {
            tangent = t_perp / t_len;
            w = glm::dot(glm::cross(nn, tangent), bs) < 0.0 ? -1.0 : 1.0;
        } else if (b_len > 1e-6 * glm::length(bs) && b_len > 0.0) {
            // cross(N, cross(B, N)) = B for B orthogonal to N, so w = +1.
            tangent = glm::normalize(glm::cross(b_perp / b_len, nn));
        } else {
            tangent = glm::dvec3(detail::any_orthonormal(glm::vec3(nn)));
        }
        v.tangent = glm::vec4(glm::vec3(tangent), float(w));
    }
}

void compute_bounds(Mesh& mesh) {
    if (mesh.vertices.empty()) {
        mesh.bounds = Bounds{};
        return;
    }
    glm::vec3 lo(std::numeric_limits<float>::max());
    glm::vec3 hi(std::numeric_limits<float>::lowest());
    for (const Vertex& v : mesh.vertices) {
        lo = glm::min(lo, v.position);
        hi = glm::max(hi, v.position);
    }
    // A zero radius (one point) is left to the renderer, which names it.
    const double radius = 0.5 * glm::length(glm::dvec3(hi) - glm::dvec3(lo));
    if (radius != 0.0 && !(radius >= kMinBoundingRadius && radius <= kMaxBoundingRadius)) {
        char text[64];
        std::snprintf(text, sizeof text, "%.3g", radius);
        throw Error(mesh.name, std::string("the vertex positions span a bounding radius of ") +
                                   text +
                                   " units; the renderer scales objects to radius 1 in float, "
                                   "which needs a radius in [1e-12, 1e12]");
    }
    mesh.bounds = Bounds{lo, hi};
}

namespace detail {

glm::vec3 any_orthonormal(const glm::vec3& n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    return glm::normalize(glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x));
}

void remove_unused_vertices(Mesh& mesh) {
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> remap(mesh.vertices.size(), kUnused);
    for (std::uint32_t i : mesh.indices) {
        remap[i] = 0;
    }
    std::uint32_t next = 0;
    for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
        if (remap[k] != kUnused) {
            remap[k] = next;
            mesh.vertices[next] = mesh.vertices[k];
            ++next;
        }
    }
    mesh.vertices.resize(next);
    for (std::uint32_t& i : mesh.indices) {
        i = remap[i];
    }
}

void center_on_origin(Mesh& mesh) {
    compute_bounds(mesh);
    const glm::vec3 c = mesh.bounds.center();
    for (Vertex& v : mesh.vertices) {
        v.position -= c;
    }
}

void finish(Mesh& mesh) {
    for (Vertex& v : mesh.vertices) v.uv1 = v.uv;
    generate_tangents(mesh);
    measure_normal_linearity(mesh);
    compute_bounds(mesh);
}

void append_grid(Mesh& mesh, int nu, int nv, const CollapsedEdges& collapsed,
                 const std::function<Vertex(double s, double t)>& vertex_at) {
    const auto base = std::uint32_t(mesh.vertices.size());
    const auto row = std::uint32_t(nu) + 1;
    for (int j = 0; j <= nv; ++j) {
        for (int i = 0; i <= nu; ++i) {
            double s = double(i) / nu;
            double t = double(j) / nv;
            // A pole copy is used by exactly one triangle: move it to the middle of that cell.
            if ((j == 0 && collapsed.v0) || (j == nv && collapsed.v1)) {
                s = (double(i) + (j == 0 ? 0.5 : -0.5)) / nu;
            }
            if ((i == 0 && collapsed.u0) || (i == nu && collapsed.u1)) {
                t = (double(j) + (i == 0 ? 0.5 : -0.5)) / nv;
            }
            mesh.vertices.push_back(vertex_at(s, t));
        }
    }
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            const std::uint32_t a = base + std::uint32_t(j) * row + std::uint32_t(i);
            const std::uint32_t b = a + 1;
            const std::uint32_t c = a + row + 1;
            const std::uint32_t d = a + row;
            const bool abc_degenerate = (j == 0 && collapsed.v0) || (i + 1 == nu && collapsed.u1);
            const bool acd_degenerate = (j + 1 == nv && collapsed.v1) || (i == 0 && collapsed.u0);
            if (!abc_degenerate) {
                mesh.indices.insert(mesh.indices.end(), {a, b, c});
            }
            if (!acd_degenerate) {
                mesh.indices.insert(mesh.indices.end(), {a, c, d});
            }
        }
    }
}

}  // namespace detail
}  // namespace leanfade::scene
