#include "gl_test_helpers.hpp"

#include "leanfade/test/scratch.hpp"

#include <cmath>

#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"

namespace leanfade::test {

std::unique_ptr<gl::Context> GlTest::context_;

void GlTest::SetUpTestSuite() {
    gl::ContextOptions options;
    options.record_errors = true;
    context_ = std::make_unique<gl::Context>(options);
}

void GlTest::TearDownTestSuite() {
    context_.reset();
}

void GlTest::TearDown() {
    const std::vector<std::string> errors = context_->take_errors();
    std::string all;
    for (const std::string& e : errors) all += e + "\n";
    EXPECT_TRUE(errors.empty()) << "GL errors:\n" << all;
}

scene::Mesh make_test_quad(float uv_scale) {
    scene::Mesh mesh;
    mesh.name = "test quad";
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const glm::vec2& c : corners) {
        scene::Vertex v{};
        v.position = glm::vec3(c, 0.0f);
        v.normal = glm::vec3(0, 0, 1);
        v.uv = (c + 1.0f) * 0.5f * uv_scale;
        v.tangent = glm::vec4(1, 0, 0, 1);
        v.uv1 = v.uv;
        mesh.vertices.push_back(v);
    }
    mesh.indices = {0, 1, 2, 0, 2, 3};
    scene::compute_bounds(mesh);
    return mesh;
}

PackedLeanMap make_constant_lean_map(glm::vec2 mean, glm::vec3 covariance, float normal_length,
                                     Storage storage, int size) {
    LeanMap map;
    int w = size, h = size;
    const glm::vec3 n = glm::normalize(glm::vec3(mean, 1.0f)) * normal_length;
    const glm::vec3 second(mean.x * mean.x + covariance.x, mean.y * mean.y + covariance.y,
                           mean.x * mean.y + covariance.z);
    while (true) {
        MomentLevel level;
        level.width = w;
        level.height = h;
        level.normal.assign(std::size_t(w * h), n);
        level.mean.assign(std::size_t(w * h), mean);
        level.second.assign(std::size_t(w * h), second);
        map.levels.push_back(level);
        if (w == 1 && h == 1) break;
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    // sc: |B| <= sc and M <= sc^2 (docs/math.md §3).
    map.scale = std::max({1e-4f, std::abs(mean.x), std::abs(mean.y), std::sqrt(second.x),
                          std::sqrt(second.y), std::sqrt(std::abs(second.z))});
    return pack_lean_map(map, storage, "leanfade tests");
}

PackedLeanMap make_bumps_map(int size, float strength, SpikeFit spike) {
    BakeOptions options;
    options.strength = strength;
    const BakeResult baked =
        bake_lean_map(make_builtin_height("bumps", size, 1), BakeSource::Height, options, "bumps");
    // With the plateau layer, as `leanfade bake` writes it (bake_packed adds it by default).
    PackedLeanMap packed = pack_lean_map(baked.map, Storage::Unorm16, "leanfade tests");
    add_plateau_layer(packed, kDefaultPlateauEpsilon, 0, 0.0f, spike);
    return packed;
}

double image_sum(const Image& image) {
    double sum = 0.0;
    for (float v : image.pixels) sum += double(v);
    return sum;
}

double relative_l1(const Image& a, const Image& b) {
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        num += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
        den += std::abs(double(b.pixels[i]));
    }
    return den > 0.0 ? num / den : num;
}

double mean_abs_difference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        sum += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    return a.pixels.empty() ? 0.0 : sum / double(a.pixels.size());
}

std::filesystem::path scratch_dir(const std::string& name) {
    return fresh_scratch_folder("gl", name);
}

}  // namespace leanfade::test
