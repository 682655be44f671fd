// Golden renders: every technique, in the shader variants the renderer picks (the plain colour
// path, the general path with fog and the eye-distance fade, the specular output), compared with
// images rendered before a change, so that a refactoring of the shading code or of the renderer
// proves that it changes no pixel.
//
// The goldens (tests/gl/golden/*.pfm) were rendered with the GL renderer named in
// tests/gl/golden/renderer.txt. On that renderer the comparison is exact (bit for bit). On
// another renderer (another driver, or llvmpipe on a CPU with other vector units, whose
// instruction selection rounds differently) it allows |a - b| <= 1e-3 |b| + 1e-4 per channel and
// a relative L1 difference below 2e-4: far below what any change to a formula does (percents),
// above the last-bit differences of exp2/log2 implementations.
//
// To re-render the goldens after an intended change of the pictures, run this suite with
// LEANFADE_UPDATE_GOLDEN=1 and commit the new files with the change that explains them.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "gl_test_helpers.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "leanfade/scene/material.hpp"

namespace leanfade::test {
namespace {

const std::filesystem::path kGoldenDir =
    std::filesystem::path(LEANFADE_SOURCE_DIR) / "tests" / "gl" / "golden";

bool updating() {
    const char* value = std::getenv("LEANFADE_UPDATE_GOLDEN");
    return value != nullptr && std::strcmp(value, "1") == 0;
}

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    return s;
}

struct GoldenCase {
    const char* name;  // also the file stem: <technique>_<name>.pfm
    void (*configure)(gl::RenderRequest&);
};

const GoldenCase kCases[] = {
    // Colour, no fog, default fading parameters: the "_plain" (and for fade "_plain_fast")
    // variants.
    {"plain", [](gl::RenderRequest&) {}},
    // Colour with exponential fog, the eye-distance fade and a non-integer power: the general
    // variant with every uniform branch.
    {"general",
     [](gl::RenderRequest& r) {
         r.settings.fog = FogMode::Exp;
         r.settings.fog_density = 0.2f;
         r.settings.fade_distance = FadeDistance::Eye;
         r.settings.fade_exponent = 1.7f;
     }},
    // The specular term alone, at a lower shininess and a finer MIP bias.
    {"specular",
     [](gl::RenderRequest& r) {
         r.output = gl::OutputMode::Specular;
         r.settings.shininess = 96.0f;
         r.settings.mip_bias = -0.5f;
     }},
};

class GoldenRenders : public GlTest {};

TEST_F(GoldenRenders, EveryTechniqueMatchesItsGolden) {
    gl::Renderer renderer(context());
    // One sphere with the bumps map and its plateau layer (two-lobe LEAN, docs/math.md §10; the
    // other techniques do not read it). The layer of the plateaus alone, as the goldens were
    // recorded: a fitted central window changes the layer's texels, not how the renderer reads
    // them (GpuMatchesCpu checks the window's maps).
    scene::Scene scene;
    scene.objects.push_back(scene::Object{scene::make_sphere(24, 24), 0, glm::mat4(1.0f)});
    scene.materials.push_back(scene::Material{});
    scene.lean_maps.push_back(make_bumps_map(64, 1.0f, SpikeFit::Plateaus));
    scene::add_plateau_maps(scene);
    renderer.set_scene(scene);

    const std::filesystem::path renderer_file = kGoldenDir / "renderer.txt";
    if (updating()) {
        std::filesystem::create_directories(kGoldenDir);
        std::ofstream(renderer_file) << context().renderer() << "\n";
    }
    ASSERT_TRUE(std::filesystem::exists(renderer_file)) << renderer_file;
    const bool exact = read_text(renderer_file) == context().renderer();
    std::printf("golden renderer '%s', this renderer '%s': %s comparison\n",
                read_text(renderer_file).c_str(), context().renderer().c_str(),
                exact ? "exact" : "tolerant");

    int compared = 0;
    for (const gl::Technique technique : gl::all_techniques()) {
        for (const GoldenCase& c : kCases) {
            gl::RenderRequest request;
            request.technique = technique;
            request.width = 40;
            request.height = 40;
            request.view = gl::view_at_distance(5.0f);
            request.reference_samples = 3;
            request.background = glm::vec3(0.05f, 0.1f, 0.15f);
            c.configure(request);
            const Image image = renderer.render(request);
            const std::string stem = std::string(gl::to_string(technique)) + "_" + c.name;
            const std::filesystem::path file = kGoldenDir / (stem + ".pfm");
            if (updating()) io::write_pfm(file.string(), image);
            ASSERT_TRUE(std::filesystem::exists(file))
                << "no golden " << file << ": render it with LEANFADE_UPDATE_GOLDEN=1";
            const Image golden = io::read_image(file.string());
            ASSERT_EQ(golden.width, image.width) << stem;
            ASSERT_EQ(golden.height, image.height) << stem;
            ASSERT_EQ(golden.channels, image.channels) << stem;
            int differing = 0;
            for (std::size_t i = 0; i < image.pixels.size(); ++i) {
                const float got = image.pixels[i], want = golden.pixels[i];
                const bool same = exact ? std::memcmp(&got, &want, sizeof(float)) == 0
                                        : std::abs(got - want) <= 1e-3f * std::abs(want) + 1e-4f;
                if (!same && differing++ < 3)
                    ADD_FAILURE() << stem << " value " << i << ": " << got << ", golden " << want;
            }
            EXPECT_EQ(differing, 0) << stem << ": " << differing << " values differ";
            if (!exact) {
                EXPECT_LT(relative_l1(image, golden), 2e-4) << stem;
            }
            EXPECT_GT(image_sum(image), 0.0) << stem << " is black";
            ++compared;
        }
    }
    EXPECT_EQ(compared, int(gl::all_techniques().size() * std::size(kCases)));
}

}  // namespace
}  // namespace leanfade::test
