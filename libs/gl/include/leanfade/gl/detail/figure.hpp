#pragma once
// The papers' comparison figures: a grid with one column per technique and one row per camera
// distance (fading paper Figs. 1, 4, 5, 8), each column and row labelled, optionally with an
// enlarged crop of each far object. Also the sRGB encoding and the tiny bitmap font they use.
#include <functional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/settings.hpp"
#include "leanfade/gl/renderer.hpp"

namespace leanfade::gl {

struct FigureRequest {
    std::vector<Technique> techniques{Technique::Bump, Technique::Lean, Technique::Fade};
    // Camera distances from the object's centre in bounding radii (> 1); the field of view is
    // fixed, so far objects are small, as in the papers.
    std::vector<float> distances{3.0f, 24.0f};
    int cell_width = 400;  // pixels of each rendered cell
    int cell_height = 400;
    float fov_y_degrees = kDefaultFovYDegrees;
    glm::vec3 view_direction = kDefaultViewDirection;
    // The point the camera looks at (world units); distances are measured from it.
    glm::vec3 target{0.0f};
    ShadingSettings settings;
    int reference_samples = 8;
    float time = 0.0f;  // seconds: moving bump layers' offsets (RenderRequest::time)
    OutputMode output = OutputMode::Color;  // what each cell shows (RenderRequest::output)
    // Rows given as cameras instead of distances (a scene's own views, such as the ocean's near,
    // mid and far, leanfade/scene/detail/ocean.hpp): when not empty, `distances`, the field of view,
    // view_direction, target and zoom are not used, and each row is labelled with its name.
    struct NamedView {
        std::string name;
        View view;
    };
    std::vector<NamedView> views;
    // Adds, below each row whose object is smaller than a third of the cell, a row of
    // nearest-neighbour enlargements of the object (integer factor, same cell size).
    bool zoom = false;
    // Linear RGB behind the object; the fog colour is used instead when fog is on.
    glm::vec3 background{0.012f, 0.013f, 0.016f};
};

struct FigureCell {
    Technique technique = Technique::Lean;
    float distance = 0.0f;  // 0 for a row of FigureRequest::views
    std::string view;       // the row's view name (FigureRequest::views), else empty
    Image radiance;  // linear RGB, cell_width x cell_height, row 0 at the top
};

struct Figure {
    std::vector<FigureCell> cells;  // row-major: distances outer, techniques inner
    Image picture;                  // the labelled grid, sRGB-encoded RGB in [0, 1]
};

// Renders every cell with `renderer` (mesh and LEAN map already set) and composes the grid.
// progress(done, total) is called after each cell when given. Throws leanfade::Error for an empty
// technique or distance list, a distance <= 1 or an invalid cell size.
Figure render_figure(Renderer& renderer, const FigureRequest& request,
                     const std::function<void(int done, int total)>& progress = {});

// A labelled grid of display images (sRGB-encoded RGB, each cw x ch): a header row of column
// names, each row labelled on the left (the layout of render_figure). Throws leanfade::Error
// ("figure", cause) when a row's cell count or a cell's size does not match.
struct FigureRow {
    std::string label;
    std::vector<Image> cells;
};
Image compose_figure(const std::vector<std::string>& columns, const std::vector<FigureRow>& rows,
                     int cw, int ch);

// Linear RGB(A) -> display values: clamped to [0, 1] and encoded with the sRGB transfer function
// (IEC 61966-2-1); alpha is left linear.
Image encode_srgb(const Image& linear);
float encode_srgb(float linear);

// Short text of a distance for labels and file names: "3", "24", "2.5".
std::string distance_text(float distance);

// The 5 x 7 bitmap font (A-Z, 0-9 and " .,:=-+x/()%_"; lower case drawn as upper case; other
// characters as a box). Each glyph advances 6 * scale pixels.
int text_width(const std::string& text, int scale);
inline int text_height(int scale) {
    return 7 * scale;
}
// Draws `text` with its top-left corner at (x, y) (pixels, row 0 at the top) into an RGB image in
// the image's own encoding; pixels outside the image are skipped.
void draw_text(Image& image, int x, int y, const std::string& text, int scale,
               const glm::vec3& color);

}  // namespace leanfade::gl
