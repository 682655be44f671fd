// Results files of `leanfade eval`: the sweep lists and the text helpers of every results file
// (results_internal.hpp); CSV and JSON: results_files.cpp; plots: results_plots.cpp; the report:
// results_report.cpp.
#include "leanfade/eval/results.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
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
#include "leanfade/core/detail/camera.hpp"

namespace leanfade::eval {

namespace results_detail {


float round_significant(double v, int digits) {
    if (v == 0.0) return 0.0f;
    const double scale = std::pow(10.0, double(digits - 1) - std::floor(std::log10(std::abs(v))));
    return float(std::round(v * scale) / scale);
}

std::string number(double v) {
    if (std::isnan(v)) return "nan";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return buffer;
}

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

// The plots' colours, a technique's at its position in kTechniques (bump red, Toksvig purple,
// CLEAN brown, LEAN blue, fade green, roughness MIPs orange, two-lobe cyan, the truth black); a
// technique added to the table takes the next spare one.
constexpr std::array<std::string_view, 12> kPlotColors{
    "#d62728", "#9467bd", "#8c564b", "#1f77b4", "#2ca02c", "#ff7f0e",
    "#17becf", "#000000", "#e377c2", "#7f7f7f", "#bcbd22", "#aec7e8",
};
static_assert(kPlotColors.size() >= kTechniques.size(), "a plot colour for every technique");

std::string technique_color(Technique technique) {
    return std::string(kPlotColors[std::size_t(technique)]);
}

std::vector<Technique> technique_order(const std::vector<CaseResult>& cases) {
    std::vector<Technique> names;
    for (const CaseResult& c : cases)
        if (std::find(names.begin(), names.end(), c.technique) == names.end())
            names.push_back(c.technique);
    return names;
}

const CaseResult* find_case(const std::vector<CaseResult>& cases, Technique technique,
                            float distance, float shininess) {
    for (const CaseResult& c : cases)
        if (c.technique == technique && c.distance == distance && c.shininess == shininess)
            return &c;
    return nullptr;
}

const std::vector<Metric>& metrics() {
    static const std::vector<Metric> list = {
        {"energy", "Specular energy / reference (clipped to 0.01-100)", "energy ratio", true, 1.0,
         "[0.01:100]", &CaseResult::energy},
        {"energy_total", "Specular energy over every covered pixel / reference (clipped to 0.01-100)",
         "energy ratio", true, 1.0, "[0.01:100]", &CaseResult::energy_total},
        {"rmse", "Relative RMSE vs reference (linear radiance)", "RMSE / reference mean", true, NAN,
         "[*:*]", &CaseResult::rmse},
        {"ssim", "SSIM vs reference (sRGB)", "SSIM", false, 1.0, "[0:1.02]", &CaseResult::ssim},
        {"flicker", "Flicker relative to the reference (clipped to 0.1-10)", "flicker ratio", true,
         1.0, "[0.1:10]", &CaseResult::flicker},
    };
    return list;
}

std::string image_name(float shininess, float distance, Technique technique) {
    // Appended piece by piece: "s" + std::string trips GCC 12's -Wrestrict false positive.
    std::string name = "s";
    name += short_number(shininess);
    name += "_d";
    name += short_number(distance);
    name += "_";
    name += to_string(technique);
    name += ".png";
    return name;
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

std::string printable(const std::string& text) {
    std::string out;
    for (char c : text.substr(0, 40)) out += is_control(c) ? '?' : c;
    return text.size() > 40 ? out + "..." : out;
}

void validate_results(const std::string& path, const SweepInfo& info,
                      const std::vector<CaseResult>& cases) {
    auto check_positive = [&](double value, const char* what) {
        if (!(std::isfinite(value) && value > 0.0))
            throw Error(path,
                        std::string(what) + " must be a finite number > 0, got " + number(value));
    };
    for (float d : info.distances) check_positive(d, "a distance");
    for (float s : info.shininesses) check_positive(s, "a shininess");
    for (const CaseResult& c : cases) {
        check_positive(c.distance, "a case's distance");
        check_positive(c.shininess, "a case's shininess");
    }
}

}  // namespace results_detail

using namespace results_detail;

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

std::vector<float> parse_distance_sweep(const std::string& text, const std::string& setting) {
    const std::string& flag = setting;
    const std::vector<std::string> range = split(text, ':');
    std::vector<float> result;
    if (range.size() == 3) {
        double a = 0.0, b = 0.0, n = 0.0;
        if (!parse_finite(range[0], a) || !parse_finite(range[1], b) ||
            !parse_finite(range[2], n) || n != std::floor(n))
            throw Error::setting(flag,
                                 "expected A:B:N (N whole) or a comma list, got '" + text + "'");
        if (!(a > 1.0) || !(b > a) || n < 1.0 || n > 1000.0 || b > kMaxCameraDistance)
            throw Error::setting(
                flag,
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
            throw Error::setting(
                flag, "A:B:N: " + range[2] + " distances from " + range[0] + " to " + range[1] +
                          " are closer than float numbers tell apart; give fewer or a "
                          "wider range");
    } else if (range.size() == 1) {
        for (const std::string& part : split(text, ',')) {
            double d = 0.0;
            if (!parse_finite(part, d))
                throw Error::setting(
                    flag, "expected A:B:N or comma-separated numbers, got '" + text + "'");
            check_camera_distance(d, flag, part);
            result.push_back(float(d));
        }
    } else {
        throw Error::setting(flag, "expected A:B:N or a comma list, got '" + text + "'");
    }
    for (std::size_t i = 0; i < result.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (result[i] == result[j])
                throw Error::setting(flag, "distance " + short_number(result[i]) + " given twice");
    return result;
}

std::vector<float> parse_shininess_list(const std::string& text, const std::string& setting) {
    const std::string& flag = setting;
    std::vector<float> result;
    for (const std::string& part : split(text, ',')) {
        double s = 0.0;
        if (!parse_finite(part, s) || !(s > 0.0) || s > 1e7)
            throw Error::setting(
                flag, "expected comma-separated exponents in (0, 1e7], got '" + text + "'");
        if (std::find(result.begin(), result.end(), float(s)) != result.end())
            throw Error::setting(flag, "shininess " + part + " given twice");
        result.push_back(float(s));
    }
    return result;
}

}  // namespace leanfade::eval
