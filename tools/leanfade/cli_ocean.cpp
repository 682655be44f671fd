// The ocean on the command line (cli_ocean.hpp).
#include "cli_ocean.hpp"

#include <cctype>
#include <filesystem>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/flow_map.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/gl/detail/scene_view.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::cli {

void add_ocean_options(CLI::App& app, scene::OceanSource& source, std::vector<std::string>& views) {
    const std::string group = "Ocean (--scene ocean, docs/ocean.md)";
    app.add_option("--ocean-layers", source.layers,
                   "Wave layers of Gabor noise, each moving its own way (2-4)")
        ->capture_default_str()
        ->group(group);
    app.add_option("--flow", source.flow,
                   "Layer weights: none (equal), gyre (a clockwise current) or a flow-map image "
                   "(red = +u, green = +v, 0.5 = still)")
        ->capture_default_str()
        ->group(group);
    add_typed_option(app, "--views", views, parse_names,
                     "Rows of `render`: the ocean's cameras near, mid, far, comma-separated",
                     join(views))
        ->group(group);
}

void apply_ocean_shading(ShadingFlags& shading, const CLI::App& app, const scene::OceanSettings& settings,
                         float aspect) {
    set_shading_defaults(scene::ocean_shading(settings, aspect), app, shading);
}

std::vector<gl::FigureRequest::NamedView> ocean_views(const std::vector<std::string>& views,
                                                      const scene::OceanSettings& settings,
                                                      const glm::mat4& model) {
    std::vector<gl::FigureRequest::NamedView> result;
    for (const std::string& name : views) {
        scene::OceanCamera camera;
        try {
            camera = scene::ocean_camera(name, settings);
        } catch (const Error& e) {
            throw Error::setting("--views", e.cause());
        }
        result.push_back(
            {name, gl::view_in_scene(model, camera.eye, camera.target, camera.fov_y_degrees,
                                     camera.near_plane, camera.far_plane)});
    }
    if (result.empty()) throw Error("--views", "no view given (near, mid or far)");
    return result;
}

std::string frame_path(const std::string& pattern, int index, const std::string& flag) {
    std::string result;
    int fields = 0;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') {
            result += pattern[i];
            continue;
        }
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            result += '%';
            ++i;
            continue;
        }
        // %d or %0Nd (N: 1 or 2 digits).
        std::size_t j = i + 1;
        int width = 0;
        if (j < pattern.size() && pattern[j] == '0') {
            ++j;
            const std::size_t digits_start = j;
            while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) &&
                   j - digits_start < 2)
                width = width * 10 + (pattern[j++] - '0');
            if (j == digits_start) width = 0;
        }
        if (j >= pattern.size() || pattern[j] != 'd')
            throw Error::setting(flag, "'" + pattern +
                                           "': only %d, %0Nd and %% are allowed in a frame "
                                           "file name");
        std::string number = std::to_string(index);
        if (int(number.size()) < width) number.insert(0, std::size_t(width) - number.size(), '0');
        result += number;
        ++fields;
        i = j;
    }
    if (fields != 1)
        throw Error::setting(flag, "'" + pattern +
                                       "': a frame sequence's file name needs one %d or %0Nd "
                                       "field (e.g. out/ocean_%03d.png)");
    return result;
}

}  // namespace leanfade::cli
