// Sphere, torus, plane and terrain.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "mesh_checks.hpp"

namespace leanfade::scene {
namespace {

constexpr double kPi = std::numbers::pi;

// Papers' counts (docs/math.md §8).
constexpr double kPaperSphere = 1984.0;
constexpr double kPaperTorus = 5824.0;
constexpr double kPaperTerrain = 122564.0;

void expect_valid_frames(const Mesh& m, float uv_tangent_cos, float uv_bitangent_cos) {
    ASSERT_TRUE(test::indices_valid(m));
    const auto f = test::frame_stats(m);
    EXPECT_EQ(f.non_finite, 0u);
    EXPECT_LT(f.max_normal_error, 1e-5f);
    EXPECT_LT(f.max_tangent_error, 1e-5f);
    EXPECT_LT(f.max_tangent_dot_normal, 1e-5f);
    EXPECT_EQ(f.bad_handedness, 0u);
    EXPECT_EQ(f.left_handed, 0u) << "built-in objects are right-handed";
    const auto u = test::uv_frame_stats(m);
    EXPECT_EQ(u.corners, 3 * m.triangle_count()) << "no triangle has degenerate UVs";
    EXPECT_EQ(u.tangent_opposed, 0u);
    EXPECT_EQ(u.bitangent_opposed, 0u);
    EXPECT_GT(u.min_cos_tangent, uv_tangent_cos);
    EXPECT_GT(u.min_cos_bitangent_orthogonal, uv_bitangent_cos);
    const auto w = test::winding_stats(m);
    EXPECT_EQ(w.degenerate, 0u);
    EXPECT_EQ(w.disagreeing, 0u);
}

void expect_closed(const Mesh& m) {
    const auto e = test::edge_stats(m);
    EXPECT_EQ(e.boundary, 0u);
    EXPECT_EQ(e.same_direction, 0u);
    EXPECT_EQ(e.non_manifold, 0u);
    EXPECT_EQ(e.degenerate_triangles, 0u);
    EXPECT_EQ(e.paired, e.edges);
    EXPECT_EQ(2 * e.edges, 3 * m.triangle_count());
}

void expect_uv_range(const Mesh& m, glm::vec2 lo, glm::vec2 hi) {
    glm::vec2 mn(1e30f), mx(-1e30f);
    for (const Vertex& v : m.vertices) {
        mn = glm::min(mn, v.uv);
        mx = glm::max(mx, v.uv);
    }
    EXPECT_NEAR(mn.x, lo.x, 1e-5f);
    EXPECT_NEAR(mn.y, lo.y, 1e-5f);
    EXPECT_NEAR(mx.x, hi.x, 1e-4f);
    EXPECT_NEAR(mx.y, hi.y, 1e-4f);
}

void expect_bounds(const Mesh& m, glm::vec3 lo, glm::vec3 hi, float tolerance) {
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(m.bounds.min[k], lo[k], tolerance) << "axis " << k;
        EXPECT_NEAR(m.bounds.max[k], hi[k], tolerance) << "axis " << k;
    }
    // The stored bounds are exactly the vertex extremes.
    Mesh copy = m;
    compute_bounds(copy);
    EXPECT_EQ(copy.bounds.min, m.bounds.min);
    EXPECT_EQ(copy.bounds.max, m.bounds.max);
}

TEST(Sphere, CountsMatchThePaper) {
    const Mesh m = make_sphere();
    EXPECT_EQ(m.name, "sphere");
    EXPECT_EQ(m.triangle_count(), 1984u);
    EXPECT_NEAR(double(m.triangle_count()), kPaperSphere, 0.1 * kPaperSphere);
    EXPECT_EQ(m.vertices.size(), 33u * 31u + 2u * 32u);  // rings with seam copies + pole copies
    EXPECT_EQ(make_sphere(8, 5).triangle_count(), 2u * 8u * 4u);
}

TEST(Sphere, ClosedOutwardAndUnit) {
    const Mesh m = make_sphere();
    expect_closed(m);
    expect_valid_frames(m, 0.98f, 0.999f);
    const double volume = test::signed_volume(m);
    EXPECT_GT(volume, 0.0);
    EXPECT_NEAR(volume, 4.0 / 3.0 * kPi, 0.02 * 4.0 / 3.0 * kPi);
    for (const Vertex& v : m.vertices) {
        EXPECT_NEAR(glm::length(v.position), 1.0f, 1e-6f);
        EXPECT_GT(glm::dot(v.normal, glm::normalize(v.position)), 0.99999f);
    }
    expect_bounds(m, glm::vec3(-1.0f), glm::vec3(1.0f), 1e-6f);
    EXPECT_NEAR(glm::length(m.bounds.center()), 0.0f, 1e-6f);
    expect_uv_range(m, {0, 0}, {16, 8});
}

TEST(Sphere, VIncreasesTowardTheNorthPoleAndUTowardPlusXAtTheFront) {
    const Mesh m = make_sphere();
    for (const Vertex& v : m.vertices) {
        const float latitude = float(kPi / 2 - std::acos(std::clamp(v.position.y, -1.0f, 1.0f)));
        EXPECT_NEAR(v.uv.y, 8.0f * (0.5f + latitude / float(kPi)), 1e-3f);
        const glm::vec3 b = v.tangent.w * glm::cross(v.normal, glm::vec3(v.tangent));
        if (std::abs(v.position.y) < 0.9f) {
            EXPECT_GT(b.y, 0.0f);
        }
        if (v.position.z > 0.99f) {
            EXPECT_GT(v.tangent.x, 0.99f);
        }
    }
}

TEST(Sphere, RejectsBadArguments) {
    EXPECT_THROW(make_sphere(2, 32), leanfade::Error);
    EXPECT_THROW(make_sphere(32, 1), leanfade::Error);
}

TEST(Torus, CountsMatchThePaper) {
    const Mesh m = make_torus();
    EXPECT_EQ(m.name, "torus");
    EXPECT_EQ(m.triangle_count(), 5824u);
    EXPECT_NEAR(double(m.triangle_count()), kPaperTorus, 0.1 * kPaperTorus);
    EXPECT_EQ(m.vertices.size(), 92u * 33u);
    EXPECT_EQ(make_torus(5, 3).triangle_count(), 30u);
}

TEST(Torus, ClosedOutwardAndUnit) {
    const Mesh m = make_torus();
    expect_closed(m);
    expect_valid_frames(m, 0.99f, 0.999f);
    const double volume = test::signed_volume(m);
    EXPECT_NEAR(volume, 2.0 * kPi * kPi * 0.75 * 0.25 * 0.25, 0.02 * volume);
    for (const Vertex& v : m.vertices) {
        const glm::vec3 centre = 0.75f * glm::normalize(glm::vec3(v.position.x, 0, v.position.z));
        EXPECT_NEAR(glm::length(v.position - centre), 0.25f, 1e-5f);
        EXPECT_GT(glm::dot(v.normal, glm::normalize(v.position - centre)), 0.9999f);
    }
    expect_bounds(m, {-1.0f, -0.25f, -1.0f}, {1.0f, 0.25f, 1.0f}, 1e-3f);
    expect_uv_range(m, {0, 0}, {12, 4});
}

TEST(Torus, RejectsBadArguments) {
    EXPECT_THROW(make_torus(2, 8), leanfade::Error);
    EXPECT_THROW(make_torus(8, 2), leanfade::Error);
}

TEST(Plane, FlatFacingUpWithRightHandedFrame) {
    const Mesh m = make_plane(4.0f, 3);
    EXPECT_EQ(m.name, "plane");
    EXPECT_EQ(m.triangle_count(), 18u);
    EXPECT_EQ(m.vertices.size(), 16u);
    expect_valid_frames(m, 0.9999f, 0.9999f);
    for (const Vertex& v : m.vertices) {
        EXPECT_EQ(v.position.y, 0.0f);
        EXPECT_EQ(v.normal, glm::vec3(0.0f, 1.0f, 0.0f));
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
        // u along +x, v along -z, one tile per kTileLength.
        EXPECT_NEAR(v.uv.x, (v.position.x + 2.0f) / kTileLength, 1e-4f);
        EXPECT_NEAR(v.uv.y, (2.0f - v.position.z) / kTileLength, 1e-4f);
    }
    expect_bounds(m, {-2.0f, 0.0f, -2.0f}, {2.0f, 0.0f, 2.0f}, 1e-6f);
    const auto e = test::edge_stats(m);
    EXPECT_EQ(e.boundary, 12u);
    EXPECT_EQ(e.same_direction, 0u);
    EXPECT_EQ(make_plane().triangle_count(), 2u * 64u * 64u);
}

TEST(Plane, RejectsBadArguments) {
    EXPECT_THROW(make_plane(0.0f, 4), leanfade::Error);
    EXPECT_THROW(make_plane(-1.0f, 4), leanfade::Error);
    EXPECT_THROW(make_plane(std::nanf(""), 4), leanfade::Error);
    EXPECT_THROW(make_plane(1.0f, 0), leanfade::Error);
}

TEST(Terrain, CountsMatchThePaper) {
    const Mesh m = make_terrain(1);
    EXPECT_EQ(m.name, "terrain");
    EXPECT_EQ(m.triangle_count(), 2u * 247u * 247u);
    EXPECT_NEAR(double(m.triangle_count()), kPaperTerrain, 0.1 * kPaperTerrain);
    EXPECT_EQ(m.vertices.size(), 248u * 248u);
}

TEST(Terrain, HeightfieldFramesAndBounds) {
    const Mesh m = make_terrain(1);
    expect_valid_frames(m, 0.85f, 0.95f);
    for (const Vertex& v : m.vertices) {
        ASSERT_GT(v.normal.y, 0.0f);
    }
    EXPECT_NEAR(m.bounds.min.x, -10.0f, 1e-4f);
    EXPECT_NEAR(m.bounds.max.x, 10.0f, 1e-4f);
    EXPECT_NEAR(m.bounds.min.z, -10.0f, 1e-4f);
    EXPECT_NEAR(m.bounds.max.z, 10.0f, 1e-4f);
    EXPECT_NEAR(m.bounds.min.y + m.bounds.max.y, 0.0f, 1e-4f) << "centred on the origin";
    EXPECT_GT(m.bounds.max.y - m.bounds.min.y, 1.0f) << "hills, not a plane";
    EXPECT_LT(m.bounds.max.y - m.bounds.min.y, 8.0f);
    expect_uv_range(m, {0, 0}, {50, 50});
    // Above the ground: seen from above, everything is front-facing.
    const auto e = test::edge_stats(m);
    EXPECT_EQ(e.boundary, 4u * 247u);
    EXPECT_EQ(e.same_direction, 0u);
    EXPECT_EQ(e.non_manifold, 0u);
}

TEST(Terrain, DeterministicFromTheSeed) {
    const Mesh a = make_terrain(7);
    const Mesh b = make_terrain(7);
    const Mesh c = make_terrain(8);
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    EXPECT_EQ(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vertex)),
              0);
    EXPECT_EQ(a.indices, b.indices);
    ASSERT_EQ(a.vertices.size(), c.vertices.size());
    std::size_t different = 0;
    for (std::size_t k = 0; k < a.vertices.size(); ++k) {
        different += a.vertices[k].position.y != c.vertices[k].position.y ? 1 : 0;
    }
    EXPECT_GT(different, a.vertices.size() / 2);
}

}  // namespace
}  // namespace leanfade::scene
