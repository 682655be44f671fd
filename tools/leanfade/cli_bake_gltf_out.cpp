// `leanfade bake SCENE.gltf|SCENE.glb -o OUT.gltf|OUT.glb` (cli_bake_gltf_out.hpp): the flags
// checked, scene::write_filtered_gltf called, its progress and report printed.
#include "cli_bake_gltf_out.hpp"

#include <cstdio>

#include "cli_flags.hpp"
#include "command.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/scene/gltf.hpp"

namespace leanfade::cli {

int run_bake_gltf_out(const GltfBakeArgs& args, const std::string& output) {
    if (!args.refused_flags.empty())
        throw Error(args.refused_flags.front(),
                    "does not apply to a glTF scene (its normal textures are OpenGL-convention "
                    "normal maps baked to KTX2)");
    if (!args.out_dir.empty())
        throw Error("--out-dir", "give -o OUT.gltf|OUT.glb or --out-dir, not both");
    scene::FilteredGltfSettings settings;
    settings.bake = gltf_bake_settings(args.bits, args.max_size, args.threads, args.strict_normals);
    settings.supercompression = args.supercompression;
    settings.zstd_level = args.zstd_level;
    settings.compression = args.compression;
    settings.durability = args.fsync ? io::Durability::Flush : io::Durability::Rename;
    settings.summary_path = args.json;

    const bool terminal = stderr_is_terminal();
    const auto progress = [terminal](std::size_t index, std::size_t count,
                                     const std::string& material) {
        if (terminal)
            std::fprintf(stderr, "\r[%zu/%zu] filtering %s...\033[K", index + 1, count,
                         terminal_text(material).c_str());
    };
    scene::FilteredGltfReport report;
    const auto print_found = [&] {
        if (terminal) std::fprintf(stderr, "\r\033[K");
        print_warnings(args.input, report.warnings);
        for (const std::string& image : report.other_convention)
            print_warnings(args.input, {gltf_convention_warning(image)});
    };
    try {
        scene::write_filtered_gltf(args.input, output, settings, &report, progress);
    } catch (const Error&) {
        print_found();
        throw;
    }
    print_found();
    std::printf("%s -> %s: %zu materials filtered\n", terminal_text(args.input).c_str(),
                terminal_text(output).c_str(), report.materials);
    for (const std::string& file : report.written)
        std::printf("  wrote %s\n", terminal_text(file).c_str());
    return 0;
}

}  // namespace leanfade::cli
