// leanfade_compression_error: the error block compression adds to the engine textures of real
// maps (docs/compression.md, docs/results.md "Compressed engine textures"). For each map: its
// roughness MIPs at base roughness 0.3 (bake --roughness-out --anisotropy-out), every level
// compressed with --compress bc and astc and decoded, and per texture the largest RMS over the
// levels (roughness: G codes; normal: x, y codes and the mean angle; anisotropy: strength x the
// doubled axis angle, codes of strength), and the whole chain's compression time. Writes
// OUT/compression_error.{csv,json,md}.
//
// With --levels-out DIR, also every map's roughness chain, uncompressed and decoded from each
// compression, as grey PNG series DIR/STEM.COMPRESSION_L.png (perceptual r), the layout of the
// rendering commands' --roughness-mips, to measure what compression does to a render's energy.
// --roughness R sets the base roughness (default 0.3).
//
//   leanfade_compression_error --out DIR [--levels-out DIR] [--roughness R]
//                              (--normal MAP | --height MAP)...
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/block_compression.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/png_io.hpp"

using namespace leanfade;
namespace fs = std::filesystem;

namespace {

struct TextureError {
    double rms_codes = 0.0;     // largest over the levels
    double mean_degrees = 0.0;  // normals: largest over the levels
    double seconds = 0.0;       // compressing the chain, 2 threads
};

glm::vec3 decode_normal(const std::uint8_t* t) {
    return glm::normalize(glm::vec3(t[0], t[1], t[2]) / 255.0f * 2.0f - 1.0f);
}

// RMS and mean angle of one level (as tests/io/test_block_compression.cpp measures them).
void level_error(const Rgba8Image& want, const Rgba8Image& got, io::EngineTexture texture,
                 double& rms, double& degrees) {
    double sum = 0.0, angles = 0.0;
    std::size_t count = 0;
    const std::size_t texels = std::size_t(want.width) * want.height;
    for (std::size_t t = 0; t < texels; ++t) {
        const std::uint8_t* w = &want.texels[4 * t];
        const std::uint8_t* g = &got.texels[4 * t];
        if (texture == io::EngineTexture::Anisotropy) {
            const auto axis = [](const std::uint8_t* x) {
                const double a = 2.0 * std::atan2(2.0 * x[1] / 255.0 - 1.0, 2.0 * x[0] / 255.0 - 1.0);
                return std::pair{x[2] * std::cos(a), x[2] * std::sin(a)};
            };
            const auto [wx, wy] = axis(w);
            const auto [gx, gy] = axis(g);
            sum += (wx - gx) * (wx - gx) + (wy - gy) * (wy - gy);
            ++count;
            continue;
        }
        for (int c = texture == io::EngineTexture::Roughness ? 1 : 0; c < 2; ++c) {
            const double d = double(w[c]) - double(g[c]);
            sum += d * d;
            ++count;
        }
        if (texture == io::EngineTexture::Normal) {
            const double cosine =
                std::clamp(double(glm::dot(decode_normal(w), decode_normal(g))), -1.0, 1.0);
            angles += std::acos(cosine) * 180.0 / 3.14159265358979;
        }
    }
    rms = std::sqrt(sum / double(count));
    degrees = angles / double(texels);
}

TextureError measure(const std::vector<Rgba8Image>& levels, io::BlockCompression compression,
                     io::EngineTexture texture) {
    TextureError e;
    const auto start = std::chrono::steady_clock::now();
    const auto blocks = io::compress_levels(levels, compression, texture, 2);
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto decoded = io::decompress_levels(blocks, compression, texture);
    for (std::size_t l = 0; l < levels.size(); ++l) {
        double rms = 0.0, degrees = 0.0;
        level_error(levels[l], decoded[l], texture, rms, degrees);
        e.rms_codes = std::max(e.rms_codes, rms);
        e.mean_degrees = std::max(e.mean_degrees, degrees);
    }
    return e;
}

}  // namespace

int main(int argc, char** argv) {
    std::string out = "out/bench/compression", levels_out;
    float base_roughness = 0.3f;
    std::vector<std::pair<std::string, BakeSource>> maps;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i];
        if (flag == "--out") out = argv[i + 1];
        else if (flag == "--levels-out") levels_out = argv[i + 1];
        else if (flag == "--roughness") base_roughness = std::stof(argv[i + 1]);
        else if (flag == "--normal") maps.emplace_back(argv[i + 1], BakeSource::Normal);
        else if (flag == "--height") maps.emplace_back(argv[i + 1], BakeSource::Height);
        else {
            std::fprintf(stderr, "leanfade_compression_error: unknown flag %s\n", flag.c_str());
            return 2;
        }
    }
    if (maps.empty()) {
        std::fprintf(stderr, "usage: leanfade_compression_error --out DIR (--normal MAP | --height MAP)...\n");
        return 2;
    }
    fs::create_directories(out);
    std::ofstream csv(fs::path(out) / "compression_error.csv");
    std::ofstream md(fs::path(out) / "compression_error.md");
    std::ofstream json(fs::path(out) / "compression_error.json");
    csv << "map,size,compression,texture,rms_codes,mean_degrees,seconds\n";
    md << "| map | size | compression | roughness RMS | normal RMS, angle | anisotropy RMS | seconds |\n"
          "|---|---|---|---|---|---|---|\n";
    json << "[\n";
    bool first = true;
    try {
        for (const auto& [path, source] : maps) {
            const Image input = io::read_image(path);
            BakeOptions options;
            if (source == BakeSource::Height) options.strength = 8.0f;
            const LeanMap map = bake_lean_map(input, source, options).map;
            RoughnessOptions roughness;
            roughness.base_roughness = base_roughness;
            const RoughnessTexturesRgba8 textures = roughness_textures_rgba8(map, roughness, nullptr);
            if (!levels_out.empty()) {
                fs::create_directories(levels_out);
                const std::string stem = fs::path(path).stem().string();
                for (const io::BlockCompression c :
                     {io::BlockCompression::None, io::BlockCompression::Bc, io::BlockCompression::Astc}) {
                    const std::vector<Rgba8Image> levels =
                        c == io::BlockCompression::None
                            ? textures.metallic_roughness
                            : io::decompress_levels(
                                  io::compress_levels(textures.metallic_roughness, c,
                                                      io::EngineTexture::Roughness, 2),
                                  c, io::EngineTexture::Roughness);
                    for (std::size_t l = 0; l < levels.size(); ++l) {
                        Image grey(levels[l].width, levels[l].height, 1);
                        for (std::size_t t = 0; t < grey.pixels.size(); ++t)
                            grey.pixels[t] = float(levels[l].texels[4 * t + 1]) / 255.0f;
                        io::write_png((fs::path(levels_out) / (stem + "." + io::to_string(c) + "_" +
                                                               std::to_string(l) + ".png"))
                                          .string(),
                                      grey, 8);
                    }
                }
            }
            const std::string size = std::to_string(input.width) + "x" + std::to_string(input.height);
            const std::string name =
                (fs::path(path).parent_path().filename() / fs::path(path).filename()).string();
            for (const io::BlockCompression c : {io::BlockCompression::Bc, io::BlockCompression::Astc}) {
                const TextureError r = measure(textures.metallic_roughness, c, io::EngineTexture::Roughness);
                const TextureError n = measure(textures.normal, c, io::EngineTexture::Normal);
                const TextureError a = measure(textures.anisotropy, c, io::EngineTexture::Anisotropy);
                const double seconds = r.seconds + n.seconds + a.seconds;
                char line[400];
                std::snprintf(line, sizeof line, "| %s | %s | %s | %.2f | %.2f, %.2f° | %.1f | %.2f |\n",
                              name.c_str(), size.c_str(), io::to_string(c), r.rms_codes, n.rms_codes,
                              n.mean_degrees, a.rms_codes, seconds);
                md << line;
                std::fputs(line, stdout);
                for (const auto& [texture, e] : {std::pair{"roughness", r}, std::pair{"normal", n},
                                                 std::pair{"anisotropy", a}}) {
                    csv << path << "," << size << "," << io::to_string(c) << "," << texture << ","
                        << e.rms_codes << "," << e.mean_degrees << "," << e.seconds << "\n";
                    json << (first ? "" : ",\n") << "  {\"map\": \"" << path << "\", \"size\": \""
                         << size << "\", \"compression\": \"" << io::to_string(c)
                         << "\", \"texture\": \"" << texture << "\", \"rms_codes\": " << e.rms_codes
                         << ", \"mean_degrees\": " << e.mean_degrees << ", \"seconds\": " << e.seconds
                         << "}";
                    first = false;
                }
            }
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "leanfade_compression_error: %s\n", e.what());
        return 1;
    }
    json << "\n]\n";
    return 0;
}
