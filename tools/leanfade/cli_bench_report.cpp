// Tables and JSON of `leanfade bench`.
#include "cli_bench_report.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <thread>

#include "leanfade/gl/detail/figure.hpp"

namespace leanfade::cli {
namespace {

std::string format(const char* pattern, double value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, pattern, value);
    return buffer;
}

// Milliseconds with about four significant digits.
std::string ms_text(double ms) {
    return format(ms < 10.0 ? "%.3f" : (ms < 100.0 ? "%.2f" : "%.1f"), ms);
}

std::string pad(const std::string& text, std::size_t width) {
    return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

std::string rpad_num(const std::string& text, std::size_t width) {
    return text.size() >= width ? " " + text : std::string(width - text.size(), ' ') + text;
}

// The view the per-scene ratios and the Fig. 12 table use: "fill" when measured, else the first.
const gl::ViewResult* headline_view(const gl::SceneResult& scene) {
    if (const gl::ViewResult* fill = scene.find("fill")) return fill;
    return scene.views.empty() ? nullptr : &scene.views.front();
}

std::vector<std::string> measured_names(const gl::FrameBenchResult& result) {
    std::vector<std::string> names;
    for (const gl::SceneResult& s : result.scenes)
        for (const gl::ViewResult& v : s.views)
            for (const gl::TechniqueTiming& t : v.timings)
                if (std::find(names.begin(), names.end(), t.name) == names.end())
                    names.push_back(t.name);
    return names;
}

nlohmann::json stats_json(const gl::SampleStats& s) {
    return {{"median_ms", s.median}, {"p25_ms", s.p25},   {"p75_ms", s.p75}, {"min_ms", s.min},
            {"max_ms", s.max},       {"mean_ms", s.mean}, {"count", s.count}};
}

nlohmann::json ratios_json(const gl::ViewResult& view) {
    nlohmann::json ratios = nlohmann::json::object();
    for (const OverheadRatio& ratio : view_ratios(view)) ratios[ratio.name()] = ratio.value;
    return ratios;
}

}  // namespace

BenchSystem describe_system() {
    BenchSystem s;
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    s.date = date;
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line)) {
        if (line.rfind("model name", 0) == 0) {
            const std::size_t colon = line.find(':');
            if (colon != std::string::npos) s.cpu = line.substr(colon + 2);
            break;
        }
    }
    if (s.cpu.empty()) s.cpu = "unknown";
    s.hardware_threads = int(std::thread::hardware_concurrency());
    if (getloadavg(s.load_average, 3) != 3)
        for (double& l : s.load_average) l = -1.0;
    return s;
}

std::string OverheadRatio::name() const {
    return std::string(to_string(technique)) + "/" +
           (baseline ? std::string(to_string(*baseline)) : std::string(gl::kFloorName));
}

std::vector<OverheadRatio> view_ratios(const gl::ViewResult& view) {
    std::vector<OverheadRatio> ratios;
    for (const TechniqueInfo& row : kTechniques)
        if (row.builds_on != row.id && view.find(row.id) != nullptr &&
            view.find(row.builds_on) != nullptr)
            ratios.push_back({row.id, row.builds_on, view.ratio(row.id, row.builds_on)});
    if (view.floor() != nullptr)
        for (const gl::TechniqueTiming& t : view.timings)
            if (t.technique)
                ratios.push_back({*t.technique, std::nullopt, view.ratio_to_floor(*t.technique)});
    return ratios;
}

std::string system_header(const BenchSystem& s) {
    std::string out = "leanfade bench, " + s.date + "\n";
    out += "CPU: " + s.cpu + " (" + std::to_string(s.hardware_threads) +
           " hardware threads), load average " + format("%.2f", s.load_average[0]) + " " +
           format("%.2f", s.load_average[1]) + " " + format("%.2f", s.load_average[2]) + "\n";
    if (!s.gl_renderer.empty()) {
        out += "GL: " + s.gl_version + " / " + s.gl_renderer + "\n";
        out += "Timing: " + s.timing_description + "\n";
    }
    return out;
}

std::string frame_tables(const gl::FrameBenchResult& result, const gl::FrameBenchRequest& r) {
    const std::vector<std::string> names = measured_names(result);
    const bool cpu_time = result.timing.method == gl::TimingMethod::CpuTime;
    std::string out;
    out += std::string(cpu_time ? "\nCPU time per frame" : "\nFrame time") +
           " with the object filling the screen, " + std::to_string(r.width) + "x" +
           std::to_string(r.height) + ", median of " + std::to_string(r.frames) +
           " interleaved frames after " + std::to_string(r.warmup) +
           " warm-up (LEAN Fig. 12 layout)\n";
    const std::size_t first = 15, cell = 25;
    std::string header = pad("technique", first);
    for (const gl::SceneResult& s : result.scenes) header += pad(s.name, cell);
    out += header + "\n";
    for (const std::string& name : names) {
        std::string row = pad(name, first);
        for (const gl::SceneResult& s : result.scenes) {
            const gl::ViewResult* v = headline_view(s);
            const gl::TechniqueTiming* t = v != nullptr ? v->find(name) : nullptr;
            std::string text = "-";
            if (t != nullptr) {
                text = format("%8.3f ms", t->stats.median);
                if (!cpu_time) text += format(" %8.1f FPS", t->fps);
            }
            row += pad(text, cell);
        }
        out += row + "\n";
    }

    out += "\nOverhead ratios of frame times (median of per-round ratios, same view)\n";
    header = pad("ratio", first);
    for (const gl::SceneResult& s : result.scenes) header += pad(s.name, cell);
    out += header + "\n";
    std::vector<OverheadRatio> pairs;  // every pair measured in some scene, first seen first
    for (const gl::SceneResult& s : result.scenes)
        if (const gl::ViewResult* v = headline_view(s))
            for (const OverheadRatio& ratio : view_ratios(*v))
                if (std::none_of(pairs.begin(), pairs.end(),
                                 [&](const OverheadRatio& p) { return p.same_pair(ratio); }))
                    pairs.push_back(ratio);
    for (const OverheadRatio& pair : pairs) {
        std::string row = pad(pair.name(), first);
        for (const gl::SceneResult& s : result.scenes) {
            std::string text = "-";
            if (const gl::ViewResult* v = headline_view(s))
                for (const OverheadRatio& ratio : view_ratios(*v))
                    if (ratio.same_pair(pair)) text = format("%.3f", ratio.value);
            row += pad(text, cell);
        }
        out += row + "\n";
    }

    out += "\nPer view: median ms [p25..p75]; coverage = pixels the object covers\n";
    for (const gl::SceneResult& s : result.scenes) {
        out += s.name + " (" + std::to_string(s.triangles) + " triangles, " +
               std::to_string(s.vertices) + " vertices)\n";
        std::string h = "  " + pad("view", 7) + pad("fov", 6) + pad("cover", 7);
        for (const std::string& name : names) h += pad(name, 25);
        out += h + "\n";
        for (const gl::ViewResult& v : s.views) {
            std::string row = "  " + pad(v.name, 7) + pad(format("%.1f", v.fov_y_degrees), 6) +
                              pad(format("%.0f%%", 100.0 * v.coverage), 7);
            for (const std::string& name : names) {
                const gl::TechniqueTiming* t = v.find(name);
                row += pad(t == nullptr
                               ? "-"
                               : rpad_num(ms_text(t->stats.median), 6) + " [" +
                                     ms_text(t->stats.p25) + ".." + ms_text(t->stats.p75) + "]",
                           25);
            }
            out += row + "\n";
        }
    }
    return out;
}

std::string bake_table(const BakeBenchResult& b) {
    std::string out =
        "\nBake throughput (bake_packed: float input -> 16-bit LEAN map with every "
        "level, " +
        std::to_string(b.threads) + " threads, AVX2 " + (b.simd ? "on" : "off") + ")\n";
    out += "copy bandwidth (memcpy of " + std::to_string(b.copy_bytes >> 20) +
           " MiB, read + write): " + format("%.0f MB/s", b.copy_bytes_per_second / 1e6) + "\n";
    out += "input   size     runs  median s   MB/s      Mtexel/s  floor s   x floor\n";
    for (const BakeBenchRow& row : b.rows) {
        out += pad(row.input, 8) + pad(std::to_string(row.size) + "^2", 9) +
               pad(std::to_string(row.runs), 6) + pad(format("%.4f", row.median_seconds), 11) +
               pad(format("%.0f", row.megabytes_per_second), 10) +
               pad(format("%.1f", row.texels_per_second / 1e6), 10) +
               pad(format("%.4f", row.floor_seconds), 10) + format("%.2f", row.floor_ratio) + "\n";
    }
    return out;
}

std::string generate_table(const std::vector<GenerateBenchRow>& rows) {
    std::string out =
        "\nPer-frame LEAN map generation on the GPU (compute pass + glGenerateMipmap; "
        "LEAN paper's per-frame generation)\n";
    out += "size     storage  pass ms    mipmap ms  total ms   Mtexel/s\n";
    for (const GenerateBenchRow& row : rows)
        out += pad(std::to_string(row.size) + "^2", 9) + pad(row.storage, 9) +
               pad(format("%.3f", row.pass.median), 11) +
               pad(format("%.3f", row.mipmap.median), 11) +
               pad(format("%.3f", row.total.median), 11) +
               format("%.1f", row.texels_per_second / 1e6) + "\n";
    return out;
}

nlohmann::json system_json(const BenchSystem& s) {
    nlohmann::json j = {
        {"date", s.date},
        {"cpu", s.cpu},
        {"hardware_threads", s.hardware_threads},
        {"load_average", {s.load_average[0], s.load_average[1], s.load_average[2]}}};
    if (!s.gl_renderer.empty()) {
        j["gl_renderer"] = s.gl_renderer;
        j["gl_version"] = s.gl_version;
        j["timing"] = s.timing;
        j["timing_description"] = s.timing_description;
    }
    return j;
}

nlohmann::json frame_json(const gl::FrameBenchResult& result, const gl::FrameBenchRequest& r) {
    nlohmann::json scenes = nlohmann::json::object();
    for (const gl::SceneResult& s : result.scenes) {
        nlohmann::json views = nlohmann::json::object();
        for (const gl::ViewResult& v : s.views) {
            nlohmann::json techniques = nlohmann::json::object();
            for (const gl::TechniqueTiming& t : v.timings) {
                nlohmann::json tj = stats_json(t.stats);
                tj["fps"] = t.fps;
                tj["frame_ms"] = t.frame_ms;
                techniques[t.name] = tj;
            }
            views[v.name] = {{"distance", v.distance},
                             {"fov_y_degrees", v.fov_y_degrees},
                             {"coverage", v.coverage},
                             {"techniques", techniques},
                             {"ratios", ratios_json(v)}};
        }
        const gl::ViewResult* headline = headline_view(s);
        scenes[s.name] = {
            {"triangles", s.triangles},
            {"vertices", s.vertices},
            {"ratios_view", headline != nullptr ? headline->name : ""},
            {"ratios", headline != nullptr ? ratios_json(*headline) : nlohmann::json::object()},
            {"views", views}};
    }
    std::vector<std::string> techniques;
    for (gl::Technique t : r.techniques) techniques.push_back(gl::to_string(t));
    return {{"size", {r.width, r.height}},
            {"frames", r.frames},
            {"warmup", r.warmup},
            {"techniques", techniques},
            {"floor", r.floor},
            {"distances", r.distances},
            {"framebuffer", "RGBA8 + DEPTH24, offscreen"},
            {"interleaving",
             "each round draws every technique once, order rotated by one per round; ratios are "
             "medians of per-round ratios"},
            {"timing", gl::to_string(result.timing.method)},
            {"scenes", scenes}};
}

nlohmann::json bake_json(const BakeBenchResult& b) {
    nlohmann::json rows = nlohmann::json::array();
    for (const BakeBenchRow& row : b.rows)
        rows.push_back({{"input", row.input},
                        {"size", row.size},
                        {"runs", row.runs},
                        {"median_seconds", row.median_seconds},
                        {"min_seconds", row.min_seconds},
                        {"input_bytes", row.input_bytes},
                        {"output_bytes", row.output_bytes},
                        {"megabytes_per_second", row.megabytes_per_second},
                        {"texels_per_second", row.texels_per_second},
                        {"floor_seconds", row.floor_seconds},
                        {"floor_ratio", row.floor_ratio}});
    return {{"function", "bake_packed"},
            {"source", "built-in bumps (seed 1) tiled from 1024, float texels"},
            {"storage", b.storage},
            {"threads", b.threads},
            {"avx2", b.simd},
            {"copy_bytes", b.copy_bytes},
            {"copy_bytes_per_second", b.copy_bytes_per_second},
            {"rows", rows}};
}

nlohmann::json generate_json(const std::vector<GenerateBenchRow>& rows) {
    nlohmann::json out = nlohmann::json::array();
    for (const GenerateBenchRow& row : rows)
        out.push_back({{"size", row.size},
                       {"storage", row.storage},
                       {"pass", stats_json(row.pass)},
                       {"mipmap", stats_json(row.mipmap)},
                       {"total", stats_json(row.total)},
                       {"texels_per_second", row.texels_per_second}});
    return out;
}

}  // namespace leanfade::cli
