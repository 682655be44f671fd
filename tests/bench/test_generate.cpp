// GPU LEAN map generation (shaders/generate_lean.comp + glGenerateMipmap) against the CPU baker:
// the top level equals the CPU's packed top level within quantisation, for height and normal
// inputs, every storage and the options; the coarsest level's moments equal the CPU's mean.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <utility>

#include "gl_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/gl/detail/generate.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

// Largest difference of decoded channel values allowed at the top level: one quantisation step
// (the GPU rounds its own float result, which differs from the CPU's in the last bits: the CPU
// takes the Sobel sums in double) plus a little.
float top_level_tolerance(Storage storage) {
    switch (storage) {
        case Storage::Unorm8:
            return 1.01f / 255.0f;
        case Storage::Unorm16:
            return 1.01f / 65535.0f;
        case Storage::Float16:
            return 1.0e-3f;  // one half-float step near 1 is 2^-11
        case Storage::Float32:
            return 2.0e-6f;
    }
    return 0.0f;
}

// An 8-bit-like normal map (3 channels, encoded 0.5 n + 0.5) of the bumps set.
Image bumps_normal_map(int width, int height, float strength) {
    const Image h = make_builtin_height("bumps", std::max(width, height), 3);
    BakeOptions options;
    options.strength = strength;
    const Image slopes = slopes_from_height(h, options).slopes;
    Image normals(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const glm::vec3 n =
                glm::normalize(glm::vec3(slopes.at(x, y, 0), slopes.at(x, y, 1), 1.0f));
            for (int c = 0; c < 3; ++c) normals.at(x, y, c) = 0.5f * n[c] + 0.5f;
        }
    return normals;
}

Image bumps_height(int width, int height) {
    const Image square = make_builtin_height("bumps", std::max(width, height), 2);
    Image out(width, height, 1);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) out.at(x, y) = square.at(x, y);
    return out;
}

struct Case {
    const char* name;
    gl::GenerateInput input;
    int width, height;
    Storage storage;
    Wrap wrap = Wrap::Repeat;
    NormalConvention convention = NormalConvention::OpenGL;
    float bake_shininess = 0.0f;
};

class Generate : public GlTest {
  protected:
    // The GPU's plateau layer of a generated size x size map against the CPU's rule.
    void check_generated_plateau(int size);
    // CPU bake and GPU generation of the same input; returns {cpu packed, gpu packed}.
    std::pair<PackedLeanMap, PackedLeanMap> both(const Case& c, LeanMap* cpu_float = nullptr) {
        const float strength = 1.5f;
        const Image image = c.input == gl::GenerateInput::Height
                                ? bumps_height(c.width, c.height)
                                : bumps_normal_map(c.width, c.height, strength);
        BakeOptions options;
        options.strength = strength;
        options.wrap = c.wrap;
        options.convention = c.convention;
        options.bake_roughness_shininess = c.bake_shininess;
        const BakeResult cpu = bake_lean_map(
            image, c.input == gl::GenerateInput::Height ? BakeSource::Height : BakeSource::Normal,
            options, c.name);
        if (cpu_float != nullptr) *cpu_float = cpu.map;

        gl::LeanGenerator generator(context());
        generator.set_source(image, c.input);
        gl::GenerateOptions g;
        g.strength = strength;
        g.wrap = c.wrap;
        g.convention = c.convention;
        g.bake_roughness_shininess = c.bake_shininess;
        // The sc the CPU packs with: the map's (UNORM), or the signed encoding's (floats).
        PackedLeanMap packed = pack_lean_map(cpu.map, c.storage, "cpu");
        g.scale = packed.scale;
        g.storage = c.storage;
        generator.generate(g);
        EXPECT_EQ(generator.levels(), mip_level_count(c.width, c.height));
        return {std::move(packed), generator.read_back()};
    }
};

TEST_F(Generate, TopLevelMatchesTheCpuBakerWithinQuantisation) {
    const Case cases[] = {
        {"height 16", gl::GenerateInput::Height, 64, 48, Storage::Unorm16},
        {"height 8", gl::GenerateInput::Height, 32, 32, Storage::Unorm8},
        {"height 16f", gl::GenerateInput::Height, 32, 40, Storage::Float16},
        {"height 32f", gl::GenerateInput::Height, 33, 17, Storage::Float32},
        {"height clamp, baked roughness", gl::GenerateInput::Height, 48, 32, Storage::Unorm16,
         Wrap::Clamp, NormalConvention::OpenGL, 64.0f},
        {"normal 16", gl::GenerateInput::Normal, 64, 64, Storage::Unorm16},
        {"normal directx 16f", gl::GenerateInput::Normal, 40, 24, Storage::Float16, Wrap::Repeat,
         NormalConvention::DirectX},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const auto [cpu, gpu] = both(c);
        ASSERT_EQ(gpu.levels.size(), cpu.levels.size());
        EXPECT_EQ(gpu.storage, c.storage);
        EXPECT_FLOAT_EQ(gpu.scale, cpu.scale);
        EXPECT_EQ(gpu.roughness_baked, cpu.roughness_baked);
        ASSERT_EQ(gpu.levels[0].width, c.width);
        ASSERT_EQ(gpu.levels[0].height, c.height);
        const float tolerance = top_level_tolerance(c.storage);
        float worst = 0.0f;
        int off = 0;
        for (int slice = 0; slice < 2; ++slice)
            for (int y = 0; y < c.height; ++y)
                for (int x = 0; x < c.width; ++x) {
                    const glm::vec4 a = fetch_packed_texel(cpu, 0, slice, x, y);
                    const glm::vec4 b = fetch_packed_texel(gpu, 0, slice, x, y);
                    for (int ch = 0; ch < 4; ++ch) {
                        const float d = std::abs(a[ch] - b[ch]);
                        worst = std::max(worst, d);
                        if (d > tolerance && off++ < 5)
                            ADD_FAILURE()
                                << "slice " << slice << " texel (" << x << ", " << y << ") channel "
                                << ch << ": cpu " << a[ch] << ", gpu " << b[ch];
                    }
                }
        EXPECT_EQ(off, 0) << off << " values off; largest difference " << worst;
        std::printf("%s: largest top-level difference %.3g (tolerance %.3g)\n", c.name,
                    double(worst), double(tolerance));
    }
}

// glGenerateMipmap averages the packed values (affine packing, docs/math.md §3): the 1x1 level's
// moments are the mean of the top level's, as the CPU's float chain has them.
TEST_F(Generate, CoarsestLevelMomentsMatchTheCpuMean) {
    for (Storage storage : {Storage::Unorm16, Storage::Float16}) {
        SCOPED_TRACE(to_string(storage));
        LeanMap cpu_float;
        const auto gpu =
            both({"height", gl::GenerateInput::Height, 128, 128, storage}, &cpu_float).second;
        const int last = int(gpu.levels.size()) - 1;
        ASSERT_EQ(gpu.levels[std::size_t(last)].width, 1);
        const auto m = shading::lf_unpack(fetch_packed_texel(gpu, last, 0, 0, 0),
                                          fetch_packed_texel(gpu, last, 1, 0, 0), gpu.scale,
                                          lean_offset(gpu.encoding));
        const MomentLevel& cpu = cpu_float.levels.back();
        const float sc = cpu_float.scale, sc2 = sc * sc;
        const float tolerance = storage == Storage::Unorm16 ? 2e-4f : 2e-3f;
        EXPECT_NEAR(m.mean.x, cpu.mean[0].x, tolerance * sc);
        EXPECT_NEAR(m.mean.y, cpu.mean[0].y, tolerance * sc);
        EXPECT_NEAR(m.second.x, cpu.second[0].x, tolerance * sc2);
        EXPECT_NEAR(m.second.y, cpu.second[0].y, tolerance * sc2);
        EXPECT_NEAR(m.second.z, cpu.second[0].z, tolerance * sc2);
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.normal[i], cpu.normal[0][i], 4.0f * tolerance);
        // The bumps have a clear roughness: the covariance at 1x1 is far above the tolerance.
        EXPECT_GT(cpu.second[0].x - cpu.mean[0].x * cpu.mean[0].x, 0.02f * sc2);
    }
}

TEST_F(Generate, RegeneratingWithNewOptionsReusesTheTexture) {
    gl::LeanGenerator generator(context());
    generator.set_source(bumps_height(32, 32), gl::GenerateInput::Height);
    gl::GenerateOptions options;
    options.scale = 2.0f;
    generator.generate(options);
    const GLuint first = generator.texture();
    options.scale = 3.0f;
    generator.generate(options);
    EXPECT_EQ(generator.texture(), first);
    EXPECT_FLOAT_EQ(generator.read_back().scale, 3.0f);
    options.storage = Storage::Float16;
    generator.generate(options);
    EXPECT_EQ(generator.read_back().storage, Storage::Float16);
}

TEST_F(Generate, BadInputsAreErrors) {
    gl::LeanGenerator generator(context());
    gl::GenerateOptions options;
    EXPECT_THROW(generator.write_top_level(options), Error);  // no source
    EXPECT_THROW(generator.set_source(Image(), gl::GenerateInput::Height), Error);
    EXPECT_THROW(generator.set_source(Image(8, 8, 1), gl::GenerateInput::Normal), Error);
    generator.set_source(Image(8, 8, 1), gl::GenerateInput::Height);
    options.scale = 0.0f;
    EXPECT_THROW(generator.write_top_level(options), Error);
    options.scale = 1.0f;
    options.strength = std::nanf("");
    EXPECT_THROW(generator.write_top_level(options), Error);
}

// The plateau layer of two-lobe LEAN (shaders/generate_plateau.comp) follows the CPU's rule
// (plateau_texels) on the generated map's own stored slopes, and its MIP levels are the layer's
// box filter (glGenerateMipmap), within half-float rounding.
void Generate::check_generated_plateau(int size) {
    gl::LeanGenerator generator(context());
    generator.set_source(bumps_height(size, size), gl::GenerateInput::Height);
    gl::GenerateOptions options;
    options.strength = 4.0f;
    options.scale = 3.0f;
    generator.generate(options);
    ASSERT_NE(generator.plateau_texture(), 0u);
    const std::vector<Image> gpu = generator.read_back_plateau();
    const Image slopes = packed_top_slopes(generator.read_back());
    const std::vector<Image> cpu = plateau_mips(
        slopes, plateau_rule(slopes.width, slopes.height, options.plateau_epsilon));
    EXPECT_EQ(plateau_rule(size, size, options.plateau_epsilon).radius_x, size / 256 > 1 ? 4 : 1);
    ASSERT_EQ(gpu.size(), cpu.size());
    // Level 0: the same texels on a plateau (a texel whose neighbour's slope lies within a float
    // rounding of epsilon may go either way), their values within half-float rounding.
    std::size_t differing = 0, on_plateau = 0;
    for (std::size_t t = 0; t < cpu[0].texel_count(); ++t) {
        const float* a = &gpu[0].pixels[4 * t];
        const float* b = &cpu[0].pixels[4 * t];
        if (b[0] > 0.0f) ++on_plateau;
        if (a[0] != b[0]) {
            ++differing;
            continue;
        }
        for (int c = 1; c < 4; ++c) EXPECT_NEAR(a[c], b[c], 1e-3f * (std::abs(b[c]) + 1e-3f));
    }
    EXPECT_GT(on_plateau, cpu[0].texel_count() / 5) << "the bumps set is mostly flat ground";
    EXPECT_LE(differing, cpu[0].texel_count() / 200);
    // Below: the box filter of the level above (power-of-two sizes), half floats.
    for (std::size_t l = 1; l < gpu.size(); ++l)
        for (std::size_t i = 0; i < gpu[l].pixels.size(); ++i)
            EXPECT_NEAR(gpu[l].pixels[i], cpu[l].pixels[i],
                        2e-3f * (std::abs(cpu[l].pixels[i]) + 0.01f) +
                            float(differing) / float(cpu[l].texel_count()) * 4.0f)
                << "level " << l << " value " << i;
}

TEST_F(Generate, PlateauLayerFollowsTheCpuRuleOnTheGeneratedMap) {
    // 64^2: the four neighbours; 1024^2: also the texels 4 apart (PlateauRule's radius).
    for (const int size : {64, 1024}) {
        SCOPED_TRACE("size " + std::to_string(size));
        check_generated_plateau(size);
    }
    gl::LeanGenerator generator(context());
    generator.set_source(bumps_height(64, 64), gl::GenerateInput::Height);
    gl::GenerateOptions options;
    options.strength = 4.0f;
    options.scale = 3.0f;
    // Without the layer: no texture.
    options.plateau_epsilon = 0.0f;
    generator.generate(options);
    EXPECT_EQ(generator.plateau_texture(), 0u);
    EXPECT_TRUE(generator.read_back_plateau().empty());
    options.plateau_epsilon = -1.0f;
    EXPECT_THROW(generator.generate(options), Error);
}

// glslangValidator's exit status and output for one shader file (paths are the test's own).
std::pair<int, std::string> run_validator(const std::string& validator, const fs::path& file) {
    const std::string command = "'" + validator + "' '" + file.string() + "' 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) return {-1, "popen failed"};
    std::string output;
    char buffer[1024];
    for (std::size_t n = 0; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        output.append(buffer, n);
    return {::pclose(pipe), output};
}

// The compute shader's variants pass the reference compiler (tests/gl does the same for the
// vertex and fragment variants).
TEST(GenerateShader, EveryVariantPassesGlslangValidator) {
    const std::string validator = LEANFADE_GLSLANG_VALIDATOR;
    ASSERT_FALSE(validator.empty() || validator.find("NOTFOUND") != std::string::npos)
        << "glslangValidator was not found at configure time (Debian: apt install glslang-tools)";
    const fs::path dir = scratch_dir("glslang_generate");
    const gl::ShaderSources sources = gl::ShaderSources::embedded();
    for (const char* input : {"SOURCE_HEIGHT", "SOURCE_NORMAL"})
        for (const char* format : {"rgba8", "rgba16", "rgba16f", "rgba32f"}) {
            const gl::ResolvedSource resolved = sources.resolve(
                "generate_lean.comp", {input, std::string("SLICE_FORMAT ") + format});
            const fs::path file = dir / (std::string(input) + "_" + format + ".comp");
            std::ofstream(file) << resolved.text;
            const auto [status, output] = run_validator(validator, file);
            EXPECT_EQ(status, 0) << input << " " << format << ":\n" << output;
        }
    const fs::path plateau = dir / "generate_plateau.comp";
    std::ofstream(plateau) << sources.resolve("generate_plateau.comp", {}).text;
    const auto [status, output] = run_validator(validator, plateau);
    EXPECT_EQ(status, 0) << "generate_plateau.comp:\n" << output;
}

}  // namespace
}  // namespace leanfade::test
