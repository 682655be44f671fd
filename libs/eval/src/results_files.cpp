// Results files of `leanfade eval`: CSV and JSON, written and read back (--replot).
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

namespace {

std::vector<std::string> technique_name_list(const std::vector<Technique>& techniques) {
    std::vector<std::string> names;
    for (Technique t : techniques) names.emplace_back(to_string(t));
    return names;
}

// A technique of results.json: one that a sweep measures (is_measured_technique).
Technique measured_technique(const std::string& name, const std::string& path) {
    for (Technique t : approximating_techniques())
        if (name == to_string(t)) return t;
    throw Error(path, "unknown technique '" + printable(name) + "' (expected " +
                          technique_names(approximating_techniques()) + ")");
}

}  // namespace

std::string results_csv(const std::vector<CaseResult>& cases) {
    std::string out = "technique,distance,shininess,energy,rmse,ssim,flicker,energy_total,seeds,"
                      "energy_spread,energy_total_spread\n";
    for (const CaseResult& c : cases)
        out += std::string(to_string(c.technique)) + "," + number(c.distance) + "," + number(c.shininess) + "," +
               number(c.energy) + "," + number(c.rmse) + "," + number(c.ssim) + "," +
               number(c.flicker) + "," + number(c.energy_total) + "," + std::to_string(c.seeds) +
               "," + number(c.energy_spread) + "," + number(c.energy_total_spread) + "\n";
    return out;
}

std::string results_json(const SweepInfo& info, const std::vector<CaseResult>& cases) {
    nlohmann::json sweep = {
        {"scene", info.scene},
        {"bumps", info.bumps},
        {"techniques", technique_name_list(info.techniques)},
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
        {"energy_total",
         "specular radiance summed over the whole image (every covered pixel, the reference's "
         "partly covered edge pixels with their share, black background) / the reference's "
         "(frame 0)"},
        {"seeds",
         "independent bump maps of the built-in set (eval --seeds); above 1, energy and "
         "energy_total are ratios of sums over the maps, rmse, ssim and flicker their means"},
        {"energy_spread", "standard deviation of energy across the seeds' maps"},
        {"energy_total_spread", "standard deviation of energy_total across the seeds' maps"},
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
        rows.push_back({{"technique", to_string(c.technique)},
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
                        {"reference_energy_error", json_number(c.reference_energy_error)},
                        {"energy_total", json_number(c.energy_total)},
                        {"specular_total", json_number(c.specular_total)},
                        {"reference_specular_total", json_number(c.reference_specular_total)},
                        {"seeds", c.seeds},
                        {"energy_spread", json_number(c.energy_spread)},
                        {"energy_total_spread", json_number(c.energy_total_spread)}});
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
        info.techniques.clear();
        for (const std::string& name : s.at("techniques").get<std::vector<std::string>>())
            info.techniques.push_back(measured_technique(name, path));
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
            r.technique = measured_technique(c.at("technique").get<std::string>(), path);
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
            // Results written before these keys: one map, no whole-image sums.
            r.energy_total = number_or_nan(c.value("energy_total", nlohmann::json()));
            r.specular_total = number_or_nan(c.value("specular_total", nlohmann::json()));
            r.reference_specular_total =
                number_or_nan(c.value("reference_specular_total", nlohmann::json()));
            r.seeds = c.value("seeds", 1);
            if (r.seeds < 1) throw Error(path, "a case's seeds must be at least 1");
            r.energy_spread = number_or_nan(c.value("energy_spread", nlohmann::json()));
            r.energy_total_spread =
                number_or_nan(c.value("energy_total_spread", nlohmann::json()));
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

}  // namespace leanfade::eval
