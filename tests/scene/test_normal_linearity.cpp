// measure_normal_linearity: how far each vertex's normal field is linear (Vertex::
// linear_normal_change, docs/math.md §11).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "leanfade/scene/detail/generators.hpp"
#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::scene {
namespace {

struct Linearity {
    std::size_t bounded = 0;  // vertices with a change > 0
    float median = 0.0f;      // of the bounded ones
};

Linearity linearity_of(const Mesh& mesh) {
    std::vector<float> changes;
    for (const Vertex& v : mesh.vertices)
        if (v.linear_normal_change > 0.0f) changes.push_back(v.linear_normal_change);
    Linearity l;
    l.bounded = changes.size();
    if (!changes.empty()) {
        std::nth_element(changes.begin(), changes.begin() + std::ptrdiff_t(changes.size() / 2),
                         changes.end());
        l.median = changes[changes.size() / 2];
    }
    return l;
}

// A sphere's normal is its position over its radius: linear in the tangent-plane offsets at every
// vertex, however fine or coarse the mesh, so geometric AA trusts its derivatives everywhere.
TEST(NormalLinearity, SphereAndPlaneAreLinearEverywhere) {
    for (const Mesh& mesh : {make_sphere(), make_sphere(128, 64), make_plane()}) {
        EXPECT_EQ(linearity_of(mesh).bounded, 0u) << mesh.name;
    }
}

// The terrain's normals turn over a few cells (its finest octave is about 5 cells long): almost
// every vertex is bounded, by a change of the order of the slope's change over a cell or two.
TEST(NormalLinearity, TerrainIsBoundedNearlyEverywhere) {
    const Mesh terrain = make_terrain(1);
    const Linearity l = linearity_of(terrain);
    EXPECT_GT(double(l.bounded), 0.9 * double(terrain.vertices.size()));
    EXPECT_GT(l.median, 0.02f);
    EXPECT_LT(l.median, 2.0f);
}

// The change is a slope change: the same mesh at another size measures the same.
TEST(NormalLinearity, IndependentOfTheMeshsScale) {
    Mesh terrain = make_terrain(2);
    Mesh scaled = terrain;
    for (Vertex& v : scaled.vertices) v.position *= 37.0f;
    measure_normal_linearity(scaled);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < terrain.vertices.size(); ++i) {
        const float a = terrain.vertices[i].linear_normal_change;
        const float b = scaled.vertices[i].linear_normal_change;
        if (std::abs(a - b) > 1e-4f * std::max(1.0f, a)) ++differ;
    }
    EXPECT_LE(differ, terrain.vertices.size() / 1000);
}

// A torus's normal field bends at the scale of its tube: with enough segments every ring around
// a vertex is close to linear, so (almost) nothing is bounded; a coarse torus is bounded, by a
// change that grows as the mesh gets coarser.
TEST(NormalLinearity, FinerMeshesAreLinearOverMoreRings) {
    const Linearity fine = linearity_of(make_torus(360, 128));
    const Linearity coarse = linearity_of(make_torus(24, 8));
    const Mesh coarse_mesh = make_torus(24, 8);
    EXPECT_LT(fine.bounded, coarse.bounded);
    EXPECT_GT(double(coarse.bounded), 0.5 * double(coarse_mesh.vertices.size()));
}

TEST(NormalLinearity, OutOfRangeIndexIsAnError) {
    Mesh mesh = make_plane(1.0f, 1);
    mesh.indices.back() = 99;
    EXPECT_ANY_THROW(measure_normal_linearity(mesh));
}

}  // namespace
}  // namespace leanfade::scene
