// MikkTSpace tangents (generate_mikktspace_tangents, leanfade/scene/gltf.hpp): T along +u in
// object space, w = +1 for ordinary and -1 for mirrored uvs, on a quad and a sphere.
#include <cmath>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "leanfade/scene/gltf.hpp"
#include "mesh_checks.hpp"

namespace leanfade::scene {
namespace {

// The unit square in the xy plane facing +z, u = x (or 1 - x when `mirror_u`), v = y.
Mesh quad(bool mirror_u) {
    Mesh mesh;
    mesh.name = "quad";
    const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const glm::vec2& c : corners) {
        Vertex v{};
        v.position = glm::vec3(c, 0.0f);
        v.normal = glm::vec3(0, 0, 1);
        v.uv = glm::vec2(mirror_u ? 1.0f - c.x : c.x, c.y);
        mesh.vertices.push_back(v);
    }
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

TEST(MikkTSpace, QuadTangentFollowsPlusU) {
    Mesh mesh = quad(false);
    generate_mikktspace_tangents(mesh);
    ASSERT_EQ(mesh.vertices.size(), 4u);
    for (const Vertex& v : mesh.vertices) {
        EXPECT_NEAR(glm::distance(glm::vec3(v.tangent), glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, 1.0f);
        // Bitangent w cross(N, T) along +v = +y.
        EXPECT_NEAR(glm::dot(v.tangent.w * glm::cross(v.normal, glm::vec3(v.tangent)),
                             glm::vec3(0, 1, 0)),
                    1.0f, 1e-6f);
    }
}

TEST(MikkTSpace, MirroredUvsGiveMinusOneHandedness) {
    Mesh mesh = quad(true);
    generate_mikktspace_tangents(mesh);
    for (const Vertex& v : mesh.vertices) {
        EXPECT_NEAR(glm::distance(glm::vec3(v.tangent), glm::vec3(-1, 0, 0)), 0.0f, 1e-6f);
        EXPECT_EQ(v.tangent.w, -1.0f);
        EXPECT_NEAR(glm::dot(v.tangent.w * glm::cross(v.normal, glm::vec3(v.tangent)),
                             glm::vec3(0, 1, 0)),
                    1.0f, 1e-6f);
    }
}

// Two quads sharing an edge, the second with its u mirrored: the shared vertices are needed
// with both handednesses and are split, each copy following its own triangles.
TEST(MikkTSpace, VerticesSharedByBothOrientationsAreSplit) {
    Mesh mesh;
    mesh.name = "mirror";
    // x in [0, 2]; u = x on the left quad, u = 2 - x on the right one: the shared edge x = 1
    // has u = 1 on both sides (a mirror seam without duplicated vertices).
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j) {
            Vertex v{};
            v.position = glm::vec3(float(i), float(j), 0.0f);
            v.normal = glm::vec3(0, 0, 1);
            v.uv = glm::vec2(i <= 1 ? float(i) : 2.0f - float(i), float(j));
            mesh.vertices.push_back(v);
        }
    auto at = [](int i, int j) { return std::uint32_t(i * 2 + j); };
    mesh.indices = {at(0, 0), at(1, 0), at(1, 1), at(0, 0), at(1, 1), at(0, 1),
                    at(1, 0), at(2, 0), at(2, 1), at(1, 0), at(2, 1), at(1, 1)};
    generate_mikktspace_tangents(mesh);
    EXPECT_EQ(mesh.vertices.size(), 8u);  // the two seam vertices duplicated
    const test::UvFrameStats uv = test::uv_frame_stats(mesh);
    EXPECT_EQ(uv.corners, 12u);
    EXPECT_GT(uv.min_cos_tangent, 0.9999f);
    EXPECT_GT(uv.min_cos_bitangent, 0.9999f);
    for (std::size_t t = 0; t < 12; ++t) {
        const float expected_w = t < 6 ? 1.0f : -1.0f;
        EXPECT_EQ(mesh.vertices[mesh.indices[t]].tangent.w, expected_w) << t;
    }
}

// Unindexed triangles (each corner its own vertex) are welded by equal attributes: the two
// copies of a shared corner get the same tangent, the angle-weighted mean of both triangles.
TEST(MikkTSpace, EqualVerticesAreWeldedAcrossIndices) {
    Mesh mesh;
    mesh.name = "fold";
    // Two triangles meeting at an edge along y, folded at 90 degrees, with one uv chart.
    const glm::vec3 p[4] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    const glm::vec2 uv[4] = {{0, 0}, {0, 1}, {1, 0}, {-1, 0}};
    const glm::vec3 n = glm::normalize(glm::vec3(1, 0, 1));
    const int tris[2][3] = {{0, 2, 1}, {0, 1, 3}};
    for (const auto& tri : tris)
        for (int c : tri) {
            Vertex v{};
            v.position = p[c];
            v.normal = n;
            v.uv = uv[c];
            mesh.indices.push_back(std::uint32_t(mesh.vertices.size()));
            mesh.vertices.push_back(v);
        }
    // Triangle (0 2 1) has normal -z and triangle (0 1 3) -x: flip them to face the normal.
    std::swap(mesh.indices[1], mesh.indices[2]);
    std::swap(mesh.indices[4], mesh.indices[5]);
    generate_mikktspace_tangents(mesh);
    // Copies of corner 0 (vertices 0 and 3) and corner 1 (vertices 2 and 4) agree.
    EXPECT_EQ(mesh.vertices[0].tangent, mesh.vertices[3].tangent);
    EXPECT_EQ(mesh.vertices[2].tangent, mesh.vertices[4].tangent);
    // Both triangles' dP/du projected onto the plane of n: (1, 0, -1) / sqrt(2) for each.
    const glm::vec3 expected = glm::normalize(glm::vec3(1, 0, -1));
    for (const Vertex& v : mesh.vertices)
        EXPECT_NEAR(glm::distance(glm::vec3(v.tangent), expected), 0.0f, 1e-5f);
}

// On the sphere (smooth, seams duplicated) MikkTSpace agrees with leanfade's own generator,
// and both follow the analytic dP/du: T = (cos phi, 0, -sin phi) for u along the longitude.
TEST(MikkTSpace, SphereTangentsFollowPlusU) {
    const Mesh reference = make_sphere(32, 32);
    Mesh mesh = reference;
    for (Vertex& v : mesh.vertices) v.tangent = glm::vec4(0.0f);
    generate_mikktspace_tangents(mesh);
    ASSERT_EQ(mesh.vertices.size(), reference.vertices.size());  // no split: w = +1 everywhere
    const test::FrameStats frames = test::frame_stats(mesh);
    EXPECT_EQ(frames.non_finite, 0u);
    EXPECT_LT(frames.max_tangent_error, 1e-5f);
    EXPECT_LT(frames.max_tangent_dot_normal, 1e-5f);
    EXPECT_EQ(frames.left_handed, 0u);
    const test::UvFrameStats uv = test::uv_frame_stats(mesh);
    EXPECT_EQ(uv.tangent_opposed, 0u);
    EXPECT_EQ(uv.bitangent_opposed, 0u);
    EXPECT_GT(uv.min_cos_tangent, 0.99f);
    float worst = 1.0f;
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const Vertex& v = mesh.vertices[i];
        if (std::abs(v.position.y) > 0.999f) continue;  // the poles: dP/du vanishes
        // Analytic: P = (sin(phi) r, y, cos(phi) r) with u growing with phi toward +x from +z.
        const glm::vec3 radial = glm::normalize(glm::vec3(v.position.x, 0.0f, v.position.z));
        const glm::vec3 analytic(radial.z, 0.0f, -radial.x);
        const float agreement = glm::dot(glm::vec3(v.tangent), analytic);
        if (v.uv.x == 0.0f || v.uv.x == 16.0f) {
            // Seam copies see the triangles of one side only (their uvs differ from the other
            // copy's, so MikkTSpace does not weld them): the chord of one segment, half a
            // segment (pi / 32, cos = 0.9952) off the analytic tangent at most.
            EXPECT_GT(agreement, 0.995f);
        } else {
            worst = std::min(worst, agreement);
        }
        EXPECT_GT(glm::dot(glm::vec3(v.tangent), glm::vec3(reference.vertices[i].tangent)), 0.999f);
    }
    EXPECT_GT(worst, 0.999f);
}

TEST(MikkTSpace, DegenerateUvsStillGiveAValidFrame) {
    Mesh mesh = quad(false);
    for (Vertex& v : mesh.vertices) v.uv = glm::vec2(0.5f);  // zero uv area everywhere
    generate_mikktspace_tangents(mesh);
    const test::FrameStats frames = test::frame_stats(mesh);
    EXPECT_EQ(frames.non_finite, 0u);
    EXPECT_LT(frames.max_tangent_error, 1e-5f);
    EXPECT_LT(frames.max_tangent_dot_normal, 1e-5f);
    EXPECT_EQ(frames.bad_handedness, 0u);
}

TEST(MikkTSpace, BadIndicesAreErrors) {
    Mesh mesh = quad(false);
    mesh.indices.back() = 7;
    EXPECT_THROW(generate_mikktspace_tangents(mesh), Error);
    mesh.indices.pop_back();
    EXPECT_THROW(generate_mikktspace_tangents(mesh), Error);
}

}  // namespace
}  // namespace leanfade::scene
