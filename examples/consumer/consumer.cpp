// A program outside the leanfade tree that uses the installed package: bakes a LEAN map in memory
// from a height map it computes, writes it as KTX2 to memory and to a file, reads both back and
// checks that they hold the same map, and shades one texel on the CPU with the shaders' math.
// Built by examples/consumer/CMakeLists.txt (find_package) and examples/consumer/Makefile
// (pkg-config); run by the test `package.InstallAndConsume` (tests/package).
//
// Usage: consumer OUTPUT_FOLDER [IMAGE]   (writes OUTPUT_FOLDER/consumer.ktx2; with IMAGE, also
// reads and bakes that file, e.g. a DDS, which the package's OpenImageIO module decodes). Exit 0
// when every check holds, 1 with a message naming the first that does not.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <leanfade/leanfade.hpp>

namespace {

int failures = 0;

void check(bool condition, const std::string& what) {
    if (!condition) {
        std::fprintf(stderr, "consumer: FAILED: %s\n", what.c_str());
        ++failures;
    }
}

// Bumps: a product of sines, heights in texel spacings (non-square, non-power-of-two size).
leanfade::Image height_map(int width, int height) {
    leanfade::Image image(width, height, 1);
    const float two_pi = 6.28318530718f;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image.at(x, y) = 2.0f * std::sin(two_pi * 3.0f * float(x) / float(width)) *
                             std::sin(two_pi * 2.0f * float(y) / float(height));
    return image;
}

bool same_levels(const leanfade::PackedLeanMap& a, const leanfade::PackedLeanMap& b) {
    if (a.levels.size() != b.levels.size()) return false;
    for (std::size_t i = 0; i < a.levels.size(); ++i) {
        const leanfade::PackedLevel& la = a.levels[i];
        const leanfade::PackedLevel& lb = b.levels[i];
        if (la.width != lb.width || la.height != lb.height || la.lean1 != lb.lean1 ||
            la.lean2 != lb.lean2)
            return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2 && argc != 3) {
        std::fprintf(stderr, "usage: consumer OUTPUT_FOLDER [IMAGE]\n");
        return 2;
    }
    const std::string file = std::string(argv[1]) + "/consumer.ktx2";
#ifdef CONSUMER_PACKAGE_VERSION
    // The installed header and the package that CMake found are the same version.
    if (std::string(LEANFADE_VERSION_STRING) != CONSUMER_PACKAGE_VERSION) {
        std::fprintf(stderr, "consumer: FAILED: leanfade/version.hpp says %s, the package %s\n",
                     LEANFADE_VERSION_STRING, CONSUMER_PACKAGE_VERSION);
        return 1;
    }
#endif
    static_assert(LEANFADE_VERSION_MAJOR >= 0 && LEANFADE_VERSION_MINOR >= 0 &&
                  LEANFADE_VERSION_PATCH >= 0);
    try {
        // Bake in memory: 16-bit UNORM layers, every MIP level (docs/math.md §3).
        const int width = 96, height = 40;
        leanfade::BakeOptions options;
        options.strength = 1.0f;
        const leanfade::Image heights = height_map(width, height);
        const leanfade::PackedBakeResult baked = leanfade::bake(
            leanfade::BakeInput(heights, leanfade::BakeSource::Height),
            leanfade::BakeSettings{options, {leanfade::Storage::Unorm16}, "leanfade consumer example"});
        const leanfade::PackedLeanMap& map = baked.packed;
        check(map.levels.size() == std::size_t(leanfade::mip_level_count(width, height)),
              "the bake has every MIP level");
        check(map.levels.front().width == width && map.levels.front().height == height,
              "level 0 has the input's size");
        check(std::isfinite(map.scale) && map.scale > 0.0f, "sc is finite and > 0");
        check(baked.summary.max_slope > 0.1f, "the bumps have slopes");

        // KTX2 in memory and in a file: the same bytes, and the same map read back.
        const std::vector<std::uint8_t> bytes = leanfade::io::write_ktx2_to_memory(map);
        leanfade::io::write_ktx2(file, map);
        std::ifstream in(file, std::ios::binary);
        const std::vector<std::uint8_t> file_bytes{std::istreambuf_iterator<char>(in),
                                                   std::istreambuf_iterator<char>()};
        check(file_bytes == bytes, "write_ktx2 and write_ktx2_to_memory give the same bytes");
        const leanfade::PackedLeanMap from_memory =
            leanfade::io::read_ktx2_from_memory(bytes, "memory");
        const leanfade::PackedLeanMap from_file = leanfade::io::read_ktx2(file);
        check(same_levels(from_memory, map) && same_levels(from_file, map),
              "the map read back has the baked texels");
        check(from_memory.scale == map.scale && from_file.scale == map.scale,
              "the map read back has the baked sc");

        // A truncated file is refused with an error naming it.
        std::vector<std::uint8_t> truncated(bytes.begin(), bytes.begin() + 100);
        bool refused = false;
        try {
            leanfade::io::read_ktx2_from_memory(truncated, "truncated.ktx2");
        } catch (const leanfade::Error& e) {
            refused = e.file() == "truncated.ktx2";
        }
        check(refused, "a truncated KTX2 file is refused, naming the file");

        // Shading on the CPU with the shaders' functions: LEAN at the centre texel of level 0.
        namespace sh = leanfade::shading;
        const glm::vec4 lean1 = leanfade::fetch_packed_texel(map, 0, 0, width / 2, height / 3);
        const glm::vec4 lean2 = leanfade::fetch_packed_texel(map, 0, 1, width / 2, height / 3);
        sh::LfParams params{};
        params.light_color = glm::vec3(1.0f);
        params.shininess = 64.0f;
        params.inv_s_shading = 1.0f / 64.0f;
        params.kd = glm::vec3(0.5f);
        params.ks = glm::vec3(1.0f);
        params.fresnel_bias = 1.0f;
        params.pmax = 1.0f;
        params.fade_exponent = 2.0f;
        const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
        const glm::vec3 view(-0.2f, 0.1f, 3.0f);
        const sh::LfShade shade = sh::lf_shade(
            sh::LF_TECHNIQUE_LEAN,
            sh::lf_unpack(lean1, lean2, map.scale, lean_offset(map.encoding)), light, view, params);
        check(std::isfinite(shade.specular.x) && shade.specular.x > 0.0f,
              "LEAN's specular term is finite and > 0");
        check(shade.diffuse.x > 0.0f && shade.diffuse.x <= 0.5f + 1e-6f,
              "the diffuse term is Kd NdotL, in (0, Kd]");

        // A file in a format of the OpenImageIO module (DDS, JPEG, TGA, ...): the package finds
        // the module wherever it is installed (docs/integration.md).
        std::string read_back;
        if (argc == 3) {
            const leanfade::Image image = leanfade::io::read_image(argv[2]);
            const leanfade::PackedBakeResult from_file = leanfade::bake(
                leanfade::BakeInput(image, leanfade::BakeSource::Auto, argv[2]),
                leanfade::BakeSettings{{}, {leanfade::Storage::Unorm16}, "leanfade consumer example"});
            check(from_file.packed.levels.size() ==
                      std::size_t(leanfade::mip_level_count(image.width, image.height)),
                  "the bake of the file has every MIP level");
            read_back = ", " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                        " read from " + argv[2];
        }

        std::printf(
            "consumer: leanfade %s, %dx%d map, %zu levels, sc %.4f, KTX2 %zu bytes, LEAN "
            "specular %.4f%s: %s\n",
            LEANFADE_VERSION_STRING, width, height, map.levels.size(), double(map.scale),
            bytes.size(), double(shade.specular.x), read_back.c_str(),
            failures == 0 ? "ok" : "FAILED");
    } catch (const leanfade::Error& e) {
        std::fprintf(stderr, "consumer: %s\n", e.what());
        return 1;
    }
    return failures == 0 ? 0 : 1;
}
