// Roughness MIPs of `leanfade bake` (cli_bake_roughness.hpp).
#include "cli_bake_roughness.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "cli_text.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/io/detail/node_tool.hpp"
#include "leanfade/version.hpp"
#include "leanfade/core/detail/input_text.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

bool is_dds(const std::string& path) {
    return fs::path(path).extension() == ".dds";
}

std::string stem_of(const std::string& path) {
    fs::path p(path);
    if (p.extension() == ".ktx2" || p.extension() == ".dds") p.replace_extension();
    return p.string();
}

// The LEANFADEcontent key of a texture (docs/ktx2.md): what it holds, and the version of that.
io::TextureKeyValues content(const std::string& what) {
    return {{io::kKeyTextureContent, what + " v1"}};
}

std::string writer_string() {
    return std::string(LEANFADE_GENERATOR);
}

// Whether a metallic-roughness texture holds anything but R = 1 (no occlusion) and B = 0 (not
// metallic), which a BC4 roughness texture cannot keep.
bool carries_occlusion_or_metallic(const Image& map) {
    for (std::size_t t = 0; t < map.pixels.size(); t += std::size_t(map.channels))
        if (map.pixels[t] < 1.0f || map.pixels[t + 2] > 0.0f) return true;
    return false;
}

}  // namespace

Image read_roughness_map(const std::string& path, const io::ReadOptions& read_options) {
    io::ReadOptions keep_alpha = read_options;
    keep_alpha.drop_alpha = false;
    return io::read_image(path, keep_alpha);
}

void add_roughness_bake_options(CLI::App& app, RoughnessBakeArgs& args) {
    app.add_option("--roughness-out", args.roughness_out,
                   "Also write roughness MIPs for engines: FILE.ktx2 (glTF metallic-roughness, "
                   "G = sqrt(alpha) with alpha^2 = alpha0^2 + Sxx + Syy per level) and "
                   "FILE.normal.ktx2 (the normal of the mean slope per level), or FILE.dds and "
                   "FILE.normal.dds; without -o or --out-dir, no LEAN map is written "
                   "(docs/roughness.md)");
    app.add_flag("--roughness-levels", args.png_levels,
                 "Also write every level of the roughness, normal and anisotropy MIPs as a PNG "
                 "in FILE.levels/");
    app.add_option("--anisotropy-out", args.anisotropy_out,
                   "Also write the KHR_materials_anisotropy texture (direction and strength from "
                   "the slope covariance) with every level, as FILE.ktx2 or FILE.dds");
    add_named_option(app, "--compress", args.compression, io::block_compression_names(),
                   "Block-compress the engine textures (--roughness-out, --anisotropy-out): bc "
                   "(desktop: BC4 roughness, BC5 normal, BC1 anisotropy), astc (mobile: ASTC "
                   "4x4) or basis (Basis Universal UASTC, KTX2 only, transcoded by any GPU: the "
                   "web, glTF's KHR_texture_basisu; needs Node.js), every level from its own "
                   "filtered level; LEAN maps stay uncompressed (docs/compression.md)",
                   io::to_string(args.compression))
        ->each([&args](const std::string&) { args.compression_given = true; });
    app.add_option("--roughness", args.roughness,
                   "Base perceptual roughness r0 in [0, 1] of the roughness MIPs (alpha0 = r0^2)")
        ->check(CLI::Range(0.0f, 1.0f))
        ->each([&args](const std::string&) { args.roughness_given = true; });
    app.add_option("--roughness-map", args.roughness_map,
                   "Base roughness per texel: a grey map of r0, or a glTF metallic-roughness "
                   "texture (r0 in G; its R, B, A are kept in the output); of another size than the "
                   "input, resampled to it (bilinear, repeating)");
}

std::string normal_output_path(const std::string& roughness_out) {
    return stem_of(roughness_out) + (is_dds(roughness_out) ? ".normal.dds" : ".normal.ktx2");
}

std::string levels_folder_path(const RoughnessBakeArgs& args) {
    return stem_of(!args.roughness_out.empty() ? args.roughness_out : args.anisotropy_out) +
           ".levels";
}

void plan_roughness_outputs(const RoughnessBakeArgs& args, std::size_t job_count,
                            float bake_roughness, io::OutputPlan& plan) {
    if (!args.requested()) {
        if (args.roughness_given || !args.roughness_map.empty() || args.png_levels ||
            args.compression_given)
            throw Error(args.roughness_given     ? "--roughness"
                        : args.png_levels        ? "--roughness-levels"
                        : args.compression_given ? "--compress"
                                                 : "--roughness-map",
                        "applies to --roughness-out and --anisotropy-out");
        return;
    }
    const char* flag = !args.roughness_out.empty() ? "--roughness-out" : "--anisotropy-out";
    if (job_count != 1) throw Error::setting(flag, "needs exactly one input");
    if (bake_roughness > 0.0f)
        throw Error::setting(
            flag,
            "needs a LEAN map without a baked roughness (drop --bake-roughness; the "
            "base roughness is --roughness or --roughness-map)");
    if (args.roughness_given && !args.roughness_map.empty())
        throw Error("--roughness", "give --roughness or --roughness-map, not both");
    for (const std::string* out : {&args.roughness_out, &args.anisotropy_out}) {
        if (out->empty()) continue;
        if (fs::path(*out).extension() != ".ktx2" && !is_dds(*out))
            throw Error(*out, "roughness and anisotropy outputs are .ktx2 or .dds files");
        if (is_dds(*out) && args.compression == io::BlockCompression::Astc)
            throw Error(*out, "DDS has no ASTC formats: write .ktx2 with --compress astc");
        if (is_dds(*out) && args.compression == io::BlockCompression::Basis)
            throw Error(*out, "DDS has no Basis Universal form: write .ktx2 with --compress basis");
    }
    if (!args.roughness_map.empty()) plan.add_input(args.roughness_map);
    if (!args.roughness_out.empty()) {
        plan.add_output(args.roughness_out, "--roughness-out");
        plan.add_output(normal_output_path(args.roughness_out), "--roughness-out");
    }
    if (!args.anisotropy_out.empty()) plan.add_output(args.anisotropy_out, "--anisotropy-out");
    if (args.png_levels) plan.add_output_folder(levels_folder_path(args));
}

RoughnessExport::RoughnessExport(const RoughnessBakeArgs& args, int width, int height,
                                 const BakeOptions& options, const io::ReadOptions& read_options,
                                 const io::WriteOptions& write_options,
                                 io::OutputTransaction& outputs)
    : args_(args),
      write_options_(write_options),
      outputs_(outputs),
      threads_(options.threads),
      in_memory_(args.png_levels || args.compression != io::BlockCompression::None ||
                 is_dds(args.roughness_out) || is_dds(args.anisotropy_out)) {
    RoughnessOptions roughness;
    roughness.base_roughness = args.roughness;
    roughness.roughness_map_name = args.roughness_map;  // errors name the map's file
    roughness.threads = options.threads;
    const Image* metallic_roughness = nullptr;
    if (!args.roughness_map.empty()) {
        // Of another size than the input: resampled to it, as a glTF's metallic-roughness
        // texture is (docs/roughness.md).
        map_image_ = resampled(read_roughness_map(args.roughness_map, read_options), width, height);
        base_ = base_roughness_channel(map_image_);
        roughness.roughness_map = &base_;
        if (map_image_.channels >= 3) metallic_roughness = &map_image_;
        if (metallic_roughness != nullptr && args.compression == io::BlockCompression::Bc &&
            !args.roughness_out.empty() && carries_occlusion_or_metallic(map_image_))
            std::fprintf(stderr,
                         "leanfade bake: warning: %s: its R (occlusion) and B (metallic) are not "
                         "kept by --compress bc (BC4 holds roughness only); --compress astc keeps "
                         "them\n",
                         terminal_text(args.roughness_map).c_str());
    }
    // Uncompressed KTX2 files without PNG levels: the bake writes their texels in place.
    RoughnessTextureTargets targets;
    const auto mapped = [&](const std::string& path, const char* what,
                            std::unique_ptr<io::Ktx2Rgba8Writer>& file,
                            std::vector<std::uint8_t*>& levels) {
        if (path.empty() || in_memory_) return;
        file = std::make_unique<io::Ktx2Rgba8Writer>(outputs.stage(path), width, height,
                                                     writer_string(), content(what),
                                                     write_options);
        levels = file->levels();
    };
    if (!args.roughness_out.empty()) {
        mapped(args.roughness_out, "roughness", roughness_file_, targets.metallic_roughness);
        mapped(normal_output_path(args.roughness_out), "normal", normal_file_, targets.normal);
    }
    mapped(args.anisotropy_out, "anisotropy", anisotropy_file_, targets.anisotropy);
    builder_ = std::make_unique<RoughnessTextureBuilder>(
        width, height, roughness, metallic_roughness,
        RoughnessTextureSet{!args.roughness_out.empty(), !args.anisotropy_out.empty()}, targets);
}

void RoughnessExport::bake_alone(const std::variant<Image, UnormImage>& input, BakeSource source,
                                 const BakeOptions& options, const std::string& source_name) {
    MomentsOnlySink moments(sink());
    bake(BakeInput(input, source, source_name), BakeSettings{options}, moments);
}

void RoughnessExport::write_texture(const std::string& path, const std::vector<Rgba8Image>& levels,
                                    io::EngineTexture texture, const std::string& content_name) {
    const std::string staged = outputs_.stage(path);
    if (args_.compression == io::BlockCompression::None) {
        if (is_dds(path))
            io::write_dds_rgba8(staged, levels, write_options_);
        else
            io::write_ktx2_rgba8(staged, levels, writer_string(), write_options_,
                                 content(content_name));
        return;
    }
    if (args_.compression == io::BlockCompression::Basis) {
        // Encoded with the others by write(); the normal's and anisotropy's A is 1 (RGB).
        uastc_.push_back({staged, &levels, false});
        return;
    }
    const io::BlockFormat& format = io::block_format(args_.compression, texture);
    const std::vector<io::CompressedLevel> compressed =
        io::compress_levels(levels, args_.compression, texture, threads_, path);
    if (is_dds(path))
        io::write_dds_compressed(staged, compressed, format, write_options_);
    else
        io::write_ktx2_compressed(staged, compressed, format, writer_string(), write_options_,
                                  content(content_name));
}

int RoughnessExport::write() {
    const int levels = mip_level_count(builder_->width(), builder_->height());
    for (auto* file : {&roughness_file_, &normal_file_, &anisotropy_file_})
        if (*file) (*file)->commit();
    if (!in_memory_) return levels;
    // In memory: each file and with --roughness-levels the PNG of every level (the uncompressed
    // texels).
    const RoughnessTexturesRgba8 textures = builder_->take();
    const std::string folder =
        args_.png_levels ? outputs_.stage_folder(levels_folder_path(args_)) : std::string();
    const auto write_all = [&](const std::string& path, const std::vector<Rgba8Image>& images,
                               io::EngineTexture texture) {
        const std::string name = io::to_string(texture);
        write_texture(path, images, texture, name);
        if (!args_.png_levels) return;
        for (std::size_t l = 0; l < images.size(); ++l)
            io::write_png_rgba8(
                (fs::path(folder) / (name + "_mip" + std::to_string(l) + ".png")).string(),
                images[l], write_options_);
    };
    if (!args_.roughness_out.empty()) {
        write_all(args_.roughness_out, textures.metallic_roughness, io::EngineTexture::Roughness);
        write_all(normal_output_path(args_.roughness_out), textures.normal,
                  io::EngineTexture::Normal);
    }
    if (!args_.anisotropy_out.empty())
        write_all(args_.anisotropy_out, textures.anisotropy, io::EngineTexture::Anisotropy);
    if (!uastc_.empty())
        io::write_ktx2_uastc(uastc_, writer_string(), io::find_node_script(io::kUastcEncoderScript));
    return levels;
}

}  // namespace leanfade::cli
