// Results files of `leanfade eval`: parsing of the sweep lists, CSV, JSON, plots and the report.
#include "leanfade/eval/results.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/core/technique.hpp"
#include "leanfade/core/text.hpp"
#include "leanfade/eval/metrics.hpp"
#include "leanfade/io/atomic_file.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::eval {
namespace {

namespace fs = std::filesystem;

bool parse_number(const std::string& text, double& value) {
    const std::optional<double> parsed = parse_finite_double(text);
    if (parsed) value = *parsed;
    return parsed.has_value();
}

// Rounds to `digits` significant digits, so that log-spaced distances print as 3.17 rather than
// 3.1748.
float round_significant(double v, int digits = 3) {
    if (v == 0.0) return 0.0f;
    const double scale =
        std::pow(10.0, double(digits - 1) - std::floor(std::log10(std::abs(v))));
    return float(std::round(v * scale) / scale);
}

// The largest camera distance of a sweep, bounding radii: beyond it the object covers far less
// than a pixel of any frame.
constexpr double kMaxSweepDistance = 1e4;

std::string number(double v) {
    if (std::isnan(v)) return "nan";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return buffer;
}

// A distance or shininess as it appears in file names and labels: "3.17", "1024".
std::string short_number(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", v);
    return buffer;
}

nlohmann::json json_number(double v) {
    if (!std::isfinite(v)) return nullptr;
    return v;
}

std::string html_escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '&':
                out += "&amp;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

// Fixed colours per technique, the same in every plot.
std::string technique_color(const std::string& name) {
    for (const TechniqueInfo& row : kTechniques)
        if (name == row.name) return std::string(row.plot_color);
    return "#7f7f7f";
}

std::vector<std::string> technique_order(const std::vector<CaseResult>& cases) {
    std::vector<std::string> names;
    for (const CaseResult& c : cases)
        if (std::find(names.begin(), names.end(), c.technique) == names.end())
            names.push_back(c.technique);
    return names;
}

const CaseResult* find_case(const std::vector<CaseResult>& cases, const std::string& technique,
                            float distance, float shininess) {
    for (const CaseResult& c : cases)
        if (c.technique == technique && c.distance == distance && c.shininess == shininess)
            return &c;
    return nullptr;
}

struct Metric {
    const char* key;    // file name and column
    const char* title;  // plot title
    const char* y_label;
    bool log_y;
    double truth;         // the reference's value (a dashed line), NaN for none
    const char* y_range;  // gnuplot range; values outside are clipped (named in the title)
    double CaseResult::*field;
};

const std::vector<Metric>& metrics() {
    static const std::vector<Metric> list = {
        {"energy", "Specular energy / reference (clipped to 0.01-100)", "energy ratio", true, 1.0,
         "[0.01:100]", &CaseResult::energy},
        {"rmse", "Relative RMSE vs reference (linear radiance)", "RMSE / reference mean", true, NAN,
         "[*:*]", &CaseResult::rmse},
        {"ssim", "SSIM vs reference (sRGB)", "SSIM", false, 1.0, "[0:1.02]", &CaseResult::ssim},
        {"flicker", "Flicker relative to the reference (clipped to 0.1-10)", "flicker ratio", true,
         1.0, "[0.1:10]", &CaseResult::flicker},
    };
    return list;
}

std::string image_name(float shininess, float distance, const std::string& technique) {
    return "s" + short_number(shininess) + "_d" + short_number(distance) + "_" + technique + ".png";
}

bool executable_on_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (path == nullptr) return false;
    for (const std::string& dir : split(path, ':')) {
        if (dir.empty()) continue;
        const std::string candidate = dir + "/" + name;
        if (::access(candidate.c_str(), X_OK) == 0) return true;
    }
    return false;
}

bool is_control(char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
}

// A name read from a file, for a one-line message: control characters as '?', at most 40
// characters.
std::string printable(const std::string& text) {
    std::string out;
    for (char c : text.substr(0, 40)) out += is_control(c) ? '?' : c;
    return text.size() > 40 ? out + "..." : out;
}

// After parsing: every technique one the renderer knows, every distance and shininess finite
// and positive (they reach the plots' script and the report).
void validate_results(const std::string& path, const SweepInfo& info,
                      const std::vector<CaseResult>& cases) {
    auto check_technique = [&](const std::string& name) {
        if (!is_measured_technique(name))
            throw Error(path, "unknown technique '" + printable(name) + "' (expected " +
                                  technique_names(approximating_techniques()) + ")");
    };
    auto check_positive = [&](double value, const char* what) {
        if (!(std::isfinite(value) && value > 0.0))
            throw Error(path, std::string(what) + " must be a finite number > 0, got " +
                                  number(value));
    };
    for (const std::string& t : info.techniques) check_technique(t);
    for (float d : info.distances) check_positive(d, "a distance");
    for (float s : info.shininesses) check_positive(s, "a shininess");
    for (const CaseResult& c : cases) {
        check_technique(c.technique);
        check_positive(c.distance, "a case's distance");
        check_positive(c.shininess, "a case's shininess");
    }
}

}  // namespace

bool is_measured_technique(std::string_view name) {
    for (Technique t : approximating_techniques())
        if (name == to_string(t)) return true;
    return false;
}

std::string gnuplot_string(std::string_view text) {
    std::string out = "'";
    for (char c : text) {
        if (c == '\'')
            out += "''";
        else
            out += is_control(c) ? '?' : c;
    }
    return out + "'";
}

std::string gnuplot_file(const std::string& name) {
    if (name.empty()) throw Error("gnuplot", "empty file name");
    for (char c : name)
        if (is_control(c))
            throw Error(printable(name),
                        "a file name with a control character cannot be given to gnuplot");
    return gnuplot_string(name.front() == '/' ? name : "./" + name);
}

std::vector<float> parse_distance_sweep(const std::string& text, const std::string& flag) {
    const std::vector<std::string> range = split(text, ':');
    std::vector<float> result;
    if (range.size() == 3) {
        double a = 0.0, b = 0.0, n = 0.0;
        if (!parse_number(range[0], a) || !parse_number(range[1], b) ||
            !parse_number(range[2], n) || n != std::floor(n))
            throw Error(flag, "expected A:B:N (N whole) or a comma list, got '" + text + "'");
        if (!(a > 1.0) || !(b > a) || n < 1.0 || n > 1000.0 || b > kMaxSweepDistance)
            throw Error(flag,
                        "A:B:N needs 1 < A < B <= 1e4 and 1 <= N <= 1000 (distances in bounding "
                        "radii), got '" +
                            text + "'");
        const int count = int(n);
        // 3 significant digits, more when the steps are finer than that (2:1000:1000 steps by
        // 0.6 %): N distinct distances.
        for (int digits = 3; digits <= 9; ++digits) {
            result.clear();
            for (int i = 0; i < count; ++i) {
                const double t = count == 1 ? 0.0 : double(i) / double(count - 1);
                result.push_back(round_significant(a * std::pow(b / a, t), digits));
            }
            if (std::adjacent_find(result.begin(), result.end()) == result.end()) break;
        }
        if (std::adjacent_find(result.begin(), result.end()) != result.end())
            throw Error(flag, "A:B:N: " + range[2] + " distances from " + range[0] + " to " +
                                  range[1] +
                                  " are closer than float numbers tell apart; give fewer or a "
                                  "wider range");
    } else if (range.size() == 1) {
        for (const std::string& part : split(text, ',')) {
            double d = 0.0;
            if (!parse_number(part, d))
                throw Error(flag, "expected A:B:N or comma-separated numbers, got '" + text + "'");
            if (!(d > 1.0))
                throw Error(flag,
                            "distances are in bounding radii from the object's centre and "
                            "must be > 1, got " +
                                part);
            if (d > kMaxSweepDistance)
                throw Error(flag, "distances must be at most 1e4 bounding radii (the object "
                                  "covers far less than a pixel beyond), got " +
                                      part);
            result.push_back(float(d));
        }
    } else {
        throw Error(flag, "expected A:B:N or a comma list, got '" + text + "'");
    }
    for (std::size_t i = 0; i < result.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (result[i] == result[j])
                throw Error(flag, "distance " + short_number(result[i]) + " given twice");
    return result;
}

std::vector<float> parse_shininess_list(const std::string& text, const std::string& flag) {
    std::vector<float> result;
    for (const std::string& part : split(text, ',')) {
        double s = 0.0;
        if (!parse_number(part, s) || !(s > 0.0) || s > 1e7)
            throw Error(flag, "expected comma-separated exponents in (0, 1e7], got '" + text + "'");
        if (std::find(result.begin(), result.end(), float(s)) != result.end())
            throw Error(flag, "shininess " + part + " given twice");
        result.push_back(float(s));
    }
    return result;
}

std::string results_csv(const std::vector<CaseResult>& cases) {
    std::string out = "technique,distance,shininess,energy,rmse,ssim,flicker\n";
    for (const CaseResult& c : cases)
        out += c.technique + "," + number(c.distance) + "," + number(c.shininess) + "," +
               number(c.energy) + "," + number(c.rmse) + "," + number(c.ssim) + "," +
               number(c.flicker) + "\n";
    return out;
}

std::string results_json(const SweepInfo& info, const std::vector<CaseResult>& cases) {
    nlohmann::json sweep = {
        {"scene", info.scene},
        {"bumps", info.bumps},
        {"techniques", info.techniques},
        {"distances", info.distances},
        {"shininesses", info.shininesses},
        {"size", {info.width, info.height}},
        {"fov_y_degrees", info.fov_y_degrees},
        {"reference_samples_per_pixel", info.reference_samples * info.reference_samples},
        {"adaptive_reference", info.adaptive_reference},
        {"frames", info.frames},
        {"motion_pixels_per_frame", info.motion_pixels},
        {"renderer", info.renderer},
        {"seconds", info.seconds},
    };
    if (!info.preset_json.empty()) sweep["preset"] = nlohmann::json::parse(info.preset_json);
    const nlohmann::json definitions = {
        {to_string(Technique::Reference),
         "docs/math.md §7: k x k samples per pixel at LOD 0 shaded with Blinn-Phong bump "
         "mapping, box-filtered; same camera. With adaptive_reference, more "
         "samples per pixel where the object covers fewer pixels than the frame "
         "(k up to 16, then averaged renders shifted by sub-sample offsets), "
         "keeping the samples per frame; reference_spp gives each case's"},
        {"reference_noise",
         "estimated relative standard error per pixel of the reference "
         "itself (a floor under rmse), from a second reference with a quarter "
         "of the samples: RMS difference / sqrt(5) / reference mean"},
        {"reference_energy_error",
         "estimated relative standard error of the reference's "
         "specular energy, from the same second reference; above 0.1 "
         "the case is flagged as not converged"},
        {"object_pixels",
         "pixels whose 3 x 3 neighbourhood is covered by the object in the "
         "single-sample render (silhouette pixels excluded)"},
        {"energy", "mean specular radiance over the object's pixels / the reference's (frame 0)"},
        {"rmse",
         "root mean square difference of the linear colour over the object's pixels and "
         "RGB / the reference's mean linear colour (frame 0)"},
        {"ssim",
         "SSIM (Wang et al. 2004: 11x11 Gaussian window, sigma 1.5, K1 0.01, K2 0.03) of "
         "the sRGB-encoded colour, window restricted to object pixels, mean over object "
         "pixels and RGB (frame 0)"},
        {"flicker",
         "mean over consecutive frames of the mean |sRGB change| per object pixel "
         "and channel while the camera pans by motion_pixels_per_frame, divided by "
         "the reference's (1 = as stable as the truth)"},
    };
    nlohmann::json rows = nlohmann::json::array();
    for (const CaseResult& c : cases)
        rows.push_back({{"technique", c.technique},
                        {"distance", c.distance},
                        {"shininess", c.shininess},
                        {"energy", json_number(c.energy)},
                        {"rmse", json_number(c.rmse)},
                        {"ssim", json_number(c.ssim)},
                        {"flicker", json_number(c.flicker)},
                        {"specular_mean", json_number(c.specular_mean)},
                        {"reference_specular_mean", json_number(c.reference_specular_mean)},
                        {"reference_mean", json_number(c.reference_mean)},
                        {"change", json_number(c.change)},
                        {"reference_change", json_number(c.reference_change)},
                        {"object_pixels", c.object_pixels},
                        {"reference_spp", c.reference_spp},
                        {"reference_noise", json_number(c.reference_noise)},
                        {"reference_energy_error", json_number(c.reference_energy_error)}});
    const nlohmann::json root = {
        {"leanfade_eval", 1}, {"sweep", sweep}, {"definitions", definitions}, {"cases", rows}};
    return root.dump(2) + "\n";
}

namespace {

// A preset nests 3 levels; results.json's sweep.preset may nest at most this deep.
constexpr int kMaxPresetJsonDepth = 16;

// How many arrays and objects of `value` nest (0 for a scalar), without recursion; the count
// stops a level past kMaxPresetJsonDepth.
int json_depth(const nlohmann::json& value) {
    int deepest = 0;
    std::vector<std::pair<const nlohmann::json*, int>> stack{{&value, 1}};
    while (!stack.empty()) {
        const auto [item, depth] = stack.back();
        stack.pop_back();
        if (!item->is_structured()) continue;
        deepest = std::max(deepest, depth);
        if (depth > kMaxPresetJsonDepth) break;
        for (const nlohmann::json& child : *item) stack.emplace_back(&child, depth + 1);
    }
    return deepest;
}

}  // namespace

void read_results_json(const std::string& path, SweepInfo& info, std::vector<CaseResult>& cases) {
    const std::string text = read_regular_file(path, kMaxResultsFileBytes, "a results file");
    auto number_or_nan = [](const nlohmann::json& v) {
        return v.is_null() ? std::nan("") : v.get<double>();
    };
    try {
        const nlohmann::json root = nlohmann::json::parse(text);
        if (root.value("leanfade_eval", 0) != 1)
            throw Error(path, "not a results.json of leanfade eval (version 1)");
        const nlohmann::json& s = root.at("sweep");
        info = SweepInfo{};
        info.scene = s.at("scene").get<std::string>();
        info.bumps = s.at("bumps").get<std::string>();
        info.techniques = s.at("techniques").get<std::vector<std::string>>();
        info.distances = s.at("distances").get<std::vector<float>>();
        info.shininesses = s.at("shininesses").get<std::vector<float>>();
        info.width = s.at("size").at(0).get<int>();
        info.height = s.at("size").at(1).get<int>();
        info.fov_y_degrees = s.at("fov_y_degrees").get<float>();
        info.reference_samples =
            int(std::lround(std::sqrt(s.at("reference_samples_per_pixel").get<double>())));
        info.adaptive_reference = s.value("adaptive_reference", false);
        info.frames = s.at("frames").get<int>();
        info.motion_pixels = s.at("motion_pixels_per_frame").get<float>();
        info.renderer = s.at("renderer").get<std::string>();
        info.seconds = s.at("seconds").get<double>();
        if (s.contains("preset")) {
            // Indentation grows with the depth: the preset's depth and size are checked on the
            // parsed value before it is written again (a deep one took memory quadratic in it).
            const nlohmann::json& preset = s.at("preset");
            if (json_depth(preset) > kMaxPresetJsonDepth)
                throw Error(path, "sweep.preset nests deeper than " +
                                      std::to_string(kMaxPresetJsonDepth) + " levels");
            if (preset.dump().size() > kMaxPresetFileBytes)
                throw Error(path, "sweep.preset is larger than a preset file may be (" +
                                      std::to_string(kMaxPresetFileBytes) + " bytes)");
            info.preset_json = preset.dump(2);
        }
        cases.clear();
        for (const nlohmann::json& c : root.at("cases")) {
            CaseResult r;
            r.technique = c.at("technique").get<std::string>();
            r.distance = c.at("distance").get<float>();
            r.shininess = c.at("shininess").get<float>();
            r.energy = number_or_nan(c.at("energy"));
            r.rmse = number_or_nan(c.at("rmse"));
            r.ssim = number_or_nan(c.at("ssim"));
            r.flicker = number_or_nan(c.at("flicker"));
            r.specular_mean = number_or_nan(c.at("specular_mean"));
            r.reference_specular_mean = number_or_nan(c.at("reference_specular_mean"));
            r.reference_mean = number_or_nan(c.at("reference_mean"));
            r.change = number_or_nan(c.at("change"));
            r.reference_change = number_or_nan(c.at("reference_change"));
            r.object_pixels = c.at("object_pixels").get<int>();
            r.reference_spp = c.value("reference_spp", 0);
            r.reference_noise = number_or_nan(c.value("reference_noise", nlohmann::json()));
            r.reference_energy_error =
                number_or_nan(c.value("reference_energy_error", nlohmann::json()));
            cases.push_back(r);
        }
    } catch (const nlohmann::json::exception& e) {
        throw Error(path, "malformed results: " + escape_text(e.what(), 2000));
    }
    validate_results(path, info, cases);
}

void write_text_file(const std::string& path, const std::string& text) {
    io::AtomicFile file(path);
    file.write(text.data(), text.size());
    file.commit();
}

bool run_gnuplot(const std::string& script_path, std::string& note) {
    if (!executable_on_path("gnuplot")) {
        note =
            "gnuplot not found on PATH (Debian: apt install gnuplot-nox): plots not drawn; "
            "the data and the script " +
            script_path + " are written";
        return false;
    }
    // gnuplot itself, no shell: the script is a file argument ("./" keeps a name starting with
    // '-' from being an option), run in the script's folder, its output read from a pipe.
    const fs::path script(script_path);
    const std::string folder = script.parent_path().empty() ? "." : script.parent_path().string();
    const std::string argument = "./" + script.filename().string();
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) {
        note = "could not start gnuplot (no pipe)";
        return false;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
    posix_spawn_file_actions_addchdir_np(&actions, folder.c_str());
    char* const argv[] = {const_cast<char*>("gnuplot"), const_cast<char*>(argument.c_str()),
                          nullptr};
    pid_t pid = 0;
    const int spawned = ::posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(fds[1]);
    if (spawned != 0) {
        ::close(fds[0]);
        note = "could not start gnuplot: " + std::string(std::strerror(spawned));
        return false;
    }
    std::string output;
    char buffer[512];
    for (;;) {
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n > 0) {
            if (output.size() < 4096) output.append(buffer, std::size_t(n));
        } else if (n == 0 || errno != EINTR) {
            break;
        }
    }
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::replace_if(output.begin(), output.end(), is_control, ' ');
        note = "gnuplot failed on " + script_path + ": " + output.substr(0, 300);
        return false;
    }
    return true;
}

bool write_plots(const std::string& folder, const std::vector<CaseResult>& cases,
                 const std::vector<float>& shininesses, std::string& note) {
    const std::vector<std::string> techniques = technique_order(cases);
    // plot_data.tsv: one block per (shininess, technique), blocks separated by two blank lines
    // (gnuplot's `index`), in that order.
    std::ostringstream data;
    data << "# distance energy rmse ssim flicker reference_noise; one block per (shininess, "
            "technique)\n";
    for (float s : shininesses)
        for (const std::string& t : techniques) {
            std::string name = t;  // a comment line: a newline would start a data row
            std::replace_if(name.begin(), name.end(), is_control, '?');
            data << "# shininess " << short_number(s) << " technique " << name << "\n";
            std::vector<const CaseResult*> rows;
            for (const CaseResult& c : cases)
                if (c.shininess == s && c.technique == t) rows.push_back(&c);
            std::sort(rows.begin(), rows.end(), [](const CaseResult* a, const CaseResult* b) {
                return a->distance < b->distance;
            });
            for (const CaseResult* c : rows) {
                data << number(c->distance);
                for (double v : {c->energy, c->rmse, c->ssim, c->flicker, c->reference_noise})
                    data << "\t" << (std::isfinite(v) ? number(v) : std::string("?"));
                data << "\n";
            }
            data << "\n\n";
        }
    write_text_file((fs::path(folder) / "plot_data.tsv").string(), data.str());
    const std::string script = (fs::path(folder) / "plots.gp").string();
    write_text_file(script, plots_script(cases, shininesses));
    return run_gnuplot(script, note);
}

std::string plots_script(const std::vector<CaseResult>& cases,
                         const std::vector<float>& shininesses) {
    const std::vector<std::string> techniques = technique_order(cases);
    const std::string data = gnuplot_file("plot_data.tsv");
    std::ostringstream gp;
    const int panels = int(shininesses.size());
    float lo = 0.0f, hi = 0.0f;
    for (const CaseResult& c : cases) {
        if (!(std::isfinite(c.distance) && c.distance > 0.0f)) continue;
        lo = lo == 0.0f ? c.distance : std::min(lo, c.distance);
        hi = std::max(hi, c.distance);
    }
    if (lo == 0.0f) lo = hi = 1.0f;
    gp << "# gnuplot script written by leanfade eval; run `gnuplot plots.gp` in this folder.\n"
       << "set datafile missing '?'\nset datafile separator '\\t'\n"
       << "set logscale x 2\nset grid\nset format y '%g'\n"
       << "set xlabel " << gnuplot_string("camera distance (bounding radii)") << "\n"
       << "set xrange [" << lo / 1.15f << ":" << hi * 1.15f << "]\n";
    for (std::size_t m = 0; m < metrics().size(); ++m) {
        const Metric& metric = metrics()[m];
        gp << "\nset terminal pngcairo size " << 360 * panels + 40 << ",360 font 'sans,10'\n"
           << "set output " << gnuplot_file(std::string(metric.key) + ".png") << "\n"
           << "set multiplot layout 1," << panels << " title " << gnuplot_string(metric.title)
           << "\n"
           << (metric.log_y ? "set logscale y\n" : "unset logscale y\n") << "set yrange "
           << metric.y_range << "\n"
           << "set ylabel " << gnuplot_string(metric.y_label) << "\n";
        for (int si = 0; si < panels; ++si) {
            // One key, in the first panel.
            gp << (si == 0 ? "set key top left opaque box font ',8' samplen 2 spacing 0.9\n"
                           : "unset key\n")
               << "set title "
               << gnuplot_string("s = " + short_number(shininesses[std::size_t(si)])) << "\n"
               << "plot ";
            if (std::isfinite(metric.truth))
                gp << metric.truth << " with lines dt 2 lc rgb '#808080' title 'reference', ";
            if (metric.field == &CaseResult::rmse)  // the floor the reference's noise sets
                gp << data << " index " << std::size_t(si) * techniques.size()
                   << " using 1:6 with lines dt 2 lw 2 lc rgb '#808080' title 'reference noise', ";
            for (std::size_t ti = 0; ti < techniques.size(); ++ti) {
                const std::size_t block = std::size_t(si) * techniques.size() + ti;
                gp << (ti == 0 ? "" : ", ") << data << " index " << block << " using 1:" << m + 2
                   << " with linespoints lw 2 pt 7 ps 0.6 lc rgb "
                   << gnuplot_string(technique_color(techniques[ti])) << " title "
                   << gnuplot_string(techniques[ti]);
            }
            gp << "\n";
        }
        gp << "unset multiplot\n";
    }
    return gp.str();
}

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
        io::write_png(
            (fs::path(folder) / "images" / image_name(ci.shininess, ci.distance,
                                                                to_string(Technique::Reference)))
                .string(),
            encode_srgb(ci.reference), 8);
        for (const auto& [name, image] : ci.techniques)
            io::write_png(
                (fs::path(folder) / "images" / image_name(ci.shininess, ci.distance, name))
                    .string(),
                encode_srgb(image), 8);
    }
    std::vector<std::string> notes;
    std::string note;
    const bool plotted = write_plots(folder, cases, info.shininesses, note);
    if (!plotted) notes.push_back(note);

    const std::vector<std::string> techniques = technique_order(cases);
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
            for (const std::string& t : techniques) h << "<th>" << html_escape(t) << "</th>";
            h << "</tr>\n";
            for (float d : info.distances) {
                const CaseResult* first = find_case(cases, techniques.front(), d, s);
                h << "<tr><th>" << short_number(d) << "<br><small>"
                  << (first ? first->reference_spp : 0) << " spp</small></th>";
                for (const std::string& t : techniques) {
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
        for (const std::string& t : techniques) h << "<th>" << html_escape(t) << "</th>";
        h << "</tr>\n";
        for (float d : info.distances) {
            h << "<tr><th>" << short_number(d) << "</th>";
            std::vector<std::string> columns{to_string(Technique::Reference)};
            columns.insert(columns.end(), techniques.begin(), techniques.end());
            for (const std::string& name : columns) {
                const std::string file = image_name(s, d, name);
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
