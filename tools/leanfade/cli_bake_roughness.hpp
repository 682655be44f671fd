#pragma once
// `leanfade bake --roughness-out FILE [--roughness R | --roughness-map MAP] [--anisotropy-out
// FILE]`: roughness MIPs for engines from the LEAN moments of the baked input (docs/roughness.md,
// docs/math.md §9, leanfade/core/roughness.hpp). cmd_bake.cpp adds the flags, plans the outputs
// and calls write_roughness_outputs once the input is read.
#include <string>
#include <variant>

#include <CLI/CLI.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/output_plan.hpp"

namespace leanfade::cli {

struct RoughnessBakeArgs {
    std::string roughness_out;   // FILE.ktx2: the metallic-roughness MIP chain
    std::string anisotropy_out;  // FILE.ktx2: the KHR_materials_anisotropy MIP chain
    float roughness = 0.0f;      // base perceptual roughness r0 where no map is given
    bool roughness_given = false;
    std::string roughness_map;   // a grey roughness map or a glTF metallic-roughness texture
    bool png_levels = false;     // --roughness-levels: every level as a PNG in FILE.levels/

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

// The files of the outputs: for --roughness-out R.ktx2, R.ktx2 and R.normal.ktx2; for
// --anisotropy-out A.ktx2, A.ktx2; with --roughness-levels, the folder R.levels/ of PNGs per
// level (roughness_mipN.png, normal_mipN.png, anisotropy_mipN.png).
std::string normal_output_path(const std::string& roughness_out);
std::string levels_folder_path(const RoughnessBakeArgs& args);

// Bakes the input's float LEAN map, computes the roughness MIPs and stages every output in
// `outputs` (published by the caller with the LEAN map). Returns the number of levels written.
int write_roughness_outputs(const RoughnessBakeArgs& args,
                            const std::variant<Image, UnormImage>& input, BakeSource source,
                            const BakeOptions& options, const io::ReadOptions& read_options,
                            const io::WriteOptions& write_options, io::OutputTransaction& outputs);

}  // namespace leanfade::cli
