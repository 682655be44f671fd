// MIP chains stored one file per level (leanfade/io/image_io.hpp, read_mip_series).
#include <filesystem>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::io {

std::vector<std::string> mip_series_files(const std::string& first_level) {
    namespace fs = std::filesystem;
    std::vector<std::string> files;
    const fs::path path(first_level);
    const std::string stem = path.stem().string();
    std::error_code error;
    if (stem.size() < 2 || stem.compare(stem.size() - 2, 2, "_0") != 0) {
        if (fs::exists(path, error)) files.push_back(first_level);
        return files;
    }
    const std::string base = stem.substr(0, stem.size() - 1);  // NAME_
    for (int level = 0; level <= 32; ++level) {
        const fs::path file =
            path.parent_path() / (base + std::to_string(level) + path.extension().string());
        if (!fs::exists(file, error)) break;
        files.push_back(file.string());
    }
    return files;
}

std::vector<Image> read_mip_series(const std::string& first_level, const ReadOptions& options) {
    namespace fs = std::filesystem;
    const fs::path path(first_level);
    const std::string stem = path.stem().string();
    if (stem.size() < 2 || stem.compare(stem.size() - 2, 2, "_0") != 0)
        throw Error(first_level, "a MIP series is named NAME_0.EXT, NAME_1.EXT, ... (level 0 "
                                 "first, as roughness-prefilter writes it)");
    const std::string base = stem.substr(0, stem.size() - 1);  // NAME_
    std::vector<Image> chain;
    chain.push_back(read_image(first_level, options));
    int width = chain.front().width, height = chain.front().height;
    // Sizes halve with floor down to 1 x 1: at most 32 levels for any accepted size.
    while (width > 1 || height > 1) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        const fs::path level =
            path.parent_path() / (base + std::to_string(chain.size()) + path.extension().string());
        std::error_code error;
        if (!fs::exists(level, error))
            throw Error(level.string(), "level " + std::to_string(chain.size()) +
                                            " of the MIP series is missing (every level down to "
                                            "1 x 1 is needed)");
        Image image = read_image(level.string(), options);
        if (image.width != width || image.height != height || image.channels != chain[0].channels)
            throw Error(level.string(), "is " + std::to_string(image.width) + "x" +
                                            std::to_string(image.height) + " with " +
                                            std::to_string(image.channels) + " channels, expected " +
                                            std::to_string(width) + "x" + std::to_string(height) +
                                            " with " + std::to_string(chain[0].channels));
        chain.push_back(std::move(image));
    }
    return chain;
}

}  // namespace leanfade::io
