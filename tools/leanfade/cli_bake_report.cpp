// The reports of `leanfade bake` (cli_bake_report.hpp).
#include "cli_bake_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli_flags.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/plateau.hpp"

namespace leanfade::cli {
namespace {

// Every step-th texel of the first 3 channels, at most 512 per side: enough for the convention
// check, in bounded memory for any input.
Image convention_sample(const std::variant<Image, UnormImage>& input) {
    const Image* floats = std::get_if<Image>(&input);
    const UnormImage* unorm = std::get_if<UnormImage>(&input);
    const int w = floats != nullptr ? floats->width : unorm->width;
    const int h = floats != nullptr ? floats->height : unorm->height;
    const int channels = floats != nullptr ? floats->channels : unorm->channels;
    const int step = std::max(1, (std::max(w, h) + 511) / 512);
    Image sample((w + step - 1) / step, (h + step - 1) / step, 3);
    if (channels < 3) return Image();
    for (int y = 0; y < sample.height; ++y)
        for (int x = 0; x < sample.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const std::size_t i =
                    (std::size_t(y * step) * std::size_t(w) + std::size_t(x * step)) *
                        std::size_t(channels) +
                    std::size_t(c);
                sample.at(x, y, c) = floats != nullptr
                                         ? floats->pixels[i]
                                         : float(unorm->samples[i]) / float(unorm->max_value);
            }
    return sample;
}

}  // namespace

BakeReport bake_report(const std::string& input, const std::string& output,
                       const PackedBakeResult& baked, double seconds,
                       bool looks_like_other_convention) {
    BakeReport report;
    report.input = input;
    report.output = output;
    report.summary = baked.summary;
    report.source = baked.source;
    report.clamped_texels = baked.clamped_texels;
    report.normal_repairs = baked.packed.normal_repairs;
    report.texels_beyond_scale = baked.texels_beyond_scale;
    report.roughness_baked = baked.packed.roughness_baked;
    report.storage = baked.packed.storage;
    report.probe_unorm16_psnr = baked.probe_unorm16_psnr;
    report.probe_float16_psnr = baked.probe_float16_psnr;
    report.seconds = seconds;
    report.looks_like_other_convention = looks_like_other_convention;
    return report;
}

void print_bake_report(const BakeReport& report) {
    const LeanMapSummary& s = report.summary;
    std::printf("%s -> %s\n", terminal_text(report.input).c_str(),
                terminal_text(report.output).c_str());
    std::printf("  %dx%d, %d levels, %s map, sc = %.6g, storage %s\n", s.width, s.height, s.levels,
                to_string(report.source), s.scale, to_string(report.storage));
    if (!std::isnan(report.probe_unorm16_psnr))
        std::printf("  storage by measurement (--bits auto): the map's highlights %.1f dB from "
                    "32f in 16-bit UNORM, %.1f dB in 16f\n",
                    report.probe_unorm16_psnr, report.probe_float16_psnr);
    std::printf("  slope |B|: mean %.4f, max %.4f\n", s.mean_slope, s.max_slope);
    std::printf("  coarsest level: covariance (xx %.5f, yy %.5f, xy %.5f), anisotropy %.3g\n",
                s.coarsest_covariance.x, s.coarsest_covariance.y, s.coarsest_covariance.z,
                s.coarsest_anisotropy);
    if (s.plateau_rule_epsilon > 0.0f) {
        std::printf("  flat (two-lobe LEAN's plateaus): %.3g %% of the texels (epsilon %.3g, radius "
                    "%dx%d texels)\n",
                    100.0 * double(s.flat_fraction), double(s.plateau_rule_epsilon),
                    s.plateau_radius_x, s.plateau_radius_y);
        if (s.spike_window.shape != SpikeWindowShape::None)
            std::printf("  spike: the slopes within a %s of radius %.3g around (%.3g, %.3g)%s, "
                        "by fit (far highlight within x%.3g of the map's own, x%.3g with the "
                        "plateaus alone)\n",
                        to_string(s.spike_window.shape), double(s.spike_window.radius),
                        double(s.spike_window.anchor.x), double(s.spike_window.anchor.y),
                        s.spike_window.with_plateaus ? " and the plateaus" : "",
                        std::exp(double(s.spike_fit_error)),
                        std::exp(double(s.plateaus_fit_error)));
        std::printf("  spike's share (two-lobe LEAN's f): %.3g %%%s\n",
                    100.0 * double(s.plateau_fraction),
                    s.plateau_fraction > 0.0f ? ""
                                              : "; no plateau layer stored: two-lobe shades as LEAN");
    }
    if (report.clamped_texels > 0)
        std::printf("  %zu normals had z < %.4f and were raised to it\n", report.clamped_texels,
                    kMinNormalZ);
    if (report.normal_repairs.any())
        std::printf("  %s\n", normal_repairs_note(report.input, report.normal_repairs).c_str());
    const std::uint64_t beyond = report.texels_beyond_scale;
    if (beyond > 0) {
        const double percent = 100.0 * double(beyond) / (double(s.width) * double(s.height));
        const bool unorm = report.storage == Storage::Unorm8 || report.storage == Storage::Unorm16;
        std::printf("  %llu texels (%.3g %%) have a slope component above sc (up to %.4g): %s\n",
                    static_cast<unsigned long long>(beyond), percent, s.max_slope,
                    unorm ? "clamped to sc in this UNORM map (docs/ktx2.md, \"Choosing storage "
                            "and sc\")"
                          : "kept, beyond [0, 1], by the float storage");
    }
    for (const std::string& file : report.also_written)
        std::printf("  also wrote %s\n", terminal_text(file).c_str());
    std::printf("  %.3f s\n", report.seconds);
}

namespace {
// A PSNR for JSON: the number, or "inf" where nothing changed.
nlohmann::json decibels_json(double db) {
    return std::isfinite(db) ? nlohmann::json(db) : nlohmann::json("inf");
}
}  // namespace

nlohmann::json bake_report_json(const BakeReport& report) {
    const LeanMapSummary& s = report.summary;
    return {{"input", report.input},
            {"output", report.output},
            {"source", to_string(report.source)},
            {"width", s.width},
            {"height", s.height},
            {"levels", s.levels},
            {"scale", s.scale},
            {"mean_slope", s.mean_slope},
            {"max_slope", s.max_slope},
            {"coarsest_covariance",
             {s.coarsest_covariance.x, s.coarsest_covariance.y, s.coarsest_covariance.z}},
            {"coarsest_anisotropy", std::isfinite(s.coarsest_anisotropy)
                                        ? nlohmann::json(s.coarsest_anisotropy)
                                        : nlohmann::json("inf")},
            {"clamped_normals", report.clamped_texels},
            {"padding_texels", report.normal_repairs.padding_texels},
            {"raised_normals", report.normal_repairs.raised_texels},
            {"texels_beyond_sc", report.texels_beyond_scale},
            {"storage", to_string(report.storage)},
            {"storage_probe_psnr",
             std::isnan(report.probe_unorm16_psnr)
                 ? nlohmann::json(nullptr)
                 : nlohmann::json{{"16", decibels_json(report.probe_unorm16_psnr)},
                                  {"16f", decibels_json(report.probe_float16_psnr)}}},
            {"roughness_baked", report.roughness_baked},
            {"plateau",
             s.plateau_rule_epsilon > 0.0f
                 ? nlohmann::json{{"fraction", s.plateau_fraction},
                                  {"flat_fraction", s.flat_fraction},
                                  {"window",
                                   s.spike_window.shape == SpikeWindowShape::None
                                       ? nlohmann::json(nullptr)
                                       : nlohmann::json{{"shape", to_string(s.spike_window.shape)},
                                                        {"radius", s.spike_window.radius},
                                                        {"anchor", {s.spike_window.anchor.x,
                                                                    s.spike_window.anchor.y}},
                                                        {"with_plateaus",
                                                         s.spike_window.with_plateaus}}},
                                  {"fit_error", s.spike_fit_error},
                                  {"plateaus_fit_error", s.plateaus_fit_error},
                                  {"epsilon", s.plateau_rule_epsilon},
                                  {"radius", {s.plateau_radius_x, s.plateau_radius_y}},
                                  {"layer_stored", s.plateau_fraction > 0.0f}}
                 : nlohmann::json(nullptr)},
            {"seconds", report.seconds},
            {"looks_like_other_convention", report.looks_like_other_convention},
            {"also_written", report.also_written}};
}

bool warn_if_other_convention(const std::string& name, const std::variant<Image, UnormImage>& input,
                              NormalConvention convention) {
    const NormalConventionCheck check =
        check_normal_convention(convention_sample(input), convention);
    if (!check.looks_flipped()) return false;
    std::fprintf(stderr, "leanfade bake: warning: %s\n",
                 convention_warning(name, convention == NormalConvention::DirectX,
                                    check.curl_as_read / std::max(check.curl_flipped, 1e-30))
                     .c_str());
    return true;
}

}  // namespace leanfade::cli
