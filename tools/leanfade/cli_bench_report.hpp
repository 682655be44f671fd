#pragma once
// Tables and JSON of `leanfade bench`: frame times in the layout of the LEAN paper's Fig. 12 (a
// row per technique, a column per scene), overhead ratios, bake throughput and per-frame
// generation.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_bench_bake.hpp"
#include "leanfade/gl/detail/frame_bench.hpp"

namespace leanfade::cli {

// The machine and the run, printed first and stored under "system".
struct BenchSystem {
    std::string date;  // UTC, ISO 8601
    std::string cpu;   // /proc/cpuinfo model name
    int hardware_threads = 0;
    double load_average[3] = {0.0, 0.0, 0.0};  // at the start of the run
    std::string gl_renderer;                   // empty when no GL was used (--bake only)
    std::string gl_version;
    std::string timing;  // "gpu" / "cpu"
    std::string timing_description;
};
BenchSystem describe_system();

// Per-frame generation at one size.
struct GenerateBenchRow {
    int size = 0;
    std::string storage;
    gl::SampleStats pass;            // compute pass, ms
    gl::SampleStats mipmap;          // glGenerateMipmap, ms
    gl::SampleStats total;           // per frame, pass + mipmap, ms
    double texels_per_second = 0.0;  // top-level texels / median total
};

// One overhead ratio: the frame time of `technique` over that of `baseline` (none: the
// constant-colour floor), the median of per-round ratios.
struct OverheadRatio {
    Technique technique = Technique::Lean;
    std::optional<Technique> baseline;
    double value = 0.0;

    std::string name() const;  // "lean/bump", "fade/floor"
    bool same_pair(const OverheadRatio& other) const {
        return technique == other.technique && baseline == other.baseline;
    }
};

// The ratios reported per scene and per view: each technique against the one its row of the
// technique table names (lean/bump, fade/lean) and every technique against the floor; those
// whose techniques were not measured are left out.
std::vector<OverheadRatio> view_ratios(const gl::ViewResult& view);

std::string frame_tables(const gl::FrameBenchResult& result, const gl::FrameBenchRequest& request);
std::string bake_table(const BakeBenchResult& result);
std::string generate_table(const std::vector<GenerateBenchRow>& rows);
std::string system_header(const BenchSystem& system);

nlohmann::json system_json(const BenchSystem& system);
nlohmann::json frame_json(const gl::FrameBenchResult& result, const gl::FrameBenchRequest& request);
nlohmann::json bake_json(const BakeBenchResult& result);
nlohmann::json generate_json(const std::vector<GenerateBenchRow>& rows);

}  // namespace leanfade::cli
