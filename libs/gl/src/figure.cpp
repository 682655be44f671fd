// Comparison figures: cells, zoom rows, labels, sRGB encoding and a 5 x 7 bitmap font.
#include "leanfade/gl/detail/figure.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "leanfade/core/error.hpp"

namespace leanfade::gl {
namespace {

struct Glyph {
    char c;
    std::array<const char*, 7> rows;  // '#' = ink, 5 columns
};

// A classic 5 x 7 dot-matrix font, only the characters labels need.
constexpr Glyph kGlyphs[] = {
    {'A', {" ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'B', {"#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### "}},
    {'C', {" ### ", "#   #", "#    ", "#    ", "#    ", "#   #", " ### "}},
    {'D', {"#### ", "#   #", "#   #", "#   #", "#   #", "#   #", "#### "}},
    {'E', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"}},
    {'F', {"#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#    "}},
    {'G', {" ### ", "#   #", "#    ", "# ###", "#   #", "#   #", " ####"}},
    {'H', {"#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"}},
    {'I', {" ### ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'J', {"  ###", "   # ", "   # ", "   # ", "   # ", "#  # ", " ##  "}},
    {'K', {"#   #", "#  # ", "# #  ", "##   ", "# #  ", "#  # ", "#   #"}},
    {'L', {"#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####"}},
    {'M', {"#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #"}},
    {'N', {"#   #", "#   #", "##  #", "# # #", "#  ##", "#   #", "#   #"}},
    {'O', {" ### ", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'P', {"#### ", "#   #", "#   #", "#### ", "#    ", "#    ", "#    "}},
    {'Q', {" ### ", "#   #", "#   #", "#   #", "# # #", "#  # ", " ## #"}},
    {'R', {"#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #"}},
    {'S', {" ####", "#    ", "#    ", " ### ", "    #", "    #", "#### "}},
    {'T', {"#####", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'U', {"#   #", "#   #", "#   #", "#   #", "#   #", "#   #", " ### "}},
    {'V', {"#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  "}},
    {'W', {"#   #", "#   #", "#   #", "# # #", "# # #", "# # #", " # # "}},
    {'X', {"#   #", "#   #", " # # ", "  #  ", " # # ", "#   #", "#   #"}},
    {'Y', {"#   #", "#   #", " # # ", "  #  ", "  #  ", "  #  ", "  #  "}},
    {'Z', {"#####", "    #", "   # ", "  #  ", " #   ", "#    ", "#####"}},
    {'0', {" ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### "}},
    {'1', {"  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "}},
    {'2', {" ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####"}},
    {'3', {"#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### "}},
    {'4', {"   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # "}},
    {'5', {"#####", "#    ", "#### ", "    #", "    #", "#   #", " ### "}},
    {'6', {"  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### "}},
    {'7', {"#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   "}},
    {'8', {" ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### "}},
    {'9', {" ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  "}},
    {' ', {"     ", "     ", "     ", "     ", "     ", "     ", "     "}},
    {'.', {"     ", "     ", "     ", "     ", "     ", " ##  ", " ##  "}},
    {',', {"     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   "}},
    {':', {"     ", " ##  ", " ##  ", "     ", " ##  ", " ##  ", "     "}},
    {'=', {"     ", "     ", "#####", "     ", "#####", "     ", "     "}},
    {'-', {"     ", "     ", "     ", "#####", "     ", "     ", "     "}},
    {'+', {"     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     "}},
    {'/', {"     ", "    #", "   # ", "  #  ", " #   ", "#    ", "     "}},
    {'(', {"   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # "}},
    {')', {" #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   "}},
    {'%', {"##   ", "##  #", "   # ", "  #  ", " #   ", "#  ##", "   ##"}},
    {'_', {"     ", "     ", "     ", "     ", "     ", "     ", "#####"}},
};

constexpr Glyph kUnknownGlyph = {'?',
                                 {"#####", "#   #", "#   #", "#   #", "#   #", "#   #", "#####"}};

const Glyph& glyph(char c) {
    // Lower-case x is the multiplication sign of zoom labels; it and every letter are drawn in
    // upper case.
    const char upper = char(std::toupper(static_cast<unsigned char>(c)));
    for (const Glyph& g : kGlyphs)
        if (g.c == upper) return g;
    return kUnknownGlyph;
}

void fill(Image& image, int x0, int y0, int w, int h, const glm::vec3& color) {
    for (int y = std::max(0, y0); y < std::min(image.height, y0 + h); ++y)
        for (int x = std::max(0, x0); x < std::min(image.width, x0 + w); ++x)
            for (int c = 0; c < 3; ++c) image.at(x, y, c) = color[c];
}

void blit(Image& dst, const Image& src, int x0, int y0) {
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x)
            for (int c = 0; c < 3; ++c) dst.at(x0 + x, y0 + y, c) = src.at(x, y, c);
}

// Nearest-neighbour enlargement by `factor` of the centre of `cell`, same size as the cell.
Image zoom_centre(const Image& cell, int factor) {
    Image out(cell.width, cell.height, 3);
    const int crop_w = (cell.width + factor - 1) / factor;
    const int crop_h = (cell.height + factor - 1) / factor;
    const int cx = (cell.width - crop_w) / 2, cy = (cell.height - crop_h) / 2;
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const int sx = std::min(cell.width - 1, cx + x / factor);
            const int sy = std::min(cell.height - 1, cy + y / factor);
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = cell.at(sx, sy, c);
        }
    return out;
}

const glm::vec3 kMarginColor{0.13f, 0.13f, 0.14f};  // sRGB-encoded
const glm::vec3 kTextColor{0.93f, 0.93f, 0.93f};    // sRGB-encoded

}  // namespace

float encode_srgb(float linear) {
    const float v = std::clamp(std::isfinite(linear) ? linear : 0.0f, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

Image encode_srgb(const Image& linear) {
    Image out = linear;
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        const bool alpha = linear.channels == 4 && i % 4 == 3;
        out.pixels[i] =
            alpha ? std::clamp(linear.pixels[i], 0.0f, 1.0f) : encode_srgb(linear.pixels[i]);
    }
    return out;
}

std::string distance_text(float distance) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", double(distance));
    return buffer;
}

int text_width(const std::string& text, int scale) {
    return text.empty() ? 0 : (int(text.size()) * 6 - 1) * scale;
}

void draw_text(Image& image, int x, int y, const std::string& text, int scale,
               const glm::vec3& color) {
    for (std::size_t i = 0; i < text.size(); ++i) {
        const Glyph& g = glyph(text[i]);
        const int gx = x + int(i) * 6 * scale;
        for (int row = 0; row < 7; ++row)
            for (int col = 0; col < 5; ++col)
                if (g.rows[std::size_t(row)][col] == '#')
                    fill(image, gx + col * scale, y + row * scale, scale, scale, color);
    }
}

Figure render_figure(Renderer& renderer, const FigureRequest& request,
                     const std::function<void(int, int)>& progress) {
    if (request.techniques.empty()) throw Error::setting("techniques", "no technique given");
    if (request.distances.empty() && request.views.empty())
        throw Error::setting("distances", "no distance given");
    if (request.cell_width < 16 || request.cell_height < 16 || request.cell_width > 8192 ||
        request.cell_height > 8192)
        throw Error::setting("size", "cells must be 16..8192 pixels on each side, got " +
                                         std::to_string(request.cell_width) + "x" +
                                         std::to_string(request.cell_height));
    const int cw = request.cell_width, ch = request.cell_height;
    const glm::vec3 background =
        request.settings.fog == FogMode::None ? request.background : request.settings.fog_color;

    Figure figure;
    // The rows: the named views, or a camera at each distance.
    std::vector<FigureRequest::NamedView> row_views = request.views;
    if (row_views.empty())
        for (float distance : request.distances)
            row_views.push_back({"", view_at_distance(distance, request.fov_y_degrees,
                                                      request.view_direction, request.target)});
    const int total = int(request.techniques.size() * row_views.size());
    struct Row {
        std::string label;
        std::vector<Image> cells;  // sRGB
    };
    std::vector<Row> rows;
    for (std::size_t v = 0; v < row_views.size(); ++v) {
        const bool named = !request.views.empty();
        const float distance = named ? 0.0f : request.distances[v];
        const View& view = row_views[v].view;
        Row row{named ? row_views[v].name : "d=" + distance_text(distance), {}};
        for (Technique technique : request.techniques) {
            RenderRequest r;
            r.technique = technique;
            r.width = cw;
            r.height = ch;
            r.view = view;
            r.settings = request.settings;
            r.reference_samples = request.reference_samples;
            r.time = request.time;
            r.output = request.output;
            r.background = background;
            figure.cells.push_back({technique, distance, row_views[v].name, renderer.render(r)});
            row.cells.push_back(encode_srgb(figure.cells.back().radiance));
            if (progress) progress(int(figure.cells.size()), total);
        }
        rows.push_back(std::move(row));
        const float diameter = 2.0f * projected_radius_pixels(view, ch);
        if (request.zoom && !named && diameter < float(ch) / 3.0f) {
            const int factor =
                std::clamp(int(std::floor(float(std::min(cw, ch)) / (1.25f * diameter))), 2, 16);
            Row zoomed;
            zoomed.label = std::string(1, 'x').append(std::to_string(factor));
            for (const Image& cell : rows.back().cells)
                zoomed.cells.push_back(zoom_centre(cell, factor));
            rows.push_back(std::move(zoomed));
        }
    }

    std::vector<std::string> columns;
    for (Technique technique : request.techniques) columns.push_back(to_string(technique));
    std::vector<FigureRow> grid;
    for (Row& row : rows) grid.push_back({row.label, std::move(row.cells)});
    Image picture = compose_figure(columns, grid, cw, ch);
    figure.picture = std::move(picture);
    return figure;
}

Image compose_figure(const std::vector<std::string>& columns, const std::vector<FigureRow>& rows,
                     int cw, int ch) {
    for (const FigureRow& row : rows) {
        if (row.cells.size() != columns.size())
            throw Error("figure", "a row has " + std::to_string(row.cells.size()) +
                                      " cells for " + std::to_string(columns.size()) + " columns");
        for (const Image& cell : row.cells)
            if (cell.width != cw || cell.height != ch)
                throw Error("figure", "the cells differ in size");
    }
    // Layout: a header row of column names, a column of row labels, 1-scale gaps.
    const int scale = std::max(1, ch / 160);
    const int pad = 3 * scale;
    const int gap = scale;
    int label_width = 0;
    for (const FigureRow& row : rows)
        label_width = std::max(label_width, text_width(row.label, scale));
    const int left = label_width + 2 * pad;
    const int top = text_height(scale) + 2 * pad;
    const int count = int(columns.size());
    const int width = left + count * (cw + gap);
    const int height = top + int(rows.size()) * (ch + gap);
    Image picture(width, height, 3);
    fill(picture, 0, 0, width, height, kMarginColor);
    for (int c = 0; c < count; ++c) {
        const std::string& name = columns[std::size_t(c)];
        const int x = left + c * (cw + gap) + (cw - text_width(name, scale)) / 2;
        draw_text(picture, x, pad, name, scale, kTextColor);
    }
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const int y = top + int(r) * (ch + gap);
        draw_text(picture, pad, y + (ch - text_height(scale)) / 2, rows[r].label, scale,
                  kTextColor);
        for (int c = 0; c < count; ++c)
            blit(picture, rows[r].cells[std::size_t(c)], left + c * (cw + gap), y);
    }
    return picture;
}

}  // namespace leanfade::gl
