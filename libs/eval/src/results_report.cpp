// Results files of `leanfade eval`: the HTML report.
#include "leanfade/eval/results.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "results_internal.hpp"

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/eval/metrics.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::eval {

using namespace results_detail;

std::vector<std::string> write_report(const std::string& folder, const SweepInfo& info,
                                      const std::vector<CaseResult>& cases,
                                      const std::vector<CaseImages>& images) {
    std::error_code ec;
    fs::create_directories(fs::path(folder) / "images", ec);
    if (!fs::is_directory(fs::path(folder) / "images"))
        throw Error(folder, "cannot create the output folder");
    write_text_file((fs::path(folder) / "results.csv").string(), results_csv(cases));
    write_text_file((fs::path(folder) / "results.json").string(), results_json(info, cases));
    for (const CaseImages& ci : images) {
        io::write_png((fs::path(folder) / "images" /
                       image_name(ci.shininess, ci.distance, Technique::Reference))
                          .string(),
                      encode_srgb(ci.reference), 8);
        for (const auto& [technique, image] : ci.techniques)
            io::write_png(
                (fs::path(folder) / "images" / image_name(ci.shininess, ci.distance, technique))
                    .string(),
                encode_srgb(image), 8);
    }
    std::vector<std::string> notes;
    std::string note;
    const bool plotted = write_plots(folder, cases, info.shininesses, note);
    if (!plotted) notes.push_back(note);

    const std::vector<Technique> techniques = technique_order(cases);
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      << "<title>leanfade eval: " << html_escape(info.scene) << " / " << html_escape(info.bumps)
      << "</title>\n<style>\n"
      << "body{font-family:sans-serif;margin:1.5em;max-width:1400px}\n"
      << "table{border-collapse:collapse;margin:0.5em 1em 1em 0;display:inline-table}\n"
      << "td,th{border:1px solid #ccc;padding:2px 6px;text-align:right;font-size:90%}\n"
      << "th{background:#f0f0f0}\nimg.cell{width:128px;height:128px;image-rendering:pixelated;"
      << "background:#000}\n.grid td{padding:1px}\n.note{color:#a00}\n</style></head><body>\n"
      << "<h1>leanfade eval: " << html_escape(info.scene) << " / " << html_escape(info.bumps)
      << "</h1>\n";
    for (const std::string& n : notes) h << "<p class=\"note\">" << html_escape(n) << "</p>\n";
    h << "<h2>What was measured</h2>\n<ul>\n"
      << "<li>Each technique against the <b>reference</b> (docs/math.md §7): "
      << (info.adaptive_reference ? "at least " : "")
      << info.reference_samples * info.reference_samples
      << " samples per pixel at LOD 0, shaded with Blinn-Phong bump mapping and box-filtered, "
      << "from the same camera. Frame " << info.width << "x" << info.height
      << " pixels, vertical field of view " << short_number(info.fov_y_degrees)
      << "&deg;; only the square around the object is rendered.</li>\n"
      << "<li><b>Object pixels</b>: covered with their 8 neighbours (silhouette left out).</li>\n"
      << "<li><b>energy</b>: mean specular radiance over the object's pixels / the "
      << "reference's.</li>\n"
      << "<li><b>rmse</b>: RMS difference of the linear colour / the reference's mean.</li>\n"
      << "<li><b>ssim</b>: SSIM (Wang et al. 2004) of the sRGB images, window restricted to the "
      << "object.</li>\n"
      << "<li><b>flicker</b>: over " << info.frames << " frames of a camera pan of "
      << short_number(info.motion_pixels)
      << " pixel per frame, the mean absolute frame-to-frame change of the sRGB value per "
      << "object pixel, divided by the reference's (1 = as stable as the truth).</li>\n"
      << "<li>Energy, rmse and ssim are taken on frame 0.</li>\n"
      << "<li>"
      << (info.adaptive_reference
              ? "Where the object covers fewer pixels, the reference takes more samples "
                "per pixel (k x k, then averaged sub-sample-shifted renders) at the "
                "same samples per frame. "
              : "")
      << "The reference's own error is estimated from a second reference with a quarter of the "
      << "samples. "
      << "<b>*</b> marks cases whose reference energy is uncertain by more than "
      << int(kUnconvergedEnergyError * 100) << "% (not converged: read them with care).</li>\n"
      << "</ul>\n"
      << "<p>Renderer: " << html_escape(info.renderer) << "; " << short_number(info.seconds)
      << " s. Data: <a href=\"results.csv\">results.csv</a>, "
      << "<a href=\"results.json\">results.json</a>, plots from <a href=\"plot_data.tsv\">"
      << "plot_data.tsv</a> by <a href=\"plots.gp\">plots.gp</a>.</p>\n";

    h << "<h2>Plots</h2>\n";
    for (const Metric& m : metrics()) {
        if (plotted) h << "<p><img src=\"" << m.key << ".png\" alt=\"" << m.title << "\"></p>\n";
    }
    if (!plotted) h << "<p class=\"note\">No plots (see above).</p>\n";

    h << "<h2>Tables</h2>\n";
    for (float s : info.shininesses) {
        h << "<h3>s = " << short_number(s) << "</h3>\n";
        for (const Metric& m : metrics()) {
            h << "<table><tr><th>" << m.key << "<br>distance</th>";
            for (Technique t : techniques) h << "<th>" << html_escape(to_string(t)) << "</th>";
            h << "</tr>\n";
            for (float d : info.distances) {
                const CaseResult* first = find_case(cases, techniques.front(), d, s);
                h << "<tr><th>" << short_number(d) << "<br><small>"
                  << (first ? first->reference_spp : 0) << " spp</small></th>";
                for (Technique t : techniques) {
                    const CaseResult* c = find_case(cases, t, d, s);
                    const bool flagged =
                        c != nullptr && !(c->reference_energy_error <= kUnconvergedEnergyError);
                    h << "<td>" << (c ? number(c->*(m.field)) : std::string(""))
                      << (flagged ? "*" : "") << "</td>";
                }
                h << "</tr>\n";
            }
            h << "</table>\n";
        }
    }

    h << "<h2>Images (frame 0, sRGB; enlarged without filtering)</h2>\n";
    for (float s : info.shininesses) {
        h << "<h3>s = " << short_number(s) << "</h3>\n<table class=\"grid\"><tr><th>distance"
          << "</th><th>reference</th>";
        for (Technique t : techniques) h << "<th>" << html_escape(to_string(t)) << "</th>";
        h << "</tr>\n";
        for (float d : info.distances) {
            h << "<tr><th>" << short_number(d) << "</th>";
            std::vector<Technique> columns{Technique::Reference};
            columns.insert(columns.end(), techniques.begin(), techniques.end());
            for (Technique column : columns) {
                const std::string name = to_string(column);
                const std::string file = image_name(s, d, column);
                if (fs::exists(fs::path(folder) / "images" / file, ec))
                    h << "<td><img class=\"cell\" src=\"images/" << file << "\" alt=\""
                      << html_escape(name) << "\"></td>";
                else
                    h << "<td></td>";
            }
            h << "</tr>\n";
        }
        h << "</table>\n";
    }
    h << "</body></html>\n";
    write_text_file((fs::path(folder) / "index.html").string(), h.str());
    return notes;
}

}  // namespace leanfade::eval
