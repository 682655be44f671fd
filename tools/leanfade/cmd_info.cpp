// leanfade info: any KTX2 file's header, levels, format descriptor and key/values, and what it is:
// a LEAN map (with its moment statistics), one of leanfade's other textures, or another writer's.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "command.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/io/detail/block_compression.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"

namespace leanfade::cli {
namespace {

std::string percent_text(float fraction) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g %%", 100.0 * double(fraction));
    return text;
}

// The engine texture a LEANFADEcontent value names ("roughness v1", ...; bake --roughness-out,
// --anisotropy-out), if any.
std::optional<io::EngineTexture> engine_texture_of(const std::string& content) {
    for (const io::EngineTexture texture :
         {io::EngineTexture::Roughness, io::EngineTexture::Normal, io::EngineTexture::Anisotropy})
        if (content == std::string(io::to_string(texture)) + " v1") return texture;
    return std::nullopt;
}

// An engine texture's levels: RGBA8, or the block format of `texture` under --compress
// (leanfade/io/detail/block_compression.hpp).
void read_engine_texture(const std::string& path, const io::Ktx2Info& info,
                         io::EngineTexture texture) {
    for (const io::BlockCompression compression : {io::BlockCompression::Bc, io::BlockCompression::Astc}) {
        const io::BlockFormat& format = io::block_format(compression, texture);
        if (info.vk_format == format.vk_format) {
            io::read_ktx2_compressed(path, format);
            return;
        }
    }
    io::read_ktx2_rgba8(path);
}

// Every check first, then the output: a refused file prints its one-line error and nothing
// else. Any KTX 2.0 file passes inspect_ktx2's structural checks or is refused; a file that says
// it is one of leanfade's (LEANFADElayout, LEANFADEcontent) must also pass the checks of its
// reader (for a LEAN map, those of `--bumps`).
int run_info(const std::string& path, int max_size) {
    io::ReadOptions options;
    options.max_dimension = max_size;
    const io::Ktx2Info info = io::inspect_ktx2(path);
    const std::string* layout = info.find(io::kLayoutKey);
    const std::string* content = info.find(io::kKeyTextureContent);
    std::string kind, moments;
    if (layout != nullptr && io::is_lean_layout_name(*layout)) {
        const PackedLeanMap map = io::read_ktx2(path, options);
        const LeanMapSummary s = summarize(unpack_lean_map(map));
        kind = "a LEAN map (LEANFADElayout '" + *layout + "', " + to_string(map.encoding) +
               " encoding)" +
               (map.has_plateau() ? ", with two-lobe LEAN's plateau layer (epsilon " +
                                        shortest_text(map.plateau_epsilon) + "): " +
                                        percent_text(plateau_fraction(map)) +
                                        " of the texels in the spike"
                                  : ", without a plateau layer (two-lobe LEAN shades it as LEAN)");
        char line[300];
        std::snprintf(line, sizeof line,
                      "moments: slope |B| mean %.4f, max %.4f; coarsest covariance (xx %.5f, yy "
                      "%.5f, xy %.5f), anisotropy %.3g\n",
                      s.mean_slope, s.max_slope, s.coarsest_covariance.x,
                      s.coarsest_covariance.y, s.coarsest_covariance.z, s.coarsest_anisotropy);
        moments = line;
    } else if (layout != nullptr && *layout == io::kCrossTermLayoutName) {
        io::read_cross_term_ktx2(path, options);
        kind = "not a LEAN map: a cross-term texture of two bump layers (bake --cross-terms)";
    } else if (layout != nullptr) {
        kind = "not a LEAN map this version reads: LEANFADElayout '" + escape_text(*layout) +
               "' (this version reads '" + io::kLeanLayoutName + "', '" +
               io::kLeanPlateauLayoutName + "', '" + io::kLeanSignedLayoutName + "' and '" +
               io::kLeanSignedPlateauLayoutName + "')";
    } else if (content != nullptr) {
        if (*content == "plateau v1")
            io::read_ktx2_rgba16f(path);
        else if (const std::optional<io::EngineTexture> texture = engine_texture_of(*content))
            read_engine_texture(path, info, *texture);
        kind = content->rfind("lean", 0) == 0
                   ? "not a LEAN map: one of its layers as a 2D texture (bake --ktx2-2d), "
                     "LEANFADEcontent '" + escape_text(*content) + "'"
                   : "not a LEAN map: a leanfade texture for engines, LEANFADEcontent '" +
                         escape_text(*content) + "' (docs/ktx2.md)";
    } else {
        kind = "not a LEAN map (no LEANFADElayout key): a texture of another writer";
    }
    std::printf("%s", io::describe(info).c_str());
    std::printf("kind: %s\n", kind.c_str());
    std::printf("%s", moments.c_str());
    return 0;
}

const CommandRegistration registration{
    "info", "Describe any KTX2 file (header, levels, format, key/values) and say whether it is a LEAN map",
    [](CLI::App& app) -> Runner {
        auto path = std::make_shared<std::string>();
        app.add_option("file", *path, "a KTX 2.0 file (a LEAN map of leanfade bake, or any other)")
            ->required();
        auto max_size = std::make_shared<int>(kDefaultMaxImageDimension);
        app.add_option("--max-size", *max_size,
                       "Largest accepted width or height of a map that is read (refused before "
                       "its levels are read; as bake's --max-size, so that a map bake wrote "
                       "with a larger one can be described)")
            ->check(CLI::Range(1, 1 << 20))
            ->capture_default_str();
        return [path, max_size] { return run_info(*path, *max_size); };
    }};

}  // namespace
}  // namespace leanfade::cli
