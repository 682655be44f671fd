// Flow maps (leanfade/core/detail/flow_map.hpp) and the layer weights of the shared shading header
// (lf_flow_weights, shaders/lean_shading.glsl): the weights sum to 1, favour the layers moving
// with the flow, and share equally where no layer does.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/flow_map.hpp"
#include "leanfade/core/shading.hpp"

using namespace leanfade;

namespace {

float sum(const glm::vec4& t) {
    return t.x + t.y + t.z + t.w;
}

}  // namespace

TEST(FlowWeights, SumToOneAndFollowTheAgreement) {
    // Four layers moving east, north, west, south (different speeds: only directions count).
    const glm::vec2 east(0.3f, 0.0f), north(0.0f, 2.0f), west(-1.0f, 0.0f), south(0.0f, -0.1f);
    for (int i = 0; i < 360; i += 7) {
        const float angle = glm::radians(float(i));
        const glm::vec2 flow(std::cos(angle), std::sin(angle));
        const glm::vec4 t = shading::lf_flow_weights(2.5f * flow, east, north, west, south, 4);
        EXPECT_NEAR(sum(t), 1.0f, 1e-6f) << i;
        // t_i = max(0, cos(angle to layer i)) / sum over the layers.
        const glm::vec4 agreement(std::max(0.0f, flow.x), std::max(0.0f, flow.y),
                                  std::max(0.0f, -flow.x), std::max(0.0f, -flow.y));
        for (int c = 0; c < 4; ++c) {
            EXPECT_GE(t[c], 0.0f);
            EXPECT_NEAR(t[c], agreement[c] / sum(agreement), 1e-5f) << i << " layer " << c;
        }
    }
    // Along a layer's direction it takes everything.
    const glm::vec4 t =
        shading::lf_flow_weights(glm::vec2(0.0f, -3.0f), east, north, west, south, 4);
    EXPECT_FLOAT_EQ(t.w, 1.0f);
    EXPECT_FLOAT_EQ(t.x + t.y + t.z, 0.0f);
}

TEST(FlowWeights, FavourTheAlignedLayerOfTwo) {
    const glm::vec2 a(1.0f, 0.2f), b(-0.3f, 1.0f), none(0.0f);
    const glm::vec4 t = shading::lf_flow_weights(glm::vec2(1.0f, 0.5f), a, b, none, none, 2);
    EXPECT_NEAR(sum(t), 1.0f, 1e-6f);
    EXPECT_GT(t.x, t.y);
    EXPECT_GT(t.y, 0.0f);
    EXPECT_EQ(t.z, 0.0f);
    EXPECT_EQ(t.w, 0.0f);
}

TEST(FlowWeights, ShareEquallyWhereNoLayerAgrees) {
    const glm::vec2 east(1.0f, 0.0f), north(0.0f, 1.0f), none(0.0f);
    // No flow.
    glm::vec4 t = shading::lf_flow_weights(glm::vec2(0.0f), east, north, none, none, 2);
    EXPECT_FLOAT_EQ(t.x, 0.5f);
    EXPECT_FLOAT_EQ(t.y, 0.5f);
    EXPECT_EQ(t.z + t.w, 0.0f);
    // A flow against both layers.
    t = shading::lf_flow_weights(glm::vec2(-1.0f, -1.0f), east, north, none, none, 2);
    EXPECT_FLOAT_EQ(t.x, 0.5f);
    EXPECT_FLOAT_EQ(t.y, 0.5f);
    // Three layers, one of them still: the still one agrees nowhere but shares the fallback.
    t = shading::lf_flow_weights(glm::vec2(1.0f, 0.0f), east, north, none, none, 3);
    EXPECT_FLOAT_EQ(t.x, 1.0f);
    t = shading::lf_flow_weights(glm::vec2(0.0f), east, north, none, none, 3);
    EXPECT_NEAR(t.x, 1.0f / 3.0f, 1e-6f);
    EXPECT_NEAR(t.z, 1.0f / 3.0f, 1e-6f);
    EXPECT_EQ(t.w, 0.0f);
}

TEST(GyreFlow, RotatesClockwiseWithUnitSpeedOutsideItsCore) {
    const int n = 64;
    const Image flow = make_gyre_flow(n, 0.1f);
    ASSERT_EQ(flow.channels, 2);
    // Right of the centre (row n/2: v just below 0.5) the flow goes down (-v); above it, right.
    const int mid = n / 2;
    EXPECT_NEAR(flow.at(n - 4, mid, 1), -1.0f, 0.05f);
    EXPECT_NEAR(flow.at(n - 4, mid, 0), 0.0f, 0.05f);
    EXPECT_NEAR(flow.at(mid, 3, 0), 1.0f, 0.05f);       // row 3: near the top, v ~ 0.95
    EXPECT_NEAR(flow.at(3, mid, 1), 1.0f, 0.05f);       // left: up
    EXPECT_NEAR(flow.at(mid, n - 4, 0), -1.0f, 0.05f);  // bottom: left
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float du = (x + 0.5f) / n - 0.5f, dv = 0.5f - (y + 0.5f) / n;
            const float r = std::sqrt(du * du + dv * dv);
            const glm::vec2 f(flow.at(x, y, 0), flow.at(x, y, 1));
            EXPECT_NEAR(glm::length(f), std::min(1.0f, r / 0.1f), 1e-5f);
            EXPECT_NEAR(glm::dot(f, glm::vec2(du, dv)), 0.0f, 1e-5f);  // tangent to the circle
        }
    EXPECT_THROW(make_gyre_flow(2), Error);
    EXPECT_THROW(make_gyre_flow(64, 0.0f), Error);
}

TEST(FlowMapImage, DecodesRedGreenAroundAHalf) {
    Image rg(2, 1, 3);
    rg.at(0, 0, 0) = 0.5f;
    rg.at(0, 0, 1) = 0.5f;
    rg.at(1, 0, 0) = 1.0f;
    rg.at(1, 0, 1) = 0.25f;
    const Image flow = flow_from_rg(rg, "flow.png");
    ASSERT_EQ(flow.channels, 2);
    EXPECT_EQ(flow.at(0, 0, 0), 0.0f);
    EXPECT_EQ(flow.at(0, 0, 1), 0.0f);
    EXPECT_EQ(flow.at(1, 0, 0), 1.0f);
    EXPECT_EQ(flow.at(1, 0, 1), -0.5f);
    const Image back = flow_to_rg(flow);
    EXPECT_EQ(back.at(1, 0, 0), 1.0f);
    EXPECT_EQ(back.at(1, 0, 1), 0.25f);
    try {
        flow_from_rg(Image(4, 4, 1), "grey.png");
        ADD_FAILURE() << "a 1-channel flow map was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "grey.png");
    }
    Image bad(1, 1, 2);
    bad.at(0, 0, 1) = std::nanf("");
    EXPECT_THROW(flow_from_rg(bad, "nan.exr"), Error);
}

TEST(FlowMapImage, WeightsPerTexelSumToOne) {
    const Image flow = make_gyre_flow(32);
    const std::vector<glm::vec2> velocities = {{1.0f, 0.0f}, {-0.5f, 0.8f}, {-0.4f, -0.9f}};
    const Image weights = flow_weights(flow, velocities);
    ASSERT_EQ(weights.channels, 4);
    ASSERT_EQ(weights.width, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            float total = 0.0f;
            for (int c = 0; c < 4; ++c) total += weights.at(x, y, c);
            EXPECT_NEAR(total, 1.0f, 1e-5f);
            EXPECT_EQ(weights.at(x, y, 3), 0.0f);
        }
    // Top of the gyre flows toward +u: the first layer (+u) dominates there.
    EXPECT_GT(weights.at(16, 1, 0), 0.9f);
    EXPECT_THROW(flow_weights(flow, std::vector<glm::vec2>{}), Error);
    EXPECT_THROW(flow_weights(flow, std::vector<glm::vec2>(5, glm::vec2(1.0f))), Error);
    EXPECT_THROW(flow_weights(Image(4, 4, 3), velocities), Error);
}
