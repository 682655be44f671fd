#pragma once
// Shared fixture and helpers of the OpenGL tests. One context per test suite, created with
// record_errors: every GL error (debug output of type error, glGetError) fails the test that
// caused it (checked in TearDown).
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/renderer.hpp"
#include "leanfade/scene/detail/mesh.hpp"

namespace leanfade::test {

class GlTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite();
    static void TearDownTestSuite();
    void TearDown() override;

    static gl::Context& context() { return *context_; }

  private:
    static std::unique_ptr<gl::Context> context_;
};

// A 2 x 2 world-unit square in the object's xy plane at z = 0, facing +z, uv = (x + 1, y + 1) / 2
// scaled by `uv_scale`, tangent +x, bitangent +y (w = +1). Its bounding radius is sqrt(2).
scene::Mesh make_test_quad(float uv_scale = 1.0f);

// A LEAN map of `size` x `size` texels all equal, from the given slope mean B and covariance
// (Sxx, Syy, Sxy) (so M = B B^T + covariance), normal = normalize(B.x, B.y, 1) scaled by
// `normal_length`, packed to `storage` with every MIP level (all identical).
PackedLeanMap make_constant_lean_map(glm::vec2 mean, glm::vec3 covariance, float normal_length,
                                     Storage storage, int size = 4);

// The built-in "bumps" set of `size` texels (seed 1), baked at `strength` and packed to 16 bits,
// with its plateau layer (add_plateau_layer).
// The spike of its plateau layer: `spike` (bake's default: auto).
PackedLeanMap make_bumps_map(int size, float strength = 1.0f, SpikeFit spike = SpikeFit::Auto);

// Sum of all channels of all pixels.
double image_sum(const Image& image);
// sum |a - b| / sum |b| over all channels (a and b of the same size).
double relative_l1(const Image& a, const Image& b);
// mean |a - b| over all channels.
double mean_abs_difference(const Image& a, const Image& b);

// A fresh, empty folder under the build's test-tmp, named after the test.
std::filesystem::path scratch_dir(const std::string& name);

}  // namespace leanfade::test
