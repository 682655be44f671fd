// The Utah teapot: exact Bezier patches, poles, orientation, seams.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "mesh_checks.hpp"

namespace leanfade::scene {
namespace {

constexpr double kPaperTeapot = 79664.0;  // docs/math.md §8

const Mesh& teapot() {
    static const Mesh m = make_teapot();
    return m;
}

TEST(Teapot, CountsMatchThePaper) {
    const Mesh& m = teapot();
    EXPECT_EQ(m.name, "teapot");
    EXPECT_EQ(m.triangle_count(), 64u * 35u * 35u - 8u * 35u);  // 78,120
    EXPECT_NEAR(double(m.triangle_count()), kPaperTeapot, 0.1 * kPaperTeapot);
    EXPECT_EQ(m.vertices.size(), 32u * 36u * 36u - 8u);  // one unused pole copy per pole patch
    EXPECT_EQ(make_teapot(4).triangle_count(), 64u * 16u - 8u * 4u);
    EXPECT_EQ(make_teapot(1).triangle_count(), 64u - 8u);
}

TEST(Teapot, RejectsBadSubdivisions) {
    EXPECT_THROW(make_teapot(0), leanfade::Error);
    EXPECT_THROW(make_teapot(-3), leanfade::Error);
}

TEST(Teapot, UnitNormalsAndOrthonormalFrames) {
    const Mesh& m = teapot();
    ASSERT_TRUE(test::indices_valid(m));
    const auto f = test::frame_stats(m);
    EXPECT_EQ(f.non_finite, 0u);
    EXPECT_LT(f.max_normal_error, 1e-5f);
    EXPECT_LT(f.max_tangent_error, 1e-5f);
    EXPECT_LT(f.max_tangent_dot_normal, 1e-5f);
    EXPECT_EQ(f.bad_handedness, 0u);
    EXPECT_EQ(f.left_handed, 0u);
}

TEST(Teapot, TangentsFollowTheUvDerivatives) {
    const auto u = test::uv_frame_stats(teapot());
    EXPECT_EQ(u.corners, 3 * teapot().triangle_count());
    EXPECT_EQ(u.tangent_opposed, 0u);
    EXPECT_EQ(u.bitangent_opposed, 0u);
    EXPECT_GT(u.min_cos_tangent, 0.98f);
    EXPECT_GT(u.min_cos_bitangent_orthogonal, 0.99f);
}

TEST(Teapot, PatchNormalsAgreeWithTriangleWinding) {
    // Normals come from the patch derivatives, winding from the grid: they must agree everywhere,
    // including the triangles at the collapsed poles.
    const auto w = test::winding_stats(teapot());
    EXPECT_EQ(w.degenerate, 0u);
    EXPECT_EQ(w.disagreeing, 0u);
    EXPECT_GT(w.min_dot, 0.8f);
}

TEST(Teapot, CentredYUpAndScaled) {
    const Mesh& m = teapot();
    EXPECT_NEAR(glm::length(m.bounds.center()), 0.0f, 1e-5f);
    // Data: 3.15 tall (z up), body radius 2, spout tip to handle about 6.43; scaled by 1/3.
    EXPECT_NEAR(m.bounds.max.y - m.bounds.min.y, 3.15f / 3.0f, 1e-4f);
    EXPECT_NEAR(m.bounds.max.z - m.bounds.min.z, 4.0f / 3.0f, 1e-4f);
    EXPECT_NEAR(m.bounds.max.x - m.bounds.min.x, 2.145f, 0.01f);
    // Spout toward +x, handle toward -x: the spout reaches higher than the body's rim.
    const Vertex* spout_tip = &m.vertices[0];
    for (const Vertex& v : m.vertices) {
        if (v.position.x > spout_tip->position.x) {
            spout_tip = &v;
        }
    }
    EXPECT_GT(spout_tip->position.y, 0.2f);
}

TEST(Teapot, PolesHaveTheLimitNormal) {
    const Mesh& m = teapot();
    std::size_t top = 0;
    std::size_t bottom = 0;
    for (const Vertex& v : m.vertices) {
        const bool on_axis = std::abs(v.position.z) < 1e-6f;
        if (on_axis && v.position.y == m.bounds.max.y) {
            ++top;
            EXPECT_GT(v.normal.y, 0.9999f) << "lid knob top must face up";
        }
        if (on_axis && v.position.y == m.bounds.min.y) {
            ++bottom;
            EXPECT_LT(v.normal.y, -0.9999f) << "bottom centre must face down";
        }
    }
    // 4 patches meet at each pole, each with one pole vertex per cell along the collapsed edge.
    EXPECT_EQ(top, 4u * 35u);
    EXPECT_EQ(bottom, 4u * 35u);
}

TEST(Teapot, OrientedOutward) {
    const Mesh& m = teapot();
    EXPECT_GT(test::signed_volume(m), 0.5);
    // The widest points of the body (|z| = 2/3 on the z axis) face away from the centre.
    for (const Vertex& v : m.vertices) {
        if (std::abs(v.position.z) > 0.6666f) {
            EXPECT_GT(v.normal.z * v.position.z, 0.0f);
            EXPECT_GT(std::abs(v.normal.z), 0.99f);
            // There u runs counter-clockwise about +y and v upward.
            const glm::vec3 b = v.tangent.w * glm::cross(v.normal, glm::vec3(v.tangent));
            EXPECT_GT(b.y, 0.99f);
            EXPECT_GT(glm::cross(v.position, glm::vec3(v.tangent)).y, 0.0f);
        }
    }
}

TEST(Teapot, PatchesJoinConsistently) {
    // After welding, every edge is shared by two triangles wound in opposite directions, except
    // along the 16 patch edges that are open in Newell's data: where the lid meets the rim
    // (lid edge and rim's inner edge, 4 patches each) and at both ends of the handle and the
    // spout (2 patches each).
    const Mesh& m = teapot();
    const auto e = test::edge_stats(m, 1e-5f);
    EXPECT_EQ(e.degenerate_triangles, 0u);
    EXPECT_EQ(e.same_direction, 0u);
    EXPECT_EQ(e.non_manifold, 0u);
    EXPECT_EQ(e.boundary, 16u * 35u);
}

TEST(Teapot, NormalsAndTilesContinueAcrossPatchSeams) {
    // For every edge shared by two patches (welded positions), the vertex copies on both sides
    // must have the same normal (Newell's patches join smoothly) and the same position within
    // the texture tile (whole tiles per patch, u counter-clockwise about +y), except that the
    // tiles necessarily converge at the two poles.
    const Mesh& m = teapot();
    std::size_t count = 0;
    const std::vector<std::uint32_t> id = test::weld_positions(m, 1e-5f, count);
    // directed welded edge -> the vertex indices of its two ends in that triangle
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::uint32_t, std::uint32_t>>
        edges;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t a = m.indices[t + k];
            const std::uint32_t b = m.indices[t + (k + 1) % 3];
            edges[{id[a], id[b]}] = {a, b};
        }
    }
    const auto is_pole = [&](const Vertex& v) {
        return std::abs(v.position.z) < 1e-6f &&
               (v.position.y == m.bounds.max.y || v.position.y == m.bounds.min.y);
    };
    const auto frac = [](float x) { return x - std::floor(x + 1e-4f); };
    std::size_t seam_edges = 0;
    float min_normal_dot = 1.0f;
    std::size_t uv_breaks = 0;
    for (const auto& [key, ends] : edges) {
        const auto other = edges.find({key.second, key.first});
        if (other == edges.end() || ends.first == other->second.second) {
            continue;  // a boundary edge, or an edge inside one patch (same vertices)
        }
        ++seam_edges;
        const std::uint32_t pairs[2][2] = {{ends.first, other->second.second},
                                           {ends.second, other->second.first}};
        for (const auto& pair : pairs) {
            const Vertex& a = m.vertices[pair[0]];
            const Vertex& b = m.vertices[pair[1]];
            min_normal_dot = std::min(min_normal_dot, glm::dot(a.normal, b.normal));
            if (!is_pole(a) && (std::abs(frac(a.uv.x) - frac(b.uv.x)) > 1e-3f ||
                                std::abs(frac(a.uv.y) - frac(b.uv.y)) > 1e-3f)) {
                ++uv_breaks;
            }
        }
    }
    EXPECT_GT(seam_edges, 1000u);
    EXPECT_GT(min_normal_dot, 0.99f);
    EXPECT_EQ(uv_breaks, 0u);
}

TEST(Teapot, UvsAreWholeTilesPerPatch) {
    for (const Vertex& v : teapot().vertices) {
        ASSERT_GE(v.uv.x, 0.0f);
        ASSERT_GE(v.uv.y, 0.0f);
        ASSERT_LE(v.uv.x, 2.0f + 1e-6f);
        ASSERT_LE(v.uv.y, 2.0f + 1e-6f);
    }
}

}  // namespace
}  // namespace leanfade::scene
