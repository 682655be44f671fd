// How far each vertex's normal field is linear (Vertex::linear_normal_change, docs/math.md §11).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "leanfade/scene/detail/mesh.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

// A neighbourhood is smooth while its quadratic fit's residual stays within this share of the
// slopes' spread.
constexpr double kSmoothResidualShare = 0.25;
// At most this many neighbours per vertex (four rings of a regular grid are 60): a fan of a
// hundred thousand triangles around one vertex (a hostile OBJ face) costs each of its vertices
// this much, not the whole fan.
constexpr std::size_t kMaxNeighbourhood = 128;

// Each vertex's neighbours through one triangle edge, as offsets into one list (CSR).
struct Adjacency {
    std::vector<std::uint32_t> first;  // vertex count + 1
    std::vector<std::uint32_t> neighbours;
};

Adjacency adjacency_of(const Mesh& mesh) {
    const std::size_t n = mesh.vertices.size();
    std::vector<std::uint64_t> edges;
    edges.reserve(mesh.indices.size() * 2);
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = mesh.indices[t + std::size_t(k)];
            const std::uint64_t b = mesh.indices[t + std::size_t((k + 1) % 3)];
            if (a == b) continue;
            edges.push_back(a << 32 | b);
            edges.push_back(b << 32 | a);
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    Adjacency adjacency;
    adjacency.first.assign(n + 1, 0);
    for (const std::uint64_t e : edges) ++adjacency.first[std::size_t(e >> 32) + 1];
    for (std::size_t i = 0; i < n; ++i) adjacency.first[i + 1] += adjacency.first[i];
    adjacency.neighbours.reserve(edges.size());
    for (const std::uint64_t e : edges) adjacency.neighbours.push_back(std::uint32_t(e));
    return adjacency;
}

// Whether a neighbourhood's normals are smooth: their slopes in the centre's tangent plane
// fitted as a quadratic function of the offsets (slope = J d + the three second-order terms,
// anchored at the centre's own slope 0) leave a residual within kSmoothResidualShare of the
// slopes' own spread.
struct RingFit {
    bool decided = false;  // false: too few neighbours for the fit, or they do not span it
    bool smooth = true;
};

constexpr std::size_t kTerms = 5;

// The fit's terms of an offset d: dx, dy, dx^2, dx dy, dy^2.
std::array<double, kTerms> quadratic_terms(const glm::dvec2& d) {
    return {d.x, d.y, d.x * d.x, d.x * d.y, d.y * d.y};
}

RingFit fit_ring(const std::vector<glm::dvec2>& offsets, const std::vector<glm::dvec2>& slopes) {
    RingFit fit;
    if (offsets.size() < 2 * kTerms) return fit;
    double radius = 0.0;
    for (const glm::dvec2& d : offsets) radius = std::max(radius, glm::length(d));
    if (!(radius > 0.0)) return fit;
    // Normal equations A [cx cy] = [bx by] in offsets scaled to the unit disc (conditioning).
    double a[kTerms][kTerms] = {};
    double b[kTerms][2] = {};
    double spread = 0.0;
    for (std::size_t i = 0; i < offsets.size(); ++i) {
        const std::array<double, kTerms> phi = quadratic_terms(offsets[i] / radius);
        for (std::size_t r = 0; r < kTerms; ++r) {
            for (std::size_t c = 0; c < kTerms; ++c) a[r][c] += phi[r] * phi[c];
            b[r][0] += phi[r] * slopes[i].x;
            b[r][1] += phi[r] * slopes[i].y;
        }
        spread += glm::dot(slopes[i], slopes[i]);
    }
    // Gaussian elimination with partial pivoting; a pivot below 1e-9 of the diagonal's scale
    // means the offsets do not determine the terms (collinear, one-sided).
    double scale = 0.0;
    for (std::size_t r = 0; r < kTerms; ++r) scale = std::max(scale, a[r][r]);
    for (std::size_t col = 0; col < kTerms; ++col) {
        std::size_t pivot = col;
        for (std::size_t r = col + 1; r < kTerms; ++r)
            if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
        if (!(std::abs(a[pivot][col]) > 1e-9 * scale)) return fit;
        for (std::size_t c = 0; c < kTerms; ++c) std::swap(a[col][c], a[pivot][c]);
        std::swap(b[col][0], b[pivot][0]);
        std::swap(b[col][1], b[pivot][1]);
        for (std::size_t r = 0; r < kTerms; ++r) {
            if (r == col) continue;
            const double f = a[r][col] / a[col][col];
            for (std::size_t c = col; c < kTerms; ++c) a[r][c] -= f * a[col][c];
            b[r][0] -= f * b[col][0];
            b[r][1] -= f * b[col][1];
        }
    }
    double residual = 0.0;
    for (std::size_t i = 0; i < offsets.size(); ++i) {
        const std::array<double, kTerms> phi = quadratic_terms(offsets[i] / radius);
        glm::dvec2 predicted(0.0);
        for (std::size_t r = 0; r < kTerms; ++r)
            predicted += phi[r] * glm::dvec2(b[r][0], b[r][1]) / a[r][r];
        const glm::dvec2 e = slopes[i] - predicted;
        residual += glm::dot(e, e);
    }
    fit.decided = true;
    // A plane (every slope 0 up to rounding) is smooth.
    fit.smooth = std::sqrt(residual) <=
                 kSmoothResidualShare * std::sqrt(spread) + 1e-7 * std::sqrt(double(offsets.size()));
    return fit;
}

}  // namespace

void measure_normal_linearity(Mesh& mesh) {
    detail::require_triangle_indices(mesh);
    const std::size_t n = mesh.vertices.size();
    const Adjacency adjacency = adjacency_of(mesh);
    std::vector<std::uint32_t> seen(n, 0);
    std::uint32_t stamp = 0;
    std::vector<std::uint32_t> frontier, next;
    std::vector<glm::dvec2> offsets, slopes;
    for (std::size_t v = 0; v < n; ++v) {
        Vertex& centre = mesh.vertices[v];
        const glm::dvec3 normal = glm::normalize(glm::dvec3(centre.normal));
        const glm::dvec3 t = glm::dvec3(detail::any_orthonormal(glm::vec3(normal)));
        const glm::dvec3 b = glm::cross(normal, t);
        ++stamp;
        seen[v] = stamp;
        frontier.assign(1, std::uint32_t(v));
        offsets.clear();
        slopes.clear();
        double change = 0.0;       // to the first ring
        double ring_change = 0.0;  // to the rings so far
        bool smooth = true;
        for (int ring = 1; ring <= kLinearityRings && !frontier.empty(); ++ring) {
            next.clear();
            for (const std::uint32_t u : frontier) {
                if (offsets.size() >= kMaxNeighbourhood) break;
                for (std::uint32_t k = adjacency.first[u]; k < adjacency.first[u + 1]; ++k) {
                    if (offsets.size() >= kMaxNeighbourhood) break;
                    const std::uint32_t w = adjacency.neighbours[k];
                    if (seen[w] == stamp) continue;
                    seen[w] = stamp;
                    next.push_back(w);
                    const Vertex& q = mesh.vertices[w];
                    const glm::dvec3 d = glm::dvec3(q.position) - glm::dvec3(centre.position);
                    const glm::dvec3 m = glm::dvec3(q.normal);
                    // The neighbour's normal as a slope in the centre's frame (a normal turned
                    // by 84 degrees or more counts as slope 10: far from smooth either way).
                    const double z = std::max(glm::dot(m, normal), 0.1);
                    offsets.emplace_back(glm::dot(d, t), glm::dot(d, b));
                    slopes.emplace_back(glm::dot(m, t) / z, glm::dot(m, b) / z);
                    ring_change = std::max(ring_change, glm::length(slopes.back()));
                }
            }
            frontier.swap(next);
            if (ring == 1) change = ring_change;
            if (smooth) {
                const RingFit fit = fit_ring(offsets, slopes);
                smooth = !(fit.decided && !fit.smooth);
            }
        }
        // Not smooth within a few rings: a triangle's derivatives hold only inside it, and the
        // 2 x 2 pixels they come from fit in it while a pixel spans at most half an edge, over
        // which the normal's slope changes by half its change to the first ring.
        centre.linear_normal_change = smooth ? 0.0f : float(std::max(0.5 * change, 1e-6));
    }
}

}  // namespace leanfade::scene
