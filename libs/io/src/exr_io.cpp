// OpenEXR through tinyexr (single part, scan-line or tiled level 0; half / float / uint channels).
#include <tinyexr.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numeric>
#include <string>
#include <string_view>
#include <vector>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"

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

// Indices (into the header's channels) of the channels to return, in output order.
std::vector<int> select_channels(const std::string& path, const EXRHeader& header) {
    std::vector<std::string> names;
    for (int i = 0; i < header.num_channels; ++i) names.emplace_back(header.channels[i].name);
    return order_channels(path, names, "OpenEXR");
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

// Largest tile side accepted (tinyexr's own limit, TINYEXR_DIMENSION_THRESHOLD, is 8 M).
constexpr std::uint32_t kMaxTileSide = 1 << 16;

// Scan lines per chunk of an OpenEXR compression (the file's code; tinyexr uses the same codes for
// the compressions it knows, and 128 for ZFP).
std::int64_t lines_per_chunk(int compression) {
    switch (compression) {
        case 3:    // ZIP
        case 5:    // PXR24
        case 128:  // ZFP (tinyexr)
            return 16;
        case 4:  // PIZ
        case 6:  // B44
        case 7:  // B44A
        case 8:  // DWAA
            return 32;
        case 9:  // DWAB
            return 256;
        default:  // NONE, RLE, ZIPS
            return 1;
    }
}

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
    const std::int64_t lines = lines_per_chunk(header.compression_type);
    const std::int64_t chunks = header.chunk_count > 0 ? std::int64_t(header.chunk_count)
                                                       : (height + lines - 1) / lines;
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
             row < std::min(first + lines, height); ++row)
            covered[std::size_t(row)] = true;
    }
    const auto missing = std::find(covered.begin(), covered.end(), false);
    if (missing != covered.end()) {
        throw Error(path, "corrupt OpenEXR data (line " +
                              std::to_string(min_y + (missing - covered.begin())) +
                              " is in no chunk)");
    }
}

// tinyexr 1.0.1 (Debian 12) asserts (SIGABRT, killing a whole batch) on some header values
// while parsing and decoding: a "tiles" attribute that is not 9 bytes, a tile size of 0 (its tile
// count overflows), a tile level mode of 3, a "type" attribute that contradicts the tiled bit or
// is unknown. The attributes are walked here first, as tinyexr reads them, and such headers are
// refused before tinyexr parses them. A malformed attribute list is left for tinyexr to report.
// Returns what the OpenImageIO path needs of the header (ExrAttributes).
struct ExrAttributes {
    bool complete = false;       // the list ended with its null byte, inside the file
    std::size_t header_len = 0;  // bytes after the version field, up to the null byte included
    int compression = -1;        // OpenEXR's code; -1 when absent
    bool has_window = false;
    std::int32_t window[4] = {};  // data window: min x, min y, max x, max y
    int channels = 0;
    bool subsampled = false;
    bool tiles = false;
    std::uint32_t tile_width = 0, tile_height = 0;
    unsigned level_mode = 0, rounding_mode = 0;
    int chunk_count = 0;
};

// The channel list: name, pixel type, pLinear and 3 reserved bytes, x and y sampling; a null
// byte ends it.
void read_channel_list(const std::uint8_t* data, std::uint32_t size, ExrAttributes& attributes) {
    std::size_t position = 0;
    while (position < size && data[position] != 0) {
        const std::size_t name_length =
            strnlen(reinterpret_cast<const char*>(data + position), size - position);
        position += name_length + 1;
        if (position + 16 > size) return;
        const auto x_sampling = std::int32_t(load_u32_le(data + position + 8));
        const auto y_sampling = std::int32_t(load_u32_le(data + position + 12));
        if (x_sampling != 1 || y_sampling != 1) attributes.subsampled = true;
        position += 16;
        ++attributes.channels;
    }
}

ExrAttributes check_header_attributes(const std::string& path,
                                      const std::vector<std::uint8_t>& bytes, bool tiled_bit) {
    ExrAttributes attributes;
    std::size_t position = 8;  // after the magic number and the version field
    bool tiles = false;
    std::string type;
    while (position < bytes.size() && bytes[position] != 0) {
        const auto* text = reinterpret_cast<const char*>(bytes.data());
        const std::size_t name_length = strnlen(text + position, bytes.size() - position);
        if (position + name_length >= bytes.size()) return attributes;
        const std::string name(text + position, name_length);
        position += name_length + 1;
        const std::size_t type_length = strnlen(text + position, bytes.size() - position);
        if (position + type_length >= bytes.size()) return attributes;
        position += type_length + 1;
        if (bytes.size() - position < 4) return attributes;
        const std::uint32_t size = load_u32_le(bytes.data() + position);
        position += 4;
        if (size > bytes.size() - position) return attributes;
        const std::uint8_t* data = bytes.data() + position;
        position += size;
        if (name == "compression" && size == 1) attributes.compression = data[0];
        if (name == "dataWindow" && size == 16) {
            attributes.has_window = true;
            for (int i = 0; i < 4; ++i)
                attributes.window[i] = std::int32_t(load_u32_le(data + 4 * i));
        }
        if (name == "channels") read_channel_list(data, size, attributes);
        if (name == "chunkCount" && size == 4)
            attributes.chunk_count = std::int32_t(load_u32_le(data));
        if (name == "tiles" && tiled_bit) {
            if (size != 9) {
                throw Error(path, "corrupt OpenEXR header (tile description of " +
                                      std::to_string(size) + " bytes, expected 9)");
            }
            const std::uint32_t tile_width = load_u32_le(data), tile_height = load_u32_le(data + 4);
            const unsigned level_mode = data[8] & 0x0Fu, rounding_mode = data[8] >> 4;
            if (tile_width == 0 || tile_height == 0 || tile_width > kMaxTileSide ||
                tile_height > kMaxTileSide) {
                throw Error(path, "corrupt OpenEXR header (tile size " +
                                      std::to_string(tile_width) + "x" +
                                      std::to_string(tile_height) + ", expected 1 to " +
                                      std::to_string(kMaxTileSide) + " per side)");
            }
            if (level_mode > 2 || rounding_mode > 1) {
                throw Error(path, "corrupt OpenEXR header (tile level mode " +
                                      std::to_string(level_mode) + ", rounding mode " +
                                      std::to_string(rounding_mode) + ")");
            }
            tiles = true;
            attributes.tile_width = tile_width;
            attributes.tile_height = tile_height;
            attributes.level_mode = level_mode;
            attributes.rounding_mode = rounding_mode;
        } else if (name == "type" && size > 0 && data[0] != 0) {
            const auto* value = reinterpret_cast<const char*>(data);
            type.assign(value, strnlen(value, size));
        }
    }
    attributes.complete = position < bytes.size();
    attributes.header_len = position + 1 - 8;
    attributes.tiles = tiled_bit && tiles;
    if (type.empty()) return attributes;
    const bool tiled = tiled_bit && tiles;
    if (type == "deepscanline" || type == "deeptile") {
        throw Error(path, "multi-part and deep OpenEXR files are not supported");
    }
    if ((type == "scanlineimage" && tiled) || (type == "tiledimage" && !tiled)) {
        throw Error(path, "corrupt OpenEXR header (type '" + type + "' in a " +
                              (tiled ? "tiled" : "scan-line") + " file)");
    }
    if (type != "scanlineimage" && type != "tiledimage") {
        throw Error(path, "corrupt OpenEXR header (unknown type '" + escape_text(type) + "')");
    }
    return attributes;
}

// tinyexr's number of levels along one side (LevelSize, RoundLog2 of tinyexr 1.0.1).
std::int64_t tiled_level_size(std::int64_t top, int level, bool round_up) {
    std::int64_t size = top >> level;
    if (round_up && (size << level) < top) ++size;
    return std::max<std::int64_t>(size, 1);
}

int tiled_level_count(std::int64_t size, bool round_up) {
    int levels = 0;
    while ((std::int64_t(1) << levels) < size) ++levels;  // ceil(log2(size))
    if (!round_up && (std::int64_t(1) << levels) != size) --levels;  // floor(log2(size))
    return levels + 1;
}

// The memory bound (check_decoded_size) and the chunk table of an OpenEXR, on the parsed header,
// before tinyexr decodes: tinyexr allocates an offset for every chunk (tile or scan-line block)
// the header implies and decodes every tile of every level, each to a whole tile of floats, so a
// 625-byte tiled file declaring 1x1 tiles over a large window made it allocate 2 GB before it
// found the data missing. The offset table and the chunk headers must fit in the file, and the
// decoded floats (tinyexr's tiles or planes, or the returned image when larger) must be backed by
// the file's data.
void check_chunks_and_decoded_size(const std::string& path, const std::vector<std::uint8_t>& bytes,
                                   const EXRHeader& header, std::size_t returned_channels) {
    const std::int64_t width =
        std::int64_t(header.data_window.max_x) - header.data_window.min_x + 1;
    const std::int64_t height =
        std::int64_t(header.data_window.max_y) - header.data_window.min_y + 1;
    const auto channels = std::uint64_t(header.num_channels);
    std::uint64_t chunks = 0, decoded = 0, chunk_header_bytes = 8;
    std::string what = "OpenEXR of " + std::to_string(width) + "x" + std::to_string(height);
    // Tiled files: the levels and the tile grid of each (tinyexr's rounding).
    const std::int64_t tile_width = std::max(header.tile_size_x, 1);
    const std::int64_t tile_height = std::max(header.tile_size_y, 1);
    const bool round_up = header.tile_rounding_mode == TINYEXR_TILE_ROUND_UP;
    int x_levels = 1, y_levels = 1;
    if (header.tile_level_mode == TINYEXR_TILE_MIPMAP_LEVELS) {
        x_levels = y_levels = tiled_level_count(std::max(width, height), round_up);
    } else if (header.tile_level_mode == TINYEXR_TILE_RIPMAP_LEVELS) {
        x_levels = tiled_level_count(width, round_up);
        y_levels = tiled_level_count(height, round_up);
    }
    const auto columns_at = [&](int x_level) {
        return (tiled_level_size(width, x_level, round_up) + tile_width - 1) / tile_width;
    };
    const auto rows_at = [&](int y_level) {
        return (tiled_level_size(height, y_level, round_up) + tile_height - 1) / tile_height;
    };
    const auto tiles_at = [&](int x_level, int y_level) {
        return std::uint64_t(columns_at(x_level)) * std::uint64_t(rows_at(y_level));
    };
    if (header.tiled != 0) {
        if (header.tile_level_mode == TINYEXR_TILE_RIPMAP_LEVELS) {
            for (int y = 0; y < y_levels; ++y)
                for (int x = 0; x < x_levels; ++x) chunks += tiles_at(x, y);
        } else {
            for (int level = 0; level < x_levels; ++level) chunks += tiles_at(level, level);
        }
        decoded = chunks * std::uint64_t(tile_width) * std::uint64_t(tile_height) * channels * 4;
        chunk_header_bytes = 20;  // tile x, y, level x, y, data size
        what += " in " + std::to_string(chunks) + " tiles of " + std::to_string(tile_width) + "x" +
                std::to_string(tile_height);
    } else {
        const std::int64_t lines = lines_per_chunk(header.compression_type);
        chunks = header.chunk_count > 0 ? std::uint64_t(header.chunk_count)
                                        : std::uint64_t((height + lines - 1) / lines);
        decoded = std::uint64_t(width) * std::uint64_t(height) * channels * 4;
    }
    what += ", " + std::to_string(channels) + " channels";
    decoded = std::max(decoded, std::uint64_t(width) * std::uint64_t(height) *
                                    std::uint64_t(returned_channels) * sizeof(float));
    const std::uint64_t table = std::uint64_t(header.header_len) + 8;  // after magic + version
    const std::uint64_t data_bytes = bytes.size() > table ? bytes.size() - table : 0;
    if (chunks > data_bytes / (8 + chunk_header_bytes)) {
        throw Error(path, "truncated OpenEXR data (" + what + " needs " + std::to_string(chunks) +
                              " chunks, more than the " + std::to_string(bytes.size()) +
                              "-byte file can hold)");
    }
    check_decoded_size(path, what, decoded, data_bytes);
    if (header.tiled == 0) return;  // scan lines: check_scanline_coverage
    // tinyexr 1.0.1 rebuilds a tile offset table that holds a 0 by walking the chunks from the
    // end of the table, trusting each chunk's data size: a corrupt one sends it far past the end
    // of its input (found by fuzz_image_bake: ASan SEGV in ReconstructTileOffsets). Such tables,
    // and offsets whose tile header would not fit in the file, are refused here.
    for (std::uint64_t k = 0; k < chunks; ++k) {
        const std::uint64_t offset = load_u64_le(bytes.data() + table + 8 * k);
        if (offset < table + 8 * chunks) {  // 0 included
            throw Error(path, "corrupt OpenEXR data (tile offset " + std::to_string(k) + " is " +
                                  std::to_string(offset) + ", inside the header or offset table)");
        }
        if (offset > bytes.size() - 20) {
            throw Error(path, "truncated or corrupt OpenEXR data (tile offset " +
                                  std::to_string(k) + " is " + std::to_string(offset) +
                                  ", past the end of the " + std::to_string(bytes.size()) +
                                  "-byte file)");
        }
        // The tile the chunk names: tinyexr multiplies its coordinates by the tile size in int
        // arithmetic, unchecked (found by fuzz_image_bake: UBSan, signed overflow in
        // DecodeTiledPixelData). They must lie in the grid of their level.
        const auto coordinate = [&](int i) {
            return std::int64_t(std::int32_t(load_u32_le(bytes.data() + offset + 4 * i)));
        };
        const std::int64_t tile_x = coordinate(0), tile_y = coordinate(1);
        const std::int64_t level_x = coordinate(2), level_y = coordinate(3);
        const bool level_known =
            level_x >= 0 && level_x < x_levels && level_y >= 0 && level_y < y_levels &&
            (header.tile_level_mode == TINYEXR_TILE_RIPMAP_LEVELS || level_x == level_y);
        if (!level_known || tile_x < 0 || tile_x >= columns_at(int(level_x)) || tile_y < 0 ||
            tile_y >= rows_at(int(level_y))) {
            throw Error(path, "corrupt OpenEXR data (chunk " + std::to_string(k) + " names tile (" +
                                  std::to_string(tile_x) + ", " + std::to_string(tile_y) +
                                  ") of level (" + std::to_string(level_x) + ", " +
                                  std::to_string(level_y) + "), outside the image)");
        }
    }
}

// tinyexr 1.0.1 places each decoded tile at the coordinates its chunk names, without checking
// them: a corrupt chunk gave a negative tile position (found by fuzz_image_bake: UBSan, a
// negative index into the image), and chunks naming the same tile leave others undecoded. The
// tiles of level 0 must be exactly the grid over the data window, each once.
void check_tile_coverage(const std::string& path, const EXRHeader& header, const EXRImage& image,
                         std::int64_t width, std::int64_t height) {
    const std::int64_t columns = (width + header.tile_size_x - 1) / header.tile_size_x;
    const std::int64_t rows = (height + header.tile_size_y - 1) / header.tile_size_y;
    std::vector<bool> decoded(std::size_t(columns * rows), false);
    for (int t = 0; t < image.num_tiles; ++t) {
        const EXRTile& tile = image.tiles[t];
        if (tile.offset_x < 0 || tile.offset_x >= columns || tile.offset_y < 0 ||
            tile.offset_y >= rows) {
            throw Error(path, "corrupt OpenEXR data (tile (" + std::to_string(tile.offset_x) +
                                  ", " + std::to_string(tile.offset_y) + ") outside the " +
                                  std::to_string(columns) + "x" + std::to_string(rows) +
                                  " tiles of the image)");
        }
        decoded[std::size_t(tile.offset_y * columns + tile.offset_x)] = true;
    }
    const auto missing = std::find(decoded.begin(), decoded.end(), false);
    if (missing != decoded.end()) {
        const auto index = std::int64_t(missing - decoded.begin());
        throw Error(path, "corrupt OpenEXR data (tile (" + std::to_string(index % columns) + ", " +
                              std::to_string(index / columns) + ") is in no chunk)");
    }
}

// Compressions tinyexr 1.0.1 does not decode ("Unknown compression type"): PXR24, B44, B44A,
// DWAA, DWAB.
bool decoded_by_openexr(int compression) { return compression >= 5 && compression <= 9; }

// The header checks of the tinyexr path (size, chunk table, decoded size, scan-line coverage), on
// the attributes read by check_header_attributes, then OpenImageIO's OpenEXR reader.
Image decode_with_openexr(const std::string& path, const std::vector<std::uint8_t>& bytes,
                          const ExrAttributes& attributes, const ReadOptions& options) {
    if (!attributes.complete || !attributes.has_window || attributes.channels < 1) {
        throw Error(path, std::string("truncated or corrupt OpenEXR header (") +
                              (!attributes.complete     ? "attribute list not terminated"
                               : !attributes.has_window ? "no data window"
                                                        : "no channels") +
                              ")");
    }
    EXRHeader header;  // filled here, nothing allocated: never given to FreeEXRHeader
    InitEXRHeader(&header);
    header.data_window.min_x = attributes.window[0];
    header.data_window.min_y = attributes.window[1];
    header.data_window.max_x = attributes.window[2];
    header.data_window.max_y = attributes.window[3];
    const std::int64_t width = std::int64_t(attributes.window[2]) - attributes.window[0] + 1;
    const std::int64_t height = std::int64_t(attributes.window[3]) - attributes.window[1] + 1;
    check_dimensions(path, width, height, options.max_dimension);
    if (attributes.subsampled)
        throw Error(path, "subsampled OpenEXR channels are not supported");
    header.num_channels = attributes.channels;
    header.compression_type = attributes.compression;
    header.chunk_count = attributes.chunk_count;
    header.header_len = unsigned(attributes.header_len);
    header.tiled = attributes.tiles ? 1 : 0;
    header.tile_size_x = int(attributes.tile_width);
    header.tile_size_y = int(attributes.tile_height);
    header.tile_level_mode = int(attributes.level_mode);
    header.tile_rounding_mode = int(attributes.rounding_mode);
    check_chunks_and_decoded_size(path, bytes, header,
                                  std::size_t(std::min(attributes.channels, 4)));
    if (header.tiled == 0) check_scanline_coverage(path, bytes, header);
    return decode_exr_with_openimageio(path, bytes, options);
}

}  // namespace

void check_exr_size(const InputFile& file, const ReadOptions& options) {
    const std::uint64_t file_size = file.size();
    std::uint64_t position = 8;  // after the magic number and the version field
    for (int attribute = 0; attribute < 4096 && position < file_size; ++attribute) {
        // A name and a type of at most 255 bytes each, their null bytes and the value's size.
        std::uint8_t buffer[2 * 256 + 4];
        const auto count =
            std::size_t(std::min<std::uint64_t>(sizeof buffer, file_size - position));
        file.read_at(position, buffer, count, "file shrank while being read");
        if (buffer[0] == 0) return;  // the end of the header: no data window (decode_exr says so)
        const auto* text = reinterpret_cast<const char*>(buffer);
        const std::size_t name_length = strnlen(text, count);
        if (name_length + 1 >= count) return;
        const std::size_t type_length = strnlen(text + name_length + 1, count - name_length - 1);
        const std::size_t size_at = name_length + 1 + type_length + 1;
        if (size_at + 4 > count) return;
        const std::uint32_t value_size = load_u32_le(buffer + size_at);
        const std::uint64_t value_at = position + size_at + 4;
        if (std::string_view(text, name_length) == "dataWindow" && value_size == 16) {
            if (value_at + 16 > file_size) return;
            std::uint8_t window[16];
            file.read_at(value_at, window, sizeof window, "file shrank while being read");
            const auto corner = [&](int i) {
                return std::int64_t(std::int32_t(load_u32_le(window + 4 * i)));
            };
            check_dimensions(file.path(), corner(2) - corner(0) + 1, corner(3) - corner(1) + 1,
                             options.max_dimension);
            return;
        }
        position = value_at + value_size;
    }
}

Image decode_exr(const std::string& path, const std::vector<std::uint8_t>& bytes,
                 const ReadOptions& options) {
    EXRVersion version{};
    if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS) {
        throw Error(path, "truncated or corrupt OpenEXR data (bad version field)");
    }
    if (version.multipart != 0 || version.non_image != 0) {
        throw Error(path, "multi-part and deep OpenEXR files are not supported");
    }
    const ExrAttributes attributes = check_header_attributes(path, bytes, version.tiled != 0);
    if (decoded_by_openexr(attributes.compression))
        return decode_with_openexr(path, bytes, attributes, options);
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

    check_chunks_and_decoded_size(path, bytes, header.header, selected.size());
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

    if (header.header.tiled != 0) {
        check_tile_coverage(path, header.header, loaded.image, width, height);
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
                    // Tile coordinates come from the chunks: negative or huge in a corrupt file
                    // (found by fuzz_image_bake: UBSan, a negative index into the image).
                    const std::int64_t image_x = std::int64_t(tile.offset_x) * tile_width + x;
                    const std::int64_t image_y = std::int64_t(tile.offset_y) * tile_height + y;
                    if (image_x < 0 || image_y < 0 || image_x >= image.width ||
                        image_y >= image.height) {
                        continue;
                    }
                    image.at(int(image_x), int(image_y), int(out)) =
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
