// OpenEXR through tinyexr (single part, scan-line or tiled level 0; half / float / uint channels).
#include <tinyexr.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>
#include <memory>
#include <numeric>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"

namespace leanfade::io::detail {
namespace {

// Owns what tinyexr allocates; frees it on every path.
struct ExrHeaderGuard {
    EXRHeader header;
    ExrHeaderGuard() { InitEXRHeader(&header); }
    ~ExrHeaderGuard() { FreeEXRHeader(&header); }
    ExrHeaderGuard(const ExrHeaderGuard&) = delete;
    ExrHeaderGuard& operator=(const ExrHeaderGuard&) = delete;
};

// tinyexr frees a partly decoded image itself when decoding fails (without clearing the
// pointers), so a failed load must disown the image instead of freeing it again. That cleanup
// frees one plane per `num_channels`, which tinyexr sets only on success: decode_exr presets it.
struct ExrImageGuard {
    EXRImage image;
    bool owned = true;
    ExrImageGuard() { InitEXRImage(&image); }
    ~ExrImageGuard() {
        if (owned) FreeEXRImage(&image);
    }
    ExrImageGuard(const ExrImageGuard&) = delete;
    ExrImageGuard& operator=(const ExrImageGuard&) = delete;
};

// Takes ownership of a tinyexr error message and returns it on one line, without its final
// full stop (tinyexr messages may hold several lines, each ending with ".\n").
std::string take_message(const char* message) {
    if (message == nullptr) return "no details";
    std::string text = message;
    FreeEXRErrorMessage(message);
    std::string line;
    for (const char character : text) {
        if (character == '\n' || character == '\r') {
            if (!line.empty() && line.back() == '.') line.pop_back();
            if (!line.empty() && !line.ends_with("; ")) line += "; ";
        } else {
            line.push_back(character);
        }
    }
    while (!line.empty() && (line.back() == ' ' || line.back() == ';' || line.back() == '.')) {
        line.pop_back();
    }
    return line.empty() ? "no details" : line;
}

std::string channel_base_name(const char* name) {
    const char* dot = std::strrchr(name, '.');
    return dot != nullptr ? std::string(dot + 1) : std::string(name);
}

// R, G, B then A (Y counts as the first colour channel): the order of the returned image.
int channel_rank(const std::string& base_name) {
    if (base_name == "R" || base_name == "r" || base_name == "Y" || base_name == "y") return 0;
    if (base_name == "G" || base_name == "g") return 1;
    if (base_name == "B" || base_name == "b") return 2;
    if (base_name == "A" || base_name == "a") return 3;
    return 4;
}

// Indices (into the header's channels) of the channels to return, in output order.
std::vector<int> select_channels(const std::string& path, const EXRHeader& header) {
    std::vector<int> order(std::size_t(header.num_channels));
    std::iota(order.begin(), order.end(), 0);
    std::vector<int> ranks;
    for (int i = 0; i < header.num_channels; ++i) {
        ranks.push_back(channel_rank(channel_base_name(header.channels[i].name)));
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return ranks[std::size_t(a)] < ranks[std::size_t(b)]; });
    if (order.size() > 4) {
        order.erase(std::remove_if(order.begin(), order.end(),
                                   [&](int i) { return ranks[std::size_t(i)] >= 4; }),
                    order.end());
        if (order.empty() || order.size() > 4) {
            throw Error(path, "OpenEXR with " + std::to_string(header.num_channels) +
                                  " channels and no R, G, B, A subset (at most 4 supported)");
        }
    }
    return order;
}

float sample_value(const unsigned char* plane, int pixel_type, std::size_t index) {
    if (pixel_type == TINYEXR_PIXELTYPE_UINT) {
        unsigned int value;
        std::memcpy(&value, plane + index * sizeof value, sizeof value);
        return float(value);
    }
    float value;  // half channels were requested as float
    std::memcpy(&value, plane + index * sizeof value, sizeof value);
    return value;
}

// tinyexr 1.0.1 (Debian 12) reads past the end of its input on some corrupt files: DecompressPiz
// copies a chunk's PIZ bitmap (up to 8 KiB + 8 bytes) without checking the chunk's length (found
// by fuzz_image_bake, see docs/robustness.md). tinyexr is given a copy of the file followed by
// this many zero bytes, so such reads stay inside our buffer, see zeros, and the chunk is then
// refused as corrupt. The size passed to tinyexr remains the file's.
constexpr std::size_t kTinyexrReadPadding = 64 * 1024;

// tinyexr 1.0.1 places each scan-line chunk by the line number the chunk itself gives, and does
// not check that the chunks cover the data window: a corrupt file whose chunks name the wrong
// lines decodes "successfully" with rows of uninitialised memory (found by fuzz_image_bake: the
// same file decoded to different values from one call to the next). Before decoding, walk the
// line offset table as tinyexr does (same block count, same lines per chunk) and require every
// row to be in some chunk. Tables tinyexr would have to reconstruct (an offset of 0) are refused.
void check_scanline_coverage(const std::string& path, const std::vector<std::uint8_t>& bytes,
                             const EXRHeader& header) {
    const std::int64_t min_y = header.data_window.min_y;
    const std::int64_t height = std::int64_t(header.data_window.max_y) - min_y + 1;
    const std::int64_t lines_per_chunk =
        header.compression_type == TINYEXR_COMPRESSIONTYPE_PIZ   ? 32
        : header.compression_type == TINYEXR_COMPRESSIONTYPE_ZIP ? 16
        : header.compression_type == TINYEXR_COMPRESSIONTYPE_ZFP ? 16
                                                                 : 1;
    const std::int64_t chunks = header.chunk_count > 0
                                    ? std::int64_t(header.chunk_count)
                                    : (height + lines_per_chunk - 1) / lines_per_chunk;
    const std::uint64_t table = std::uint64_t(header.header_len) + 8;  // after magic + version
    if (chunks <= 0 || table + 8 * std::uint64_t(chunks) > bytes.size())
        throw Error(path, "truncated OpenEXR data (line offset table)");
    std::vector<bool> covered(std::size_t(height), false);
    for (std::int64_t k = 0; k < chunks; ++k) {
        const std::uint64_t offset = load_u64_le(bytes.data() + table + 8 * std::uint64_t(k));
        if (offset == 0 || offset > bytes.size() - 8) {
            throw Error(path, "corrupt OpenEXR data (line offset " + std::to_string(k) +
                                  " points outside the file)");
        }
        const auto line = std::int32_t(load_u32_le(bytes.data() + offset));
        const std::int64_t first = std::int64_t(line) - min_y;
        for (std::int64_t row = std::max<std::int64_t>(first, 0);
             row < std::min(first + lines_per_chunk, height); ++row)
            covered[std::size_t(row)] = true;
    }
    const auto missing = std::find(covered.begin(), covered.end(), false);
    if (missing != covered.end()) {
        throw Error(path, "corrupt OpenEXR data (line " +
                              std::to_string(min_y + (missing - covered.begin())) +
                              " is in no chunk)");
    }
}

}  // namespace

Image decode_exr(const std::string& path, const std::vector<std::uint8_t>& bytes,
                 const ReadOptions& options) {
    EXRVersion version{};
    if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS) {
        throw Error(path, "truncated or corrupt OpenEXR data (bad version field)");
    }
    if (version.multipart != 0 || version.non_image != 0) {
        throw Error(path, "multi-part and deep OpenEXR files are not supported");
    }
    ExrHeaderGuard header;
    const char* message = nullptr;
    if (ParseEXRHeaderFromMemory(&header.header, &version, bytes.data(), bytes.size(), &message) !=
        TINYEXR_SUCCESS) {
        throw Error(path, "truncated or corrupt OpenEXR header (" + take_message(message) + ")");
    }
    const EXRBox2i& window = header.header.data_window;
    const std::int64_t width = std::int64_t(window.max_x) - window.min_x + 1;
    const std::int64_t height = std::int64_t(window.max_y) - window.min_y + 1;
    check_dimensions(path, width, height, options.max_dimension);
    if (header.header.num_channels < 1) throw Error(path, "OpenEXR without channels");
    const std::vector<int> selected = select_channels(path, header.header);

    for (int i = 0; i < header.header.num_channels; ++i) {
        if (header.header.channels[i].x_sampling > 1 || header.header.channels[i].y_sampling > 1) {
            throw Error(path, "subsampled OpenEXR channels are not supported");
        }
        if (header.header.pixel_types[i] == TINYEXR_PIXELTYPE_HALF) {
            header.header.requested_pixel_types[i] = TINYEXR_PIXELTYPE_FLOAT;
        }
    }

    if (header.header.tiled == 0) check_scanline_coverage(path, bytes, header.header);

    std::vector<std::uint8_t> padded(bytes.size() + kTinyexrReadPadding, 0);
    std::copy(bytes.begin(), bytes.end(), padded.begin());
    ExrImageGuard loaded;
    loaded.image.num_channels = header.header.num_channels;  // see ExrImageGuard
    if (LoadEXRImageFromMemory(&loaded.image, &header.header, padded.data(), bytes.size(),
                               &message) != TINYEXR_SUCCESS) {
        loaded.owned = false;
        throw Error(path, "truncated or corrupt OpenEXR data (" + take_message(message) + ")");
    }
    if (loaded.image.width != width || loaded.image.height != height) {
        throw Error(path, "corrupt OpenEXR data (decoded size differs from the data window)");
    }

    Image image(int(width), int(height), int(selected.size()));
    for (std::size_t out = 0; out < selected.size(); ++out) {
        const int channel = selected[out];
        const int pixel_type = header.header.requested_pixel_types[channel];
        if (header.header.tiled == 0) {
            const unsigned char* plane = loaded.image.images[channel];
            for (std::size_t i = 0; i < image.texel_count(); ++i) {
                image.pixels[i * selected.size() + out] = sample_value(plane, pixel_type, i);
            }
            continue;
        }
        const int tile_width = header.header.tile_size_x;
        const int tile_height = header.header.tile_size_y;
        for (int t = 0; t < loaded.image.num_tiles; ++t) {
            const EXRTile& tile = loaded.image.tiles[t];
            const unsigned char* plane = tile.images[channel];
            for (int y = 0; y < tile.height; ++y) {
                for (int x = 0; x < tile.width; ++x) {
                    const int image_x = tile.offset_x * tile_width + x;
                    const int image_y = tile.offset_y * tile_height + y;
                    if (image_x >= image.width || image_y >= image.height) continue;
                    image.at(image_x, image_y, int(out)) =
                        sample_value(plane, pixel_type,
                                     std::size_t(y) * std::size_t(tile_width) + std::size_t(x));
                }
            }
        }
    }
    check_finite(path, image);
    return image;
}

std::vector<std::uint8_t> encode_exr(const std::string& path, const Image& image) {
    check_writable(path, image);
    check_finite(path, image);

    // OpenEXR lists channels sorted by name; `source` is the image channel of each entry.
    struct NamedChannel {
        const char* name;
        int source;
    };
    std::vector<NamedChannel> channels;
    switch (image.channels) {
        case 1:
            channels = {{"Y", 0}};
            break;
        case 2:
            channels = {{"A", 1}, {"Y", 0}};
            break;
        case 3:
            channels = {{"B", 2}, {"G", 1}, {"R", 0}};
            break;
        default:
            channels = {{"A", 3}, {"B", 2}, {"G", 1}, {"R", 0}};
            break;
    }

    const std::size_t texels = image.texel_count();
    std::vector<std::vector<float>> planes(channels.size(), std::vector<float>(texels));
    std::vector<unsigned char*> plane_pointers;
    std::vector<EXRChannelInfo> infos(channels.size());
    std::vector<int> pixel_types(channels.size(), TINYEXR_PIXELTYPE_FLOAT);
    for (std::size_t c = 0; c < channels.size(); ++c) {
        for (std::size_t i = 0; i < texels; ++i) {
            planes[c][i] =
                image.pixels[i * std::size_t(image.channels) + std::size_t(channels[c].source)];
        }
        plane_pointers.push_back(reinterpret_cast<unsigned char*>(planes[c].data()));
        std::memset(&infos[c], 0, sizeof infos[c]);
        std::strncpy(infos[c].name, channels[c].name, sizeof infos[c].name - 1);
    }

    EXRHeader header;  // points into our vectors: not freed with FreeEXRHeader
    InitEXRHeader(&header);
    header.num_channels = int(channels.size());
    header.channels = infos.data();
    header.pixel_types = pixel_types.data();
    header.requested_pixel_types = pixel_types.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

    EXRImage exr_image;
    InitEXRImage(&exr_image);
    exr_image.images = plane_pointers.data();
    exr_image.width = image.width;
    exr_image.height = image.height;
    exr_image.num_channels = int(channels.size());

    unsigned char* memory = nullptr;
    const char* message = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&exr_image, &header, &memory, &message);
    const std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
    if (size == 0 || memory == nullptr) {
        throw Error(path, "cannot encode OpenEXR (" + take_message(message) + ")");
    }
    return std::vector<std::uint8_t>(memory, memory + size);
}

}  // namespace leanfade::io::detail
