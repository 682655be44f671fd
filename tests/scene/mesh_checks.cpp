#include "mesh_checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace leanfade::scene::test {
namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

// A hash grid of cell 2 * tolerance: each point looks at the 27 cells around its own.
std::vector<std::uint32_t> weld_positions(const Mesh& mesh, float tolerance, std::size_t& count) {
    struct CellHash {
        std::size_t operator()(const std::array<long long, 3>& c) const {
            return std::size_t(c[0] * 73856093LL ^ c[1] * 19349663LL ^ c[2] * 83492791LL);
        }
    };
    std::unordered_map<std::array<long long, 3>, std::vector<std::uint32_t>, CellHash> grid;
    std::vector<std::uint32_t> id(mesh.vertices.size());
    std::vector<glm::vec3> representatives;
    const double cell = 2.0 * double(tolerance);
    for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
        const glm::vec3 p = mesh.vertices[k].position;
        const std::array<long long, 3> c = {std::llround(std::floor(p.x / cell)),
                                            std::llround(std::floor(p.y / cell)),
                                            std::llround(std::floor(p.z / cell))};
        std::uint32_t found = UINT32_MAX;
        for (long long dx = -1; dx <= 1 && found == UINT32_MAX; ++dx) {
            for (long long dy = -1; dy <= 1 && found == UINT32_MAX; ++dy) {
                for (long long dz = -1; dz <= 1 && found == UINT32_MAX; ++dz) {
                    const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == grid.end()) {
                        continue;
                    }
                    for (std::uint32_t r : it->second) {
                        if (glm::length(representatives[r] - p) <= tolerance) {
                            found = r;
                            break;
                        }
                    }
                }
            }
        }
        if (found == UINT32_MAX) {
            found = std::uint32_t(representatives.size());
            representatives.push_back(p);
            grid[c].push_back(found);
        }
        id[k] = found;
    }
    count = representatives.size();
    return id;
}

FrameStats frame_stats(const Mesh& mesh) {
    FrameStats s;
    for (const Vertex& v : mesh.vertices) {
        const glm::vec3 t(v.tangent);
        if (!finite(v.position) || !finite(v.normal) || !finite(t) || !std::isfinite(v.tangent.w) ||
            !std::isfinite(v.uv.x) || !std::isfinite(v.uv.y)) {
            ++s.non_finite;
            continue;
        }
        s.max_normal_error = std::max(s.max_normal_error, std::abs(glm::length(v.normal) - 1.0f));
        s.max_tangent_error = std::max(s.max_tangent_error, std::abs(glm::length(t) - 1.0f));
        s.max_tangent_dot_normal =
            std::max(s.max_tangent_dot_normal, std::abs(glm::dot(t, v.normal)));
        if (v.tangent.w != 1.0f && v.tangent.w != -1.0f) {
            ++s.bad_handedness;
        }
        if (v.tangent.w == -1.0f) {
            ++s.left_handed;
        }
    }
    return s;
}

UvFrameStats uv_frame_stats(const Mesh& mesh) {
    UvFrameStats s;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const Vertex* v[3] = {&mesh.vertices[mesh.indices[t]], &mesh.vertices[mesh.indices[t + 1]],
                              &mesh.vertices[mesh.indices[t + 2]]};
        const glm::dvec3 e1 = glm::dvec3(v[1]->position - v[0]->position);
        const glm::dvec3 e2 = glm::dvec3(v[2]->position - v[0]->position);
        const glm::dvec2 d1 = glm::dvec2(v[1]->uv - v[0]->uv);
        const glm::dvec2 d2 = glm::dvec2(v[2]->uv - v[0]->uv);
        const double r = d1.x * d2.y - d2.x * d1.y;
        const glm::dvec3 face = glm::cross(e1, e2);
        if (std::abs(r) < 1e-12 || glm::length(face) < 1e-14) {
            continue;
        }
        const glm::dvec3 fn = glm::normalize(face);
        const glm::dvec3 dpdu = glm::normalize((e1 * d2.y - e2 * d1.y) / r);
        const glm::dvec3 dpdv = glm::normalize((e2 * d1.x - e1 * d2.x) / r);
        for (const Vertex* c : v) {
            const glm::dvec3 n(c->normal);
            const glm::dvec3 tan(c->tangent);
            const glm::dvec3 bit = double(c->tangent.w) * glm::cross(n, tan);
            const glm::dvec3 tp = tan - fn * glm::dot(fn, tan);
            const glm::dvec3 bp = bit - fn * glm::dot(fn, bit);
            const glm::dvec3 tn = glm::normalize(tp);
            const float ct = float(glm::dot(tn, dpdu));
            const float cb = float(glm::dot(glm::normalize(bp), dpdv));
            const float co =
                float(glm::dot(glm::normalize(bp), glm::normalize(dpdv - tn * glm::dot(tn, dpdv))));
            s.min_cos_bitangent_orthogonal =
                std::min(s.min_cos_bitangent_orthogonal, std::isfinite(co) ? co : -2.0f);
            ++s.corners;
            s.min_cos_tangent = std::min(s.min_cos_tangent, std::isfinite(ct) ? ct : -2.0f);
            s.min_cos_bitangent = std::min(s.min_cos_bitangent, std::isfinite(cb) ? cb : -2.0f);
            s.tangent_opposed += (ct > 0.0f) ? 0 : 1;
            s.bitangent_opposed += (cb > 0.0f) ? 0 : 1;
        }
    }
    return s;
}

WindingStats winding_stats(const Mesh& mesh) {
    WindingStats s;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        ++s.triangles;
        const Vertex& a = mesh.vertices[mesh.indices[t]];
        const Vertex& b = mesh.vertices[mesh.indices[t + 1]];
        const Vertex& c = mesh.vertices[mesh.indices[t + 2]];
        const glm::dvec3 face =
            glm::cross(glm::dvec3(b.position - a.position), glm::dvec3(c.position - a.position));
        if (glm::length(face) < 1e-14) {
            ++s.degenerate;
            continue;
        }
        const glm::dvec3 fn = glm::normalize(face);
        bool bad = false;
        for (const Vertex* v : {&a, &b, &c}) {
            const float d = float(glm::dot(fn, glm::dvec3(v->normal)));
            s.min_dot = std::min(s.min_dot, std::isfinite(d) ? d : -2.0f);
            bad = bad || !(d > 0.0f);
        }
        s.disagreeing += bad ? 1 : 0;
    }
    return s;
}

EdgeStats edge_stats(const Mesh& mesh, float tolerance) {
    EdgeStats s;
    const std::vector<std::uint32_t> id = weld_positions(mesh, tolerance, s.welded_vertices);
    // key: (min, max) -> (count min->max, count max->min)
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<int, int>> edges;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t w[3] = {id[mesh.indices[t]], id[mesh.indices[t + 1]],
                                    id[mesh.indices[t + 2]]};
        if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) {
            ++s.degenerate_triangles;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = w[k];
            const std::uint32_t b = w[(k + 1) % 3];
            auto& e = edges[{std::min(a, b), std::max(a, b)}];
            (a < b ? e.first : e.second) += 1;
        }
    }
    s.edges = edges.size();
    for (const auto& [key, e] : edges) {
        const int total = e.first + e.second;
        if (total == 1) {
            ++s.boundary;
        } else if (total == 2 && e.first == 1) {
            ++s.paired;
        } else if (total == 2) {
            ++s.same_direction;
        } else {
            ++s.non_manifold;
        }
    }
    return s;
}

double signed_volume(const Mesh& mesh) {
    double volume = 0.0;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const glm::dvec3 a(mesh.vertices[mesh.indices[t]].position);
        const glm::dvec3 b(mesh.vertices[mesh.indices[t + 1]].position);
        const glm::dvec3 c(mesh.vertices[mesh.indices[t + 2]].position);
        volume += glm::dot(a, glm::cross(b, c));
    }
    return volume / 6.0;
}

bool indices_valid(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0) {
        return false;
    }
    return std::all_of(mesh.indices.begin(), mesh.indices.end(),
                       [&](std::uint32_t i) { return i < mesh.vertices.size(); });
}

}  // namespace leanfade::scene::test
