// Mesh types, bounds and tangent generation on small hand-made meshes.
#include <cstddef>
#include <type_traits>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/mesh.hpp"
#include "mesh_checks.hpp"

namespace leanfade::scene {
namespace {

// A unit quad in the xy-plane facing +z, two CCW triangles, with the given corner UVs
// (corners (0,0), (1,0), (1,1), (0,1)).
Mesh quad(glm::vec2 uv00, glm::vec2 uv10, glm::vec2 uv11, glm::vec2 uv01) {
    Mesh m;
    m.name = "quad";
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    m.vertices = {{{0, 0, 0}, n, uv00, {}, uv00, 0.0f},
                  {{1, 0, 0}, n, uv10, {}, uv10, 0.0f},
                  {{1, 1, 0}, n, uv11, {}, uv11, 0.0f},
                  {{0, 1, 0}, n, uv01, {}, uv01, 0.0f}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

TEST(MeshTypes, VertexIsFourteenTightlyPackedFloats) {
    EXPECT_TRUE(std::is_standard_layout_v<Vertex>);
    EXPECT_EQ(sizeof(Vertex), 60u);
    EXPECT_EQ(offsetof(Vertex, position), 0u);
    EXPECT_EQ(offsetof(Vertex, normal), 12u);
    EXPECT_EQ(offsetof(Vertex, uv), 24u);
    EXPECT_EQ(offsetof(Vertex, tangent), 32u);
    EXPECT_EQ(offsetof(Vertex, uv1), 48u);
}

TEST(MeshTypes, BoundsCentreAndRadius) {
    const Bounds b{{-1.0f, 0.0f, 2.0f}, {3.0f, 2.0f, 6.0f}};
    EXPECT_EQ(b.center(), glm::vec3(1.0f, 1.0f, 4.0f));
    EXPECT_FLOAT_EQ(b.radius(), 3.0f);  // half of |(4, 2, 4)| = 6
}

TEST(MeshTypes, ComputeBoundsCoversAllVertices) {
    Mesh m = quad({0, 0}, {1, 0}, {1, 1}, {0, 1});
    m.vertices[2].position = glm::vec3(5.0f, -3.0f, 2.0f);
    compute_bounds(m);
    EXPECT_EQ(m.bounds.min, glm::vec3(0.0f, -3.0f, 0.0f));
    EXPECT_EQ(m.bounds.max, glm::vec3(5.0f, 1.0f, 2.0f));
    EXPECT_EQ(m.triangle_count(), 2u);

    Mesh empty;
    empty.bounds = Bounds{glm::vec3(1.0f), glm::vec3(2.0f)};
    compute_bounds(empty);
    EXPECT_EQ(empty.bounds.min, glm::vec3(0.0f));
    EXPECT_EQ(empty.bounds.max, glm::vec3(0.0f));
}

TEST(GenerateTangents, AxisAlignedUvsGiveRightHandedFrame) {
    Mesh m = quad({0, 0}, {1, 0}, {1, 1}, {0, 1});
    generate_tangents(m);
    for (const Vertex& v : m.vertices) {
        EXPECT_NEAR(v.tangent.x, 1.0f, 1e-6f);
        EXPECT_NEAR(v.tangent.y, 0.0f, 1e-6f);
        EXPECT_NEAR(v.tangent.z, 0.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(GenerateTangents, MirroredUvsGiveLeftHandedFrame) {
    // u decreases along +x: T = -x, and cross(N, T) = -y opposes dP/dv = +y, so w = -1.
    Mesh m = quad({1, 0}, {0, 0}, {0, 1}, {1, 1});
    generate_tangents(m);
    for (const Vertex& v : m.vertices) {
        EXPECT_NEAR(v.tangent.x, -1.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, -1.0f);
        const glm::vec3 b = v.tangent.w * glm::cross(v.normal, glm::vec3(v.tangent));
        EXPECT_NEAR(b.y, 1.0f, 1e-6f);
    }
    const auto stats = test::uv_frame_stats(m);
    EXPECT_EQ(stats.tangent_opposed, 0u);
    EXPECT_EQ(stats.bitangent_opposed, 0u);
}

TEST(GenerateTangents, RotatedUvsFollowDerivatives) {
    // u along +y, v along -x: T = +y, bitangent = cross(z, y) = -x, right-handed.
    Mesh m = quad({0, 1}, {0, 0}, {1, 0}, {1, 1});
    generate_tangents(m);
    for (const Vertex& v : m.vertices) {
        EXPECT_NEAR(v.tangent.y, 1.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(GenerateTangents, TangentIsOrthogonalisedAgainstTiltedNormal) {
    Mesh m = quad({0, 0}, {1, 0}, {1, 1}, {0, 1});
    const glm::vec3 tilted = glm::normalize(glm::vec3(0.5f, 0.2f, 1.0f));
    for (Vertex& v : m.vertices) {
        v.normal = tilted;
    }
    generate_tangents(m);
    const auto f = test::frame_stats(m);
    EXPECT_LT(f.max_tangent_error, 1e-6f);
    EXPECT_LT(f.max_tangent_dot_normal, 1e-6f);
    EXPECT_GT(m.vertices[0].tangent.x, 0.8f);
}

TEST(GenerateTangents, DegenerateUvsFallBackToAnyOrthonormalTangent) {
    for (const glm::vec2 same : {glm::vec2(0.5f, 0.5f), glm::vec2(0.0f)}) {
        Mesh m = quad(same, same, same, same);
        generate_tangents(m);
        const auto f = test::frame_stats(m);
        EXPECT_EQ(f.non_finite, 0u);
        EXPECT_LT(f.max_tangent_error, 1e-6f);
        EXPECT_LT(f.max_tangent_dot_normal, 1e-6f);
        EXPECT_EQ(f.bad_handedness, 0u);
    }
    // Collinear UVs (u constant, zero UV area): no derivatives at all, still a valid frame.
    Mesh m = quad({0, 0}, {0, 0}, {0, 1}, {0, 1});
    generate_tangents(m);
    const auto f = test::frame_stats(m);
    EXPECT_EQ(f.non_finite, 0u);
    EXPECT_LT(f.max_tangent_dot_normal, 1e-6f);
}

TEST(GenerateTangents, UnreferencedVertexStillGetsAFrame) {
    Mesh m = quad({0, 0}, {1, 0}, {1, 1}, {0, 1});
    m.vertices.push_back({{2, 2, 2}, glm::normalize(glm::vec3(1, 1, 1)), {0, 0}, {}, {0, 0}, 0.0f});
    generate_tangents(m);
    const auto f = test::frame_stats(m);
    EXPECT_EQ(f.non_finite, 0u);
    EXPECT_LT(f.max_tangent_error, 1e-6f);
    EXPECT_LT(f.max_tangent_dot_normal, 1e-6f);
}

TEST(GenerateTangents, RejectsBadIndices) {
    Mesh m = quad({0, 0}, {1, 0}, {1, 1}, {0, 1});
    m.indices.back() = 7;
    EXPECT_THROW(generate_tangents(m), leanfade::Error);
    m.indices = {0, 1};
    EXPECT_THROW(generate_tangents(m), leanfade::Error);
}

}  // namespace
}  // namespace leanfade::scene
