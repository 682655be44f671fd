// The plateau layer output of `leanfade bake` (cli_bake_plateau.hpp).
#include "cli_bake_plateau.hpp"

#include <filesystem>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {

void add_plateau_bake_option(CLI::App& app, std::string& plateau_out) {
    app.add_option("--plateau-out", plateau_out,
                   "Also write the plateau layer of two-lobe LEAN (f, f Bs, f |Bs|^2 per texel, "
                   "every MIP level) as a 2D half-float FILE.ktx2, decoded from the LEAN map's "
                   "plateau layer (docs/ktx2.md)");
}

void plan_plateau_output(const std::string& plateau_out, std::size_t job_count,
                         io::OutputPlan& plan) {
    if (plateau_out.empty()) return;
    if (job_count != 1) throw Error("--plateau-out", "needs exactly one input");
    if (std::filesystem::path(plateau_out).extension() != ".ktx2")
        throw Error(plateau_out, "the plateau layer is a .ktx2 file");
    plan.add_output(plateau_out, "--plateau-out");
}

int write_plateau_output(const std::string& plateau_out, const PackedLeanMap& map, float epsilon,
                         int threads, const io::WriteOptions& write_options,
                         io::OutputTransaction& outputs) {
    if (!(epsilon > 0.0f))
        throw Error("--plateau-out", "the LEAN map has no plateau layer (--plateau-epsilon 0)");
    // The layer as the LEAN map stores it, decoded to (f, f Bs, f |Bs|^2); a map in which the
    // bake found nothing flat stores none, and its layer is 0 at every texel.
    std::vector<Image> levels;
    if (map.has_plateau()) {
        levels = unpack_plateau_layer(map, threads);
    } else {
        for (const PackedLevel& level : map.levels)
            levels.emplace_back(level.width, level.height, 4, 0.0f);
    }
    const io::TextureKeyValues keys{{io::kKeyTextureContent, "plateau v1"},
                                    {io::kPlateauEpsilonKey, shortest_text(epsilon)}};
    io::write_ktx2_rgba16f(outputs.stage(plateau_out), levels,
                           std::string(LEANFADE_GENERATOR), write_options, keys);
    return int(levels.size());
}

}  // namespace leanfade::cli
