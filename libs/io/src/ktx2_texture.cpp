// Plain 2D textures with MIPs as KTX 2.0 (leanfade/io/detail/ktx2_texture.hpp).
#include "leanfade/io/detail/ktx2_texture.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>

#include <glm/gtc/packing.hpp>

#include "ktx2_internal.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/version.hpp"

namespace leanfade::io {
namespace {

using namespace ktx2_detail;

// One level's size and texel bytes, rows top first.
struct LevelBytes {
    int width = 0;
    int height = 0;
    std::span<const std::uint8_t> bytes;
};

// One level's size and byte count (the file's layout needs no texels).
using LevelSize = TextureLevelSize;

std::vector<LevelSize> sizes_of(const std::vector<LevelBytes>& levels) {
    std::vector<LevelSize> sizes;
    for (const LevelBytes& l : levels) sizes.push_back({l.width, l.height, l.bytes.size()});
    return sizes;
}

LevelByteCount texel_bytes_of(const FormatInfo& format) {
    return [texel_bytes = std::size_t(format.texel_bytes)](int w, int h) {
        return std::size_t(w) * std::size_t(h) * texel_bytes;
    };
}

// The layout of a 2D texture file: its head (header, level index, data format descriptor and
// key/value data, padded to the first level) and where each level's texels go.
struct File2d {
    std::vector<std::uint8_t> head;
    std::vector<std::uint64_t> offsets;  // per level, level 0 first
    std::uint64_t size = 0;              // of the whole file
};

// `sizes`: the chain's levels, level 0 first (checked by check_chain).
File2d plan_2d(const FormatInfo& format, const std::vector<LevelSize>& sizes,
               const std::string& writer, const std::string& name, const TextureKeyValues& extra) {
    check_mip_chain(sizes, texel_bytes_of(format), "", name);
    const auto level_count = std::uint32_t(sizes.size());
    const std::vector<std::uint8_t> key_values = texture_key_value_data(writer, extra, name);
    const std::vector<std::uint8_t> dfd = encode_data_format(expected_data_format(format));
    const std::uint64_t dfd_offset = kHeaderSize + kLevelIndexEntrySize * level_count;
    const std::uint64_t kvd_offset = dfd_offset + dfd.size();

    // Level data from the smallest level to the largest, each aligned to lcm(texel size, 4).
    const std::uint64_t alignment = level_alignment(format);
    File2d file;
    file.offsets.resize(level_count);
    std::uint64_t end = kvd_offset + key_values.size();
    for (std::uint32_t l = level_count; l-- > 0;) {
        end = align_up(end, alignment);
        file.offsets[l] = end;
        end += sizes[l].bytes;
    }
    file.size = end;

    std::vector<std::uint8_t>& bytes = file.head;
    bytes.assign(kIdentifier.begin(), kIdentifier.end());
    append_u32_le(bytes, format.vk_format);
    append_u32_le(bytes, format.type_size);
    append_u32_le(bytes, std::uint32_t(sizes.front().width));
    append_u32_le(bytes, std::uint32_t(sizes.front().height));
    append_u32_le(bytes, 0);  // pixelDepth: 2D
    append_u32_le(bytes, 0);  // layerCount: not an array
    append_u32_le(bytes, 1);  // faceCount
    append_u32_le(bytes, level_count);
    append_u32_le(bytes, 0);  // supercompressionScheme: none
    append_u32_le(bytes, std::uint32_t(dfd_offset));
    append_u32_le(bytes, std::uint32_t(dfd.size()));
    append_u32_le(bytes, std::uint32_t(kvd_offset));
    append_u32_le(bytes, std::uint32_t(key_values.size()));
    append_u64_le(bytes, 0);  // sgdByteOffset
    append_u64_le(bytes, 0);  // sgdByteLength
    for (std::uint32_t l = 0; l < level_count; ++l) {
        append_u64_le(bytes, file.offsets[l]);
        append_u64_le(bytes, sizes[l].bytes);
        append_u64_le(bytes, sizes[l].bytes);
    }
    bytes.insert(bytes.end(), dfd.begin(), dfd.end());
    bytes.insert(bytes.end(), key_values.begin(), key_values.end());
    bytes.resize(std::size_t(file.offsets.back()), 0);  // padding up to the smallest level
    return file;
}

std::vector<std::uint8_t> encode_2d(const FormatInfo& format, const std::vector<LevelBytes>& levels,
                                    const std::string& writer, const std::string& name,
                                    const TextureKeyValues& extra) {
    File2d file = plan_2d(format, sizes_of(levels), writer, name, extra);
    std::vector<std::uint8_t>& bytes = file.head;
    bytes.resize(std::size_t(file.size), 0);
    for (std::size_t l = 0; l < levels.size(); ++l)
        std::copy(levels[l].bytes.begin(), levels[l].bytes.end(),
                  bytes.begin() + std::ptrdiff_t(file.offsets[l]));
    return bytes;
}

// The sizes of a full chain from width x height down to 1 x 1.
std::vector<LevelSize> chain_sizes(int width, int height, std::size_t texel_bytes,
                                   const std::string& name) {
    if (width < 1 || height < 1 || width > 65536 || height > 65536)
        throw Error(name, "level 0 must be 1 to 65536 texels on a side, got " +
                              std::to_string(width) + "x" + std::to_string(height));
    std::vector<LevelSize> sizes;
    for (int w = width, h = height;; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
        sizes.push_back({w, h, std::size_t(w) * std::size_t(h) * texel_bytes});
        if (w == 1 && h == 1) break;
    }
    return sizes;
}

// Half floats of a 4-channel image, little-endian.
std::vector<std::uint8_t> to_half_bytes(const Image& image, std::size_t level,
                                        const std::string& name) {
    if (image.channels != 4)
        throw Error(name, "level " + std::to_string(level) + " must have 4 channels, got " +
                              std::to_string(image.channels));
    std::vector<std::uint8_t> bytes(image.pixels.size() * 2);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const float v = image.pixels[i];
        if (!std::isfinite(v) || std::abs(v) > 65504.0f)
            throw Error(name, "level " + std::to_string(level) +
                                  " holds a value a half float cannot store");
        const std::uint16_t h = glm::packHalf1x16(v);
        bytes[2 * i] = std::uint8_t(h & 0xFFu);
        bytes[2 * i + 1] = std::uint8_t(h >> 8);
    }
    return bytes;
}

}  // namespace

namespace ktx2_detail {

void check_mip_chain(const std::vector<TextureLevelSize>& levels, const LevelByteCount& level_bytes,
                     const std::string& unit, const std::string& name) {
    if (levels.empty()) throw Error(name, "a texture needs at least one level");
    const TextureLevelSize& top = levels.front();
    if (top.width < 1 || top.height < 1 || top.width > 65536 || top.height > 65536)
        throw Error(name, "level 0 must be 1 to 65536 texels on a side, got " +
                              std::to_string(top.width) + "x" + std::to_string(top.height));
    int w = top.width, h = top.height;
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const TextureLevelSize& level = levels[l];
        if (level.width != w || level.height != h)
            throw Error(name, "level " + std::to_string(l) + " must be " + std::to_string(w) +
                                  "x" + std::to_string(h));
        const std::size_t size = level_bytes(w, h);
        if (level.bytes != size)
            throw Error(name, "level " + std::to_string(l) + " must hold " +
                                  std::to_string(size) + " bytes" + unit);
        if (w == 1 && h == 1 && l + 1 != levels.size())
            throw Error(name, "levels after the 1x1 level");
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    if (levels.back().width != 1 || levels.back().height != 1)
        throw Error(name, "the MIP chain must go down to 1x1");
}

std::vector<TextureLevelData> read_plain_2d_levels(const std::string& path,
                                                   std::uint32_t vk_format,
                                                   const std::string& format_name,
                                                   const LevelByteCount& level_bytes,
                                                   const std::string& unit) {
    const Ktx2Info info = inspect_ktx2(path);
    if (info.vk_format != vk_format)
        throw Error(path, "expected " + format_name + ", got " + vk_format_name(info.vk_format));
    if (info.pixel_depth != 0 || info.layer_count > 1 || info.face_count != 1 ||
        info.supercompression_scheme != kSchemeNone)
        throw Error(path, "expected a plain 2D texture (no depth, layers, faces or "
                          "supercompression)");
    const detail::InputFile file(path);
    std::vector<TextureLevelData> levels;
    for (const Ktx2Level& entry : info.levels) {
        const int width = int(entry.width), height = int(entry.height);
        const std::size_t size = level_bytes(width, height);
        if (entry.byte_length != size)
            throw Error(path, "a level of " + std::to_string(width) + "x" +
                                  std::to_string(height) + " texels must hold " +
                                  std::to_string(size) + " bytes" + unit);
        TextureLevelData level{width, height, std::vector<std::uint8_t>(size)};
        file.read_at(entry.byte_offset, level.bytes.data(), size, "cannot read a level's texels");
        levels.push_back(std::move(level));
    }
    return levels;
}

void write_file_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes,
                           const WriteOptions& options) {
    AtomicFile file(path, options.durability);
    file.write(bytes);
    file.commit();
}

std::vector<std::uint8_t> texture_key_value_data(const std::string& writer,
                                                 const TextureKeyValues& extra,
                                                 const std::string& name,
                                                 const TextureKeyValues& ktx_keys) {
    TextureKeyValues all{{kKeyOrientation, "rd"}, {kKeyWriter, writer}};
    all.insert(all.end(), ktx_keys.begin(), ktx_keys.end());
    for (const auto& [key, value] : extra) {
        if (key.empty() || key.rfind("KTX", 0) == 0)
            throw Error(name, "key '" + key + "' is reserved or empty");
        if (key.find('\0') != std::string::npos || value.find('\0') != std::string::npos)
            throw Error(name, "key '" + key + "' holds a NUL byte");
        all.emplace_back(key, value);
    }
    std::sort(all.begin(), all.end());
    for (std::size_t i = 1; i < all.size(); ++i)
        if (all[i].first == all[i - 1].first)
            throw Error(name, "key '" + all[i].first + "' given twice");
    std::vector<std::uint8_t> bytes;
    for (const auto& [key, value] : all) append_key_value(bytes, key, value);
    return bytes;
}

}  // namespace ktx2_detail

std::vector<std::uint8_t> encode_ktx2_rgba8(const std::vector<Rgba8Level>& levels,
                                            const std::string& writer, const std::string& name,
                                            const TextureKeyValues& key_values) {
    std::vector<LevelBytes> views;
    for (const Rgba8Level& level : levels) views.push_back({level.width, level.height, level.texels});
    return encode_2d(format_of(Storage::Unorm8), views, writer, name, key_values);
}

void write_ktx2_rgba8(const std::string& path, const std::vector<Rgba8Level>& levels,
                      const std::string& writer, const WriteOptions& options,
                      const TextureKeyValues& key_values) {
    write_file_atomically(path, encode_ktx2_rgba8(levels, writer, path, key_values), options);
}

Ktx2Rgba8Writer::Ktx2Rgba8Writer(const std::string& path, int width, int height,
                                 const std::string& writer, const TextureKeyValues& key_values,
                                 const WriteOptions& options)
    : file_(path, options.durability) {
    const FormatInfo& format = format_of(Storage::Unorm8);
    const std::vector<LevelSize> sizes = chain_sizes(width, height, format.texel_bytes, path);
    const File2d plan = plan_2d(format, sizes, writer, path, key_values);
    std::uint8_t* bytes = file_.map(std::size_t(plan.size));
    std::copy(plan.head.begin(), plan.head.end(), bytes);
    for (std::uint64_t offset : plan.offsets) levels_.push_back(bytes + offset);
}

void Ktx2Rgba8Writer::commit() {
    levels_.clear();
    file_.commit();
}

std::vector<std::uint8_t> encode_ktx2_rgba16f(const std::vector<Image>& levels,
                                              const std::string& writer, const std::string& name,
                                              const TextureKeyValues& key_values) {
    std::vector<std::vector<std::uint8_t>> halves;
    for (std::size_t l = 0; l < levels.size(); ++l)
        halves.push_back(to_half_bytes(levels[l], l, name));
    std::vector<LevelBytes> views;
    for (std::size_t l = 0; l < levels.size(); ++l)
        views.push_back({levels[l].width, levels[l].height, halves[l]});
    return encode_2d(format_of(Storage::Float16), views, writer, name, key_values);
}

void write_ktx2_rgba16f(const std::string& path, const std::vector<Image>& levels,
                        const std::string& writer, const WriteOptions& options,
                        const TextureKeyValues& key_values) {
    write_file_atomically(path, encode_ktx2_rgba16f(levels, writer, path, key_values), options);
}

void write_ktx2_layer_textures(const std::string& lean1_path, const std::string& lean2_path,
                               const PackedLeanMap& map, const WriteOptions& options) {
    const FormatInfo& format = format_of(map.storage);
    validate_for_write(lean1_path, map, format, true);
    const std::string writer =
        map.generator.empty() ? std::string(LEANFADE_GENERATOR) : map.generator;
    for (int layer = 0; layer < 2; ++layer) {
        const std::string& path = layer == 0 ? lean1_path : lean2_path;
        std::vector<LevelBytes> views;
        for (const PackedLevel& level : map.levels)
            views.push_back({level.width, level.height, layer == 0 ? level.lean1 : level.lean2});
        TextureKeyValues keys = lean_metadata_keys(map);
        keys.emplace_back(kKeyTextureContent, layer == 0 ? "lean1 v1" : "lean2 v1");
        write_file_atomically(path, encode_2d(format, views, writer, path, keys), options);
    }
}

std::vector<Rgba8Level> read_ktx2_rgba8(const std::string& path) {
    const FormatInfo& format = format_of(Storage::Unorm8);
    std::vector<Rgba8Level> levels;
    for (TextureLevelData& level :
         read_plain_2d_levels(path, format.vk_format, format.name, texel_bytes_of(format), ""))
        levels.push_back({level.width, level.height, std::move(level.bytes)});
    return levels;
}

std::vector<Image> read_ktx2_rgba16f(const std::string& path) {
    const FormatInfo& format = format_of(Storage::Float16);
    const std::vector<TextureLevelData> data =
        read_plain_2d_levels(path, format.vk_format, format.name, texel_bytes_of(format), "");
    std::vector<Image> levels;
    for (std::size_t l = 0; l < data.size(); ++l) {
        const std::vector<std::uint8_t>& bytes = data[l].bytes;
        Image image(data[l].width, data[l].height, 4);
        for (std::size_t i = 0; i < image.pixels.size(); ++i) {
            const auto h = std::uint16_t(bytes[2 * i] | (bytes[2 * i + 1] << 8));
            image.pixels[i] = glm::unpackHalf1x16(h);
            if (!std::isfinite(image.pixels[i]))
                throw Error(path, "level " + std::to_string(l) + " holds a value that is not finite");
        }
        levels.push_back(std::move(image));
    }
    return levels;
}

}  // namespace leanfade::io
