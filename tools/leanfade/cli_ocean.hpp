#pragma once
// The built-in `ocean` scene on the command line (leanfade/scene/detail/ocean.hpp, docs/ocean.md): its
// flags, the ocean's shading as the defaults of the shading flags, its near / mid / far cameras
// as the rows of `render`, and the frame sequences of `render --frames`.
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include "cli_render_options.hpp"
#include "leanfade/gl/detail/figure.hpp"
#include "leanfade/scene/detail/ocean.hpp"
#include "leanfade/scene/scene_source.hpp"

namespace leanfade::cli {

// --ocean-layers --flow (the ocean's source, leanfade/scene/scene_source.hpp) and --views (the
// rows of `render --scene ocean`: its cameras near, mid, far), in the "Ocean (--scene ocean)"
// group.
void add_ocean_options(CLI::App& app, scene::OceanSource& source, std::vector<std::string>& views);

// The ocean's shading (scene::ocean_shading) for images of width / height `aspect` becomes the
// value of every shading flag not given on the command line.
void apply_ocean_shading(ShadingFlags& shading, const CLI::App& app, const scene::OceanSettings& settings,
                         float aspect);

// The cameras named by --views as the rows of a figure, in the renderer's world space (`model`:
// Renderer::model_matrix() of the ocean). Throws leanfade::Error("--views", cause).
std::vector<gl::FigureRequest::NamedView> ocean_views(const std::vector<std::string>& views,
                                                      const scene::OceanSettings& settings,
                                                      const glm::mat4& model);

// Frame `index` of a sequence: `pattern` with its one printf-style integer field ("%d", "%03d")
// replaced by the index ("%%" is a percent sign). Throws leanfade::Error(flag, cause) for a
// pattern with no field or more than one, or another directive.
std::string frame_path(const std::string& pattern, int index, const std::string& flag = "-o");

}  // namespace leanfade::cli
