// The layer figures of `leanfade render --mixings` (cli_render_mixings.hpp).
#include "cli_render_mixings.hpp"

#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/eval/metrics.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/output_plan.hpp"

namespace leanfade::cli {
namespace {

// The object's pixels: those that differ from the background in the reference cell or in `a`.
eval::Mask object_pixels(const Image& a, const Image& reference, const glm::vec3& background) {
    eval::Mask mask(a.width, a.height);
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            bool inside = false;
            for (int c = 0; c < 3; ++c)
                inside = inside || a.at(x, y, c) != background[c] ||
                         reference.at(x, y, c) != background[c];
            mask.inside[std::size_t(y) * std::size_t(a.width) + std::size_t(x)] = inside;
        }
    return mask;
}

}  // namespace

void add_mixings_option(CLI::App& app, MixingFigureArgs& args) {
    add_typed_option(
        app, "--mixings", args.mixings,
        [](const std::string& text) {
            std::vector<LayerMixing> mixings;
            for (const std::string& name : split(text, ','))
                mixings.push_back(parse_layer_mixing(name, "--mixings"));
            return mixings;
        },
        "With --layers: a column per mixing method (comma-separated, the first is the "
        "reference of the printed relative RMSE and energy)")
        ->group("Bump layers (docs/math.md §6)");
}

int run_mixing_figure(const MixingFigureArgs& args, const RenderSourceFlags& input,
                      gl::FigureRequest request, const GlFlags& gl_flags,
                      const std::vector<std::string>& inputs) {
    if (input.layers.empty())
        throw Error("--mixings", "compares the mixing methods of bump layers: give --layers");
    const std::vector<LayerMixing>& mixings = args.mixings;
    if (mixings.size() < 2) throw Error("--mixings", "give two methods or more to compare");
    io::OutputPlan plan;
    for (const std::string& path : inputs) plan.add_input(path);
    plan.add_output(args.output, "-o", ".png");
    std::string json_path;
    if (!args.table.empty()) {
        plan.add_output(args.table, "--table");
        json_path = args.table.substr(0, args.table.rfind('.')) + ".json";
        plan.add_output(json_path, "--table");
    }
    plan.check();

    gl::Context context(context_options(gl_flags));
    gl::Renderer renderer(context, shader_sources(gl_flags));
    std::vector<gl::Figure> figures;   // one per mixing
    std::vector<gl::Figure> specular;  // the same cells' specular term: what mixing changes
    for (LayerMixing mixing : mixings) {
        RenderSourceFlags flags = input;
        flags.layers.mixing = mixing;
        renderer.set_scene(load_render_scene(flags, request.settings));
        figures.push_back(gl::render_figure(renderer, request));
        gl::FigureRequest specular_request = request;
        specular_request.output = gl::OutputMode::Specular;
        specular_request.background = glm::vec3(0.0f);
        specular.push_back(gl::render_figure(renderer, specular_request));
    }

    // Columns: mixing outer, technique inner; rows: the distances.
    std::vector<std::string> columns;
    for (LayerMixing mixing : mixings)
        for (gl::Technique technique : request.techniques)
            columns.push_back(request.techniques.size() == 1
                                  ? std::string(to_string(mixing))
                                  : std::string(to_string(mixing)) + " " + to_string(technique));
    const std::size_t per_row = request.techniques.size();
    std::vector<gl::FigureRow> rows;
    std::ostringstream csv;
    csv << "distance,technique,mixing,reference,relative_rmse,energy_ratio\n";
    nlohmann::json table = nlohmann::json::array();
    std::printf("%-9s %-9s %-9s %14s %13s\n", "distance", "technique", "mixing", "relative RMSE",
                "energy ratio");
    for (std::size_t r = 0; r < request.distances.size(); ++r) {
        gl::FigureRow row{"d=" + gl::distance_text(request.distances[r]), {}};
        for (std::size_t m = 0; m < mixings.size(); ++m)
            for (std::size_t t = 0; t < per_row; ++t) {
                row.cells.push_back(gl::encode_srgb(figures[m].cells[r * per_row + t].radiance));
                // The metrics of the specular term over the object's pixels (colour cells).
                const Image& cell = specular[m].cells[r * per_row + t].radiance;
                const Image& reference = specular[0].cells[r * per_row + t].radiance;
                const eval::Mask mask =
                    object_pixels(figures[m].cells[r * per_row + t].radiance,
                                  figures[0].cells[r * per_row + t].radiance, request.background);
                const double rmse = eval::relative_rmse(cell, reference, mask);
                const double energy =
                    eval::masked_mean(cell, mask) / std::max(eval::masked_mean(reference, mask),
                                                             1e-30);
                const char* technique = to_string(request.techniques[t]);
                std::printf("%-9s %-9s %-9s %14.4g %13.4f\n",
                            gl::distance_text(request.distances[r]).c_str(), technique,
                            to_string(mixings[m]), rmse, energy);
                csv << gl::distance_text(request.distances[r]) << "," << technique << ","
                    << to_string(mixings[m]) << "," << to_string(mixings[0]) << "," << rmse << ","
                    << energy << "\n";
                table.push_back({{"distance", request.distances[r]},
                                 {"technique", technique},
                                 {"mixing", to_string(mixings[m])},
                                 {"reference", to_string(mixings[0])},
                                 {"relative_rmse", rmse},
                                 {"energy_ratio", energy}});
            }
        rows.push_back(std::move(row));
    }
    const Image picture = gl::compose_figure(columns, rows, request.cell_width,
                                             request.cell_height);
    io::OutputTransaction outputs;
    io::write_png(outputs.stage(args.output), picture, 8);
    if (!args.table.empty()) {
        const std::string text = csv.str();
        io::AtomicFile file(outputs.stage(args.table));
        file.write(text.data(), text.size());
        file.commit();
        const std::string json = nlohmann::json{{"layers", join(input.layers.sources)},
                                                {"cases", table}}.dump(2) + "\n";
        io::AtomicFile json_file(outputs.stage(json_path));
        json_file.write(json.data(), json.size());
        json_file.commit();
    }
    outputs.publish();
    std::printf("%s: %zu mixing methods x %zu distances on %s\n", args.output.c_str(),
                mixings.size(), request.distances.size(), context.renderer().c_str());
    return 0;
}

}  // namespace leanfade::cli
