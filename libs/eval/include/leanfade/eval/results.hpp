#pragma once
// Results of `leanfade eval` and their files: the sweep's parameters, one row per (technique,
// distance, shininess) case, results.csv, results.json, gnuplot plots and the index.html report.
// GL-free.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/core/technique.hpp"

namespace leanfade::eval {

// One measured case. The CSV holds the first seven fields; results.json all of them.
struct CaseResult {
    Technique technique = Technique::Lean;  // one of approximating_techniques()
    float distance = 0.0f;  // camera distance, bounding radii
    float shininess = 0.0f;
    double energy = 0.0;   // specular_mean / reference_specular_mean
    double rmse = 0.0;     // relative RMSE of the linear colour against the reference
    double ssim = 0.0;     // masked SSIM of the sRGB images
    double flicker = 0.0;  // change / reference_change (NaN when the reference does not change)

    double specular_mean = 0.0;            // mean specular radiance over the object's pixels
    double reference_specular_mean = 0.0;  // the same for the reference
    double reference_mean = 0.0;           // mean linear colour of the reference (rmse's scale)
    double change = 0.0;            // mean |frame - previous frame| per object pixel and channel
    double reference_change = 0.0;  // the same for the reference
    int object_pixels = 0;          // pixels measured in frame 0
    int reference_spp = 0;          // samples per pixel of the reference in this case
    // Estimated relative standard errors of the reference itself, from a second reference with
    // a quarter of the samples (k/2 x k/2): for n times fewer samples the difference of the two
    // has sqrt(1 + n) times the error of the better one. reference_noise: per pixel, relative to
    // reference_mean (a floor under rmse); reference_energy_error: of reference_specular_mean.
    double reference_noise = 0.0;
    double reference_energy_error = 0.0;
    // Over every pixel of the image (the object's covered pixels, not eroded; the reference's
    // partly covered edge pixels with their share; the background is black): the sums of the
    // three channels of the specular images and their ratio. `energy` measures the eroded
    // object mask, which leaves out thin parts (a teapot's handle, spout and rim).
    double specular_total = 0.0;
    double reference_specular_total = 0.0;
    double energy_total = 0.0;  // specular_total / reference_specular_total
    // Sweeps over several bump maps (eval --seeds, combine_seeds): how many, and the standard
    // deviation across them of each map's energy and energy_total (0 for one map). With more
    // than one, energy and energy_total are ratios of sums over the maps.
    int seeds = 1;
    double energy_spread = 0.0;
    double energy_total_spread = 0.0;
};

// One sweep per bump map (the same request, a built-in set with different seeds) combined into
// one: per case, the ratios of the seed-summed specular sums (masked: specular_mean times
// object_pixels) and their spread across the maps; rmse, ssim and flicker are the maps' means;
// seeds = the number of sweeps. Every sweep must hold the same cases in the same order. Throws
// leanfade::Error("seeds", ...) otherwise.
std::vector<CaseResult> combine_seeds(const std::vector<std::vector<CaseResult>>& sweeps);

// Cases whose reference_energy_error is above this are flagged as "reference not converged".
inline constexpr double kUnconvergedEnergyError = 0.1;

// What was swept and how; written to results.json and the report.
struct SweepInfo {
    std::string scene;
    std::string bumps;
    std::vector<Technique> techniques;
    std::vector<float> distances;
    std::vector<float> shininesses;
    int width = 0;  // the full frame; only the square around the object is rendered
    int height = 0;
    float fov_y_degrees = 0.0f;
    int reference_samples = 0;  // k: k x k samples per pixel (at least; see adaptive_reference)
    bool adaptive_reference = false;  // k raised where the object is small (SweepRequest)
    int frames = 0;
    float motion_pixels = 0.0f;  // camera pan per frame, pixels at the object's centre
    std::string preset_json;     // scene, bumps and shading as a preset (core/preset.hpp)
    std::string renderer;        // GL_RENDERER
    double seconds = 0.0;        // wall time of the sweep
};

// Frame-0 colour images of one (shininess, distance): the reference and each technique, linear
// RGB, the same crop, background filled.
struct CaseImages {
    float shininess = 0.0f;
    float distance = 0.0f;
    Image reference;
    std::vector<std::pair<Technique, Image>> techniques;
};

// The text of a distance sweep: "A:B:N" (N >= 2 log-spaced distances from A to B,
// 1 < A < B <= 1e4, rounded to 3 significant digits or more where N needs them to differ; N = 1
// gives A) or a comma list of distances in (1, 1e4] (bounding radii, check_camera_distance).
// Throws leanfade::Error(setting, cause).
std::vector<float> parse_distance_sweep(const std::string& text,
                                        const std::string& setting = "distances");
// Comma list of Blinn-Phong exponents > 0. Throws leanfade::Error(setting, cause).
std::vector<float> parse_shininess_list(const std::string& text,
                                        const std::string& setting = "shininess");

// The header and one line per case (%.6g numbers; NaN as "nan").
std::string results_csv(const std::vector<CaseResult>& cases);
// {"sweep": {...}, "definitions": {...}, "cases": [...]}; NaN as null.
std::string results_json(const SweepInfo& info, const std::vector<CaseResult>& cases);

// Writes into `folder` (created if missing): results.csv, results.json, images/*.png (the
// images' sRGB encodings), plots (see write_plots) and index.html, whose image grid shows the
// files of images/ present for the cases. Files are written atomically. Returns the report's
// notes (e.g. "gnuplot not found: ..."), also shown in index.html.
// With no images (a redraw from read_results_json), the existing images/ are shown.
std::vector<std::string> write_report(const std::string& folder, const SweepInfo& info,
                                      const std::vector<CaseResult>& cases,
                                      const std::vector<CaseImages>& images);

// The plots of a sweep: energy.png, energy_total.png, rmse.png, ssim.png and flicker.png in
// `folder`, each with a panel per shininess and a line per technique against log distance, drawn
// by gnuplot from plot_data.tsv and plots.gp (both kept, so the plots can be redrawn by hand). Returns false and
// sets `note` when gnuplot is not installed (Debian: gnuplot-nox) or fails: the data and the
// script are written anyway.
bool write_plots(const std::string& folder, const std::vector<CaseResult>& cases,
                 const std::vector<float>& shininesses, std::string& note);

// Reads a results.json written by results_json (the fields of SweepInfo and CaseResult it
// holds). Throws leanfade::Error(path, cause) for a missing or malformed file, a technique that
// is not a measured technique of the table (is_measured_technique), or a distance or shininess that is not a finite number > 0.
void read_results_json(const std::string& path, SweepInfo& info, std::vector<CaseResult>& cases);

// Runs gnuplot on a script file, in the script's folder; false with `note` set when gnuplot is
// missing or fails. gnuplot is started directly (posix_spawnp), never through a shell, with the
// script as its one argument.
bool run_gnuplot(const std::string& script_path, std::string& note);

// Whether `name` is a technique a sweep measures: one of the technique table's
// (core/technique.hpp) but the supersampled reference. results.json names no other.
bool is_measured_technique(std::string_view name);

// Text as a gnuplot single-quoted string literal, safe for any text: ' is doubled (the only
// escape inside single quotes, where neither backquotes nor @macros are expanded) and control
// characters, which would end the command (newline) or cut the line (NUL), become '?'.
std::string gnuplot_string(std::string_view text);
// A file name as a gnuplot string literal, for a script run in the file's folder. A relative
// name gets "./" in front, so that a name starting with '<' or '|' (gnuplot's pipes to and from
// a shell command) or '-' (inline data) is read as a file. A name cannot be changed as a title
// can: one with a control character throws leanfade::Error(name, cause).
std::string gnuplot_file(const std::string& name);

// The script of write_plots (it reads plot_data.tsv and writes the four PNGs in its folder).
// Every name and title in it is a gnuplot_string or gnuplot_file.
std::string plots_script(const std::vector<CaseResult>& cases,
                         const std::vector<float>& shininesses);

// Writes text to a file atomically (throws leanfade::Error(path, cause)).
void write_text_file(const std::string& path, const std::string& text);

}  // namespace leanfade::eval
