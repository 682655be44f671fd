#pragma once
// `leanfade render --layers ... --mixings height,textures,approx`: the LEAN paper's layer figures
// (Figs. 9 and 10): the same layered material drawn with each mixing method side by side, a
// column per method (and technique), a row per distance, and the relative RMSE and energy of
// every column against the first method's, printed and written as CSV and JSON.
#include <string>
#include <vector>

#include "cli_render_scene.hpp"
#include "leanfade/gl/detail/figure.hpp"

namespace leanfade::cli {

struct MixingFigureArgs {
    std::vector<LayerMixing> mixings;  // the methods compared, the first is the reference
    std::string table;    // CSV file of the metrics (a .json beside it), or empty
    std::string output;   // the picture
};

// --mixings: names of kLayerMixings, comma-separated.
void add_mixings_option(CLI::App& app, MixingFigureArgs& args);
// Renders and writes the figure; returns the exit code. Throws leanfade::Error naming the flag.
int run_mixing_figure(const MixingFigureArgs& args, const RenderSourceFlags& input,
                      gl::FigureRequest request, const GlFlags& gl_flags,
                      const std::vector<std::string>& inputs);

}  // namespace leanfade::cli
