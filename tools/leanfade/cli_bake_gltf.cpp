// glTF scenes on the command line (cli_bake_gltf.hpp).
#include "cli_bake_gltf.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "cli_flags.hpp"
#include "command.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/detail/lean_map_cache.hpp"

namespace leanfade::cli {
namespace {

namespace fs = std::filesystem;

}  // namespace

scene::GltfBakeSettings gltf_bake_settings(const StoragePolicy& bits, int max_size, int threads,
                                           bool strict_normals) {
    scene::GltfBakeSettings settings;
    settings.strict_normals = strict_normals;
    // "auto" (bake's choice per map) is 16-bit UNORM here: normal textures have bounded slopes.
    settings.storage = bits.automatic ? Storage::Unorm16 : bits.storage;
    if (max_size > 0) settings.max_image_size = max_size;
    settings.threads = threads;
    settings.cache_folder = scene::default_lean_cache_folder();
    return settings;
}

void print_warnings(const std::string& path, const std::vector<std::string>& warnings) {
    for (const std::string& w : warnings)
        std::fprintf(stderr, "leanfade: %s\n", terminal_text(path + ": " + w).c_str());
}

int run_bake_gltf(const GltfBakeArgs& args) {
    if (!args.refused_flags.empty())
        throw Error(args.refused_flags.front(),
                    "does not apply to a glTF scene (its normal textures are OpenGL-convention "
                    "normal maps baked to KTX2)");
    const scene::GltfBakeSettings settings =
        gltf_bake_settings(args.bits, args.max_size, args.threads, args.strict_normals);
    // A missing --out-dir is created, and removed again if the run writes nothing into it.
    const io::CreatedFolders out_folder(args.out_dir);
    const scene::GltfScene gltf = scene::load_gltf(args.input);
    print_warnings(args.input, gltf.warnings);

    // One output per (normal image, scale), named after the first material that uses it.
    struct Job {
        int image = -1;
        float scale = 1.0f;
        std::string material;
        std::string output;
    };
    std::vector<Job> jobs;
    std::map<std::pair<int, float>, std::size_t> seen;
    const fs::path folder =
        args.out_dir.empty() ? fs::path(args.input).parent_path() : fs::path(args.out_dir);
    const std::string stem = fs::path(args.input).stem().string();
    // Each output name once: a name already taken (by an earlier material of the same name
    // part, or by a material named like a numbered one, "a", "a", "a-2") gets the first free
    // number.
    std::set<std::string> names;
    for (const scene::GltfMaterial& m : gltf.materials) {
        if (m.normal_image < 0) continue;
        if (seen.count({m.normal_image, m.normal_scale}) != 0) continue;
        seen[{m.normal_image, m.normal_scale}] = jobs.size();
        const std::string name = scene::unique_name(scene::file_name_part(m.name), "", names);
        jobs.push_back({m.normal_image, m.normal_scale, m.name,
                        (folder / (stem + "." + name + ".ktx2")).string()});
    }
    if (jobs.empty()) throw Error(args.input, "no material of the scene has a normal texture");

    io::OutputPlan plan;
    plan.add_input(args.input);
    for (const std::string& file : scene::gltf_referenced_files(args.input)) plan.add_input(file);
    for (const Job& j : jobs) plan.add_output(j.output, "material '" + j.material + "'");
    if (!args.json.empty()) plan.add_output(args.json, "--json");
    plan.check();

    const io::Durability durability = args.fsync ? io::Durability::Flush : io::Durability::Rename;
    io::OutputTransaction outputs(durability);
    io::WriteOptions write_options;
    write_options.durability = durability;
    write_options.supercompression = args.supercompression;
    write_options.zstd_level = args.zstd_level;
    nlohmann::json summaries = nlohmann::json::array();
    std::string report;  // printed once the outputs are published
    const bool progress = stderr_is_terminal();
    try {
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            const Job& j = jobs[i];
            if (progress)
                std::fprintf(stderr, "\r[%zu/%zu] baking %s...\033[K", i + 1, jobs.size(),
                             terminal_text(j.material).c_str());
            const auto start = std::chrono::steady_clock::now();
            bool cached = false;
            std::string cache_warning;
            const PackedLeanMap map = scene::bake_normal_texture(gltf, j.image, j.scale, settings,
                                                                 &cached, &cache_warning);
            io::write_ktx2(outputs.stage(j.output), map, write_options);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (progress) std::fprintf(stderr, "\r\033[K");
            if (!cache_warning.empty()) print_warnings(args.input, {"cache: " + cache_warning});
            const std::string& image = gltf.images[std::size_t(j.image)].name;
            char line[256];
            report += terminal_text(args.input) + ": material '" + terminal_text(j.material) +
                      "' (" + terminal_text(image) + ", scale ";
            std::snprintf(line, sizeof line, "%g", double(j.scale));
            report += std::string(line) + ") -> " + terminal_text(j.output) + "\n";
            std::snprintf(line, sizeof line, "  %dx%d, %zu levels, sc = %.6g, %s, %.3f s\n",
                          map.levels[0].width, map.levels[0].height, map.levels.size(),
                          double(map.scale), cached ? "from the cache" : "baked", seconds);
            report += line;
            if (map.normal_repairs.any())
                report += "  " + terminal_text(normal_repairs_note(image, map.normal_repairs)) + "\n";
            if (map.source_looks_flipped)
                print_warnings(args.input, {gltf_convention_warning(image)});
            summaries.push_back({{"input", args.input},
                                 {"material", j.material},
                                 {"image", image},
                                 {"normal_scale", j.scale},
                                 {"output", j.output},
                                 {"width", map.levels[0].width},
                                 {"height", map.levels[0].height},
                                 {"levels", map.levels.size()},
                                 {"scale", map.scale},
                                 {"from_cache", cached},
                                 {"padding_texels", map.normal_repairs.padding_texels},
                                 {"raised_normals", map.normal_repairs.raised_texels},
                                 {"looks_like_other_convention", map.source_looks_flipped},
                                 {"seconds", seconds}});
        }
        if (!args.json.empty()) {
            const std::string text =
                summaries.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
            io::AtomicFile file(outputs.stage(args.json), durability);
            file.write(text.data(), text.size());
            file.commit();
        }
    } catch (const Error& e) {
        throw outputs.named(e);  // the output's name, not its temporary's
    }
    outputs.publish();
    std::fwrite(report.data(), 1, report.size(), stdout);
    return 0;
}

}  // namespace leanfade::cli
