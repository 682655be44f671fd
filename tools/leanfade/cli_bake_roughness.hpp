#pragma once
// `leanfade bake --roughness-out FILE [--roughness R | --roughness-map MAP] [--anisotropy-out
// FILE]`: roughness MIPs for engines from the LEAN moments of the baked input (docs/roughness.md,
// docs/math.md §9, leanfade/core/roughness.hpp). cmd_bake.cpp adds the flags, plans the outputs
// and runs a RoughnessExport with the bake once the input is read.
#include <memory>
#include <string>
#include <variant>

#include <CLI/CLI.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/basis_universal.hpp"
#include "leanfade/io/detail/block_compression.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/io/detail/output_plan.hpp"

namespace leanfade::cli {

struct RoughnessBakeArgs {
    std::string roughness_out;   // FILE.ktx2: the metallic-roughness MIP chain
    std::string anisotropy_out;  // FILE.ktx2: the KHR_materials_anisotropy MIP chain
    float roughness = 0.0f;      // base perceptual roughness r0 where no map is given
    bool roughness_given = false;
    std::string roughness_map;   // a grey roughness map or a glTF metallic-roughness texture
    bool png_levels = false;     // --roughness-levels: every level as a PNG in FILE.levels/
    // --compress: the outputs block-compressed (BC4/BC5/BC1 or ASTC 4x4; docs/compression.md).
    io::BlockCompression compression = io::BlockCompression::None;
    bool compression_given = false;

    bool requested() const { return !roughness_out.empty() || !anisotropy_out.empty(); }
};

// A base roughness map as read (alpha kept: a glTF metallic-roughness texture keeps its 4
// channels), under the size limit of `read_options`; leanfade::base_roughness_channel takes r
// from it. Throws io::read_image's errors.
Image read_roughness_map(const std::string& path, const io::ReadOptions& read_options);

void add_roughness_bake_options(CLI::App& app, RoughnessBakeArgs& args);

// Checks the flags before any file is touched (they need exactly one input and a LEAN map without
// baked roughness) and adds every output to `plan` and the map to its inputs. Throws
// leanfade::Error(flag, cause).
void plan_roughness_outputs(const RoughnessBakeArgs& args, std::size_t job_count,
                            float bake_roughness, io::OutputPlan& plan);

// The files of the outputs: for --roughness-out R.ktx2, R.ktx2 and R.normal.ktx2 (R.dds:
// R.normal.dds); for --anisotropy-out A.ktx2, A.ktx2; with --roughness-levels, the folder R.levels/ of PNGs per
// level (roughness_mipN.png, normal_mipN.png, anisotropy_mipN.png).
std::string normal_output_path(const std::string& roughness_out);
std::string levels_folder_path(const RoughnessBakeArgs& args);

// The engine textures of one bake (--roughness-out, --anisotropy-out), made inside the fused bake
// from its float moments (RoughnessTextureBuilder): given to the LEAN bake as its moment sink, or
// baked alone when no LEAN map is asked for.
class RoughnessExport {
  public:
    // Reads the roughness map (--roughness-map) and sizes the textures for an input of
    // width x height texels: the KTX2 files are staged in `outputs` and mapped, so that the bake
    // writes their texels in place (with --roughness-levels the levels are kept in memory for
    // the PNGs too). Throws leanfade::Error naming the map or the file for their errors.
    RoughnessExport(const RoughnessBakeArgs& args, int width, int height, const BakeOptions& options,
                    const io::ReadOptions& read_options, const io::WriteOptions& write_options,
                    io::OutputTransaction& outputs);
    RoughnessExport(const RoughnessExport&) = delete;
    RoughnessExport& operator=(const RoughnessExport&) = delete;

    // What the LEAN bake hands its moments to (bake_packed_to's `moments`).
    MomentRunSink sink() { return builder_->sink(); }
    // Only the engine textures: the fused bake of `input` with nothing packed (bake_moments).
    void bake_alone(const std::variant<Image, UnormImage>& input, BakeSource source,
                    const BakeOptions& options, const std::string& source_name);
    // Completes every output staged in the transaction (published by the caller, with the LEAN
    // map if any). Returns the number of levels written.
    int write();

  private:
    const RoughnessBakeArgs& args_;
    const io::WriteOptions& write_options_;
    io::OutputTransaction& outputs_;
    Image map_image_, base_;
    // Writes one texture's levels to `path` in the form asked for (KTX2 or DDS, compressed or
    // not).
    void write_texture(const std::string& path, const std::vector<Rgba8Image>& levels,
                       io::EngineTexture texture, const std::string& content_name);
    // --compress basis: the textures to encode, all in one run of the encoder (write()).
    std::vector<io::UastcTexture> uastc_;
    int threads_ = 0;
    bool in_memory_ = false;  // the textures are kept in memory (not written in place)
    // The mapped KTX2 files (none with --roughness-levels, --compress or DDS): roughness, normal,
    // anisotropy.
    std::unique_ptr<io::Ktx2Rgba8Writer> roughness_file_, normal_file_, anisotropy_file_;
    std::unique_ptr<RoughnessTextureBuilder> builder_;
};

}  // namespace leanfade::cli
