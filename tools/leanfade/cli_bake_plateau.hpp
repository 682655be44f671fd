#pragma once
// `leanfade bake MAP -o OUT --plateau-out FILE.ktx2`: the plateau layer of two-lobe LEAN
// (docs/math.md §10, leanfade/core/detail/plateau.hpp) as a 2D half-float KTX2 texture with its MIP
// chain, computed from the LEAN map as stored (the values `leanfade render` computes when it loads
// the map), for engines and WebGL2 pages that load it as a texture (docs/ktx2.md).
#include <cstddef>
#include <string>

#include <CLI/CLI.hpp>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/output_plan.hpp"

namespace leanfade::cli {

void add_plateau_bake_option(CLI::App& app, std::string& plateau_out);

// Checks the flag before any file is touched (one input, a .ktx2 name) and adds the output to
// `plan`. Throws leanfade::Error("--plateau-out", cause).
void plan_plateau_output(const std::string& plateau_out, std::size_t job_count,
                         io::OutputPlan& plan);

// Stages FILE.ktx2 in `outputs`: the plateau MIPs of `map` as it stores them, baked with the
// rule's setting `epsilon` (> 0); all 0 for a map whose bake found nothing flat and stored no
// layer. Returns the number of levels.
int write_plateau_output(const std::string& plateau_out, const PackedLeanMap& map, float epsilon,
                         int threads, const io::WriteOptions& write_options,
                         io::OutputTransaction& outputs);

}  // namespace leanfade::cli
