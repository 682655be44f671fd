// KTX 2.0 (Khronos, https://registry.khronos.org/KTX/specs/2.0/ktxspec.v2.html) for LEAN maps.
// All multi-byte fields are little-endian. File layout written here:
//   header (80 bytes) | level index (24 bytes per level) | DFD | key/value data |
//   padding | level n-1 | ... | level 0
#include "leanfade/io/ktx2.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <optional>
#include <sstream>

#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/core/parallel.hpp"
#include "leanfade/io/atomic_file.hpp"

namespace leanfade::io {
namespace {

using detail::append_u32_le;
using detail::append_u64_le;
using detail::load_u32_le;
using detail::load_u64_le;

constexpr std::array<std::uint8_t, 12> kIdentifier = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                                      '0',  0xBB, '\r', '\n', 0x1A, '\n'};
constexpr std::size_t kHeaderSize = 80;  // identifier + 9 uint32 + 4 uint32 + 2 uint64
constexpr std::size_t kLevelIndexEntrySize = 24;
constexpr std::uint32_t kMaxLevelCount = 32;  // a uint32 size has at most 32 levels
constexpr std::uint32_t kLayerCount = 2;      // lean1, lean2

// Khronos Data Format (KDFWG) constants used by the basic descriptor block.
constexpr std::uint32_t kDfdVersion13 = 2;
constexpr std::uint32_t kDfdModelRgbsda = 1;
constexpr std::uint32_t kDfdPrimariesBt709 = 1;
constexpr std::uint32_t kDfdTransferLinear = 1;
constexpr std::uint32_t kDfdChannelAlpha = 15;
constexpr std::uint32_t kDfdQualifierSigned = 0x4;
constexpr std::uint32_t kDfdQualifierFloat = 0x8;
constexpr std::uint32_t kDfdBlockHeaderSize = 24;
constexpr std::uint32_t kDfdSampleSize = 16;
constexpr std::uint32_t kFloatMinusOneBits = 0xBF800000u;  // -1.0f
constexpr std::uint32_t kFloatOneBits = 0x3F800000u;       // 1.0f

constexpr const char* kKeyOrientation = "KTXorientation";
constexpr const char* kKeyWriter = "KTXwriter";

struct FormatInfo {
    Storage storage;
    std::uint32_t vk_format;
    std::uint32_t type_size;    // bytes per channel
    std::uint32_t texel_bytes;  // bytes per RGBA texel
    bool is_float;
    const char* name;
};

constexpr std::array<FormatInfo, 4> kFormats = {{
    {Storage::Unorm8, kVkFormatR8G8B8A8Unorm, 1, 4, false, "VK_FORMAT_R8G8B8A8_UNORM"},
    {Storage::Unorm16, kVkFormatR16G16B16A16Unorm, 2, 8, false, "VK_FORMAT_R16G16B16A16_UNORM"},
    {Storage::Float16, kVkFormatR16G16B16A16Sfloat, 2, 8, true, "VK_FORMAT_R16G16B16A16_SFLOAT"},
    {Storage::Float32, kVkFormatR32G32B32A32Sfloat, 4, 16, true, "VK_FORMAT_R32G32B32A32_SFLOAT"},
}};

const FormatInfo* find_format(std::uint32_t vk_format) {
    for (const FormatInfo& format : kFormats) {
        if (format.vk_format == vk_format) return &format;
    }
    return nullptr;
}

const FormatInfo& format_of(Storage storage) {
    for (const FormatInfo& format : kFormats) {
        if (format.storage == storage) return format;
    }
    throw Error("", "unknown storage");
}

std::uint64_t align_up(std::uint64_t value, std::uint64_t alignment) {
    return (value + alignment - 1) / alignment * alignment;
}

// Alignment of level data: lcm(texel block size, 4).
std::uint64_t level_alignment(const FormatInfo& format) {
    return std::lcm(std::uint64_t(format.texel_bytes), std::uint64_t(4));
}

std::uint32_t full_chain_length(std::uint32_t width, std::uint32_t height) {
    std::uint32_t levels = 1;
    for (std::uint32_t size = std::max(width, height); size > 1; size /= 2) ++levels;
    return levels;
}

std::uint32_t level_size(std::uint32_t size, std::uint32_t level) {
    return std::max<std::uint32_t>(1, level < 32 ? size >> level : 0);
}

// Bytes of one layer of one level.
std::uint64_t layer_bytes(const FormatInfo& format, std::uint32_t width, std::uint32_t height) {
    return std::uint64_t(width) * height * format.texel_bytes;
}

// True when [offset, offset + length) lies inside a file of `size` bytes (no overflow).
bool inside(std::uint64_t offset, std::uint64_t length, std::uint64_t size) {
    return offset <= size && length <= size - offset;
}

Ktx2DataFormat expected_data_format(const FormatInfo& format) {
    Ktx2DataFormat data_format;
    data_format.descriptor_block_size = kDfdBlockHeaderSize + 4 * kDfdSampleSize;
    data_format.total_size = 4 + data_format.descriptor_block_size;
    data_format.version_number = kDfdVersion13;
    data_format.color_model = kDfdModelRgbsda;
    data_format.color_primaries = kDfdPrimariesBt709;
    data_format.transfer_function = kDfdTransferLinear;
    data_format.bytes_plane[0] = format.texel_bytes;
    const std::uint32_t bits = format.type_size * 8;
    for (std::uint32_t channel = 0; channel < 4; ++channel) {
        Ktx2Sample sample;
        sample.bit_offset = channel * bits;
        sample.bit_length = bits;
        sample.channel_id = channel < 3 ? channel : kDfdChannelAlpha;
        if (format.is_float) {
            sample.qualifiers = kDfdQualifierFloat | kDfdQualifierSigned;
            sample.sample_lower = kFloatMinusOneBits;
            sample.sample_upper = kFloatOneBits;
        } else {
            sample.sample_lower = 0;
            sample.sample_upper = bits == 8 ? 255u : 65535u;
        }
        data_format.samples.push_back(sample);
    }
    return data_format;
}

std::vector<std::uint8_t> encode_data_format(const Ktx2DataFormat& data_format) {
    std::vector<std::uint8_t> bytes;
    append_u32_le(bytes, data_format.total_size);
    append_u32_le(bytes, data_format.vendor_id | (data_format.descriptor_type << 17));
    append_u32_le(bytes, data_format.version_number | (data_format.descriptor_block_size << 16));
    append_u32_le(bytes, data_format.color_model | (data_format.color_primaries << 8) |
                             (data_format.transfer_function << 16) | (data_format.flags << 24));
    std::uint32_t dimensions = 0;
    for (int i = 0; i < 4; ++i) dimensions |= data_format.texel_block_dimensions[i] << (8 * i);
    append_u32_le(bytes, dimensions);
    for (int word = 0; word < 2; ++word) {
        std::uint32_t planes = 0;
        for (int i = 0; i < 4; ++i) planes |= data_format.bytes_plane[4 * word + i] << (8 * i);
        append_u32_le(bytes, planes);
    }
    for (const Ktx2Sample& sample : data_format.samples) {
        append_u32_le(bytes, sample.bit_offset | ((sample.bit_length - 1) << 16) |
                                 ((sample.channel_id | (sample.qualifiers << 4)) << 24));
        append_u32_le(bytes, 0);  // sample position: texel origin
        append_u32_le(bytes, sample.sample_lower);
        append_u32_le(bytes, sample.sample_upper);
    }
    return bytes;
}

Ktx2DataFormat decode_data_format(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    if (bytes.size() < 4 + kDfdBlockHeaderSize) {
        throw Error(
            path, "data format descriptor too short (" + std::to_string(bytes.size()) + " bytes)");
    }
    Ktx2DataFormat data_format;
    data_format.total_size = load_u32_le(bytes.data());
    if (data_format.total_size != bytes.size()) {
        throw Error(path, "dfdTotalSize " + std::to_string(data_format.total_size) +
                              " differs from dfdByteLength " + std::to_string(bytes.size()));
    }
    const std::uint8_t* block = bytes.data() + 4;
    const std::uint32_t word0 = load_u32_le(block);
    const std::uint32_t word1 = load_u32_le(block + 4);
    const std::uint32_t word2 = load_u32_le(block + 8);
    const std::uint32_t word3 = load_u32_le(block + 12);
    data_format.vendor_id = word0 & 0x1FFFFu;
    data_format.descriptor_type = word0 >> 17;
    data_format.version_number = word1 & 0xFFFFu;
    data_format.descriptor_block_size = word1 >> 16;
    data_format.color_model = word2 & 0xFF;
    data_format.color_primaries = (word2 >> 8) & 0xFF;
    data_format.transfer_function = (word2 >> 16) & 0xFF;
    data_format.flags = word2 >> 24;
    for (int i = 0; i < 4; ++i) data_format.texel_block_dimensions[i] = (word3 >> (8 * i)) & 0xFF;
    for (int i = 0; i < 8; ++i) data_format.bytes_plane[i] = block[16 + i];
    const std::uint32_t block_size = data_format.descriptor_block_size;
    if (block_size < kDfdBlockHeaderSize || block_size > bytes.size() - 4 ||
        (block_size - kDfdBlockHeaderSize) % kDfdSampleSize != 0) {
        throw Error(path, "bad data format descriptor block size " + std::to_string(block_size));
    }
    const std::uint32_t sample_count = (block_size - kDfdBlockHeaderSize) / kDfdSampleSize;
    for (std::uint32_t i = 0; i < sample_count; ++i) {
        const std::uint8_t* sample_bytes = block + kDfdBlockHeaderSize + i * kDfdSampleSize;
        const std::uint32_t word = load_u32_le(sample_bytes);
        Ktx2Sample sample;
        sample.bit_offset = word & 0xFFFF;
        sample.bit_length = ((word >> 16) & 0xFF) + 1;
        sample.channel_id = (word >> 24) & 0xF;
        sample.qualifiers = word >> 28;
        sample.sample_lower = load_u32_le(sample_bytes + 8);
        sample.sample_upper = load_u32_le(sample_bytes + 12);
        data_format.samples.push_back(sample);
    }
    return data_format;
}

std::vector<std::pair<std::string, std::string>> decode_key_values(
    const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::vector<std::pair<std::string, std::string>> key_values;
    std::size_t position = 0;
    while (bytes.size() - position >= 4) {
        const std::uint32_t length = load_u32_le(bytes.data() + position);
        position += 4;
        if (length > bytes.size() - position) {
            throw Error(path, "key/value entry of " + std::to_string(length) +
                                  " bytes runs past the key/value data");
        }
        const auto* entry = reinterpret_cast<const char*>(bytes.data() + position);
        const void* terminator = std::memchr(entry, '\0', length);
        if (terminator == nullptr) throw Error(path, "key/value entry without a NUL after its key");
        const std::size_t key_length = std::size_t(static_cast<const char*>(terminator) - entry);
        std::string value(entry + key_length + 1, length - key_length - 1);
        if (!value.empty() && value.back() == '\0') value.pop_back();
        std::string key(entry, key_length);
        for (const auto& [seen, unused] : key_values) {
            if (seen == key) {
                throw Error(path, "key/value data holds the key '" + escape_text(key) +
                                      "' more than once");
            }
        }
        key_values.emplace_back(std::move(key), std::move(value));
        position = std::size_t(align_up(position + length, 4));
        if (position > bytes.size()) break;  // final padding not counted in kvdByteLength
    }
    return key_values;
}

std::string format_float(float value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

// A count of texels written by to_string: decimal digits only.
std::uint64_t parse_count(const std::string& path, const std::string& key,
                          const std::string& text) {
    std::uint64_t value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size()) {
        throw Error(path, "bad " + key + " value '" + escape_text(text) +
                              "' (expected a count of texels)");
    }
    return value;
}

float parse_float(const std::string& path, const std::string& key, const std::string& text) {
    float value = 0.0f;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (result.ec != std::errc() || result.ptr != text.data() + text.size() ||
        !std::isfinite(value)) {
        throw Error(path, "bad " + key + " value '" + escape_text(text) + "'");
    }
    return value;
}

void append_key_value(std::vector<std::uint8_t>& out, const std::string& key,
                      const std::string& value) {
    const std::uint32_t length = std::uint32_t(key.size() + 1 + value.size() + 1);
    append_u32_le(out, length);
    out.insert(out.end(), key.begin(), key.end());
    out.push_back(0);
    out.insert(out.end(), value.begin(), value.end());
    out.push_back(0);  // string values are NUL-terminated, as KTXorientation and KTXwriter require
    while (out.size() % 4 != 0) out.push_back(0);
}

// check_layers: the layers' byte counts too (not for a layout whose layers are written later).
void validate_for_write(const std::string& path, const PackedLeanMap& map,
                        const FormatInfo& format, bool check_layers) {
    if (map.levels.empty()) throw Error(path, "LEAN map without levels");
    const PackedLevel& top = map.levels.front();
    if (top.width < 1 || top.height < 1) {
        throw Error(path, "LEAN map level 0 has size " + std::to_string(top.width) + "x" +
                              std::to_string(top.height));
    }
    const std::uint32_t chain =
        full_chain_length(std::uint32_t(top.width), std::uint32_t(top.height));
    if (map.levels.size() != chain) {  // read_ktx2 refuses a partial chain
        throw Error(path, std::to_string(map.levels.size()) + " levels for a " +
                              std::to_string(top.width) + "x" + std::to_string(top.height) +
                              " map (a LEAN map has all " + std::to_string(chain) +
                              " levels of its MIP chain)");
    }
    for (std::size_t i = 0; i < map.levels.size(); ++i) {
        const PackedLevel& level = map.levels[i];
        const std::uint32_t width = level_size(std::uint32_t(top.width), std::uint32_t(i));
        const std::uint32_t height = level_size(std::uint32_t(top.height), std::uint32_t(i));
        if (level.width != int(width) || level.height != int(height)) {
            throw Error(path, "level " + std::to_string(i) + " is " + std::to_string(level.width) +
                                  "x" + std::to_string(level.height) + ", expected " +
                                  std::to_string(width) + "x" + std::to_string(height));
        }
        const std::uint64_t expected = layer_bytes(format, width, height);
        if (check_layers && (level.lean1.size() != expected || level.lean2.size() != expected)) {
            throw Error(path, "level " + std::to_string(i) + " layers hold " +
                                  std::to_string(level.lean1.size()) + " and " +
                                  std::to_string(level.lean2.size()) + " bytes, expected " +
                                  std::to_string(expected));
        }
    }
    if (!(std::isfinite(map.scale) && map.scale > 0.0f)) {
        throw Error(path, "LEAN scale " + format_float(map.scale) + " is not finite and > 0");
    }
    if (!(std::isfinite(map.baked_shininess) && map.baked_shininess >= 0.0f)) {
        throw Error(path, "baked shininess " + format_float(map.baked_shininess) +
                              " is not finite and >= 0");
    }
}

const char* normal_convention_name(NormalConvention convention) {
    return convention == NormalConvention::DirectX ? "directx" : "opengl";
}

}  // namespace

std::uint32_t vk_format_of(Storage storage) {
    return format_of(storage).vk_format;
}

const char* vk_format_name(std::uint32_t vk_format) {
    const FormatInfo* format = find_format(vk_format);
    return format != nullptr ? format->name : "unknown";
}

const std::string* Ktx2Info::find(const std::string& key) const {
    for (const auto& [entry_key, value] : key_values) {
        if (entry_key == key) return &value;
    }
    return nullptr;
}

namespace {

// Where everything goes in a KTX2 file of `layout`: the bytes of its header, level index, DFD and
// key/value data, and each level's offset and length (both layers) in a file of `size` bytes.
struct Ktx2FilePlan {
    std::vector<std::uint8_t> head;
    std::vector<std::uint64_t> level_offsets;
    std::vector<std::uint64_t> level_lengths;
    std::uint64_t size = 0;
};

Ktx2FilePlan plan_ktx2_file(const std::string& path, const PackedLeanMap& layout, bool check_layers,
                            const char* layout_name = kLeanLayoutName) {
    const FormatInfo& format = format_of(layout.storage);
    validate_for_write(path, layout, format, check_layers);
    const auto level_count = std::uint32_t(layout.levels.size());
    const PackedLevel& top = layout.levels.front();

    std::vector<std::pair<std::string, std::string>> key_values = {
        {kKeyOrientation, "rd"},
        {kKeyWriter,
         layout.generator.empty() ? std::string("leanfade " LEANFADE_VERSION) : layout.generator},
        {kScaleKey, format_float(layout.scale)},
        {kRoughnessBakedKey, layout.roughness_baked ? "1" : "0"},
        {kBakedShininessKey, format_float(layout.baked_shininess)},
        {kNormalConventionKey, normal_convention_name(layout.source_convention)},
        {kLayoutKey, layout_name},
    };
    if (layout.normal_repairs.padding_texels > 0)
        key_values.emplace_back(kPaddingTexelsKey,
                                std::to_string(layout.normal_repairs.padding_texels));
    if (layout.normal_repairs.raised_texels > 0)
        key_values.emplace_back(kRaisedTexelsKey,
                                std::to_string(layout.normal_repairs.raised_texels));
    if (layout.source_looks_flipped) key_values.emplace_back(kConventionWarningKey, "other");
    std::sort(key_values.begin(), key_values.end());  // by key bytes, as the spec requires
    std::vector<std::uint8_t> key_value_bytes;
    for (const auto& [key, value] : key_values) append_key_value(key_value_bytes, key, value);

    const std::vector<std::uint8_t> dfd_bytes = encode_data_format(expected_data_format(format));
    const std::uint64_t dfd_offset = kHeaderSize + kLevelIndexEntrySize * level_count;
    const std::uint64_t kvd_offset = dfd_offset + dfd_bytes.size();

    // Level data from the smallest level to the largest, each aligned.
    std::vector<std::uint64_t> level_offsets(level_count), level_lengths(level_count);
    std::uint64_t end = kvd_offset + key_value_bytes.size();
    for (std::uint32_t level = level_count; level-- > 0;) {
        end = align_up(end, level_alignment(format));
        level_offsets[level] = end;
        level_lengths[level] =
            2 * layer_bytes(format, std::uint32_t(layout.levels[level].width),
                            std::uint32_t(layout.levels[level].height));
        end += level_lengths[level];
    }
    if (end > std::uint64_t(SIZE_MAX)) throw Error(path, "LEAN map too large to write");

    // Header, level index, DFD and key/value data: a few hundred bytes.
    std::vector<std::uint8_t> bytes(kIdentifier.begin(), kIdentifier.end());
    append_u32_le(bytes, format.vk_format);
    append_u32_le(bytes, format.type_size);
    append_u32_le(bytes, std::uint32_t(top.width));
    append_u32_le(bytes, std::uint32_t(top.height));
    append_u32_le(bytes, 0);  // pixelDepth: 2D
    append_u32_le(bytes, kLayerCount);
    append_u32_le(bytes, 1);  // faceCount
    append_u32_le(bytes, level_count);
    append_u32_le(bytes, 0);  // supercompressionScheme: none
    append_u32_le(bytes, std::uint32_t(dfd_offset));
    append_u32_le(bytes, std::uint32_t(dfd_bytes.size()));
    append_u32_le(bytes, std::uint32_t(kvd_offset));
    append_u32_le(bytes, std::uint32_t(key_value_bytes.size()));
    append_u64_le(bytes, 0);  // sgdByteOffset
    append_u64_le(bytes, 0);  // sgdByteLength
    for (std::uint32_t level = 0; level < level_count; ++level) {
        append_u64_le(bytes, level_offsets[level]);
        append_u64_le(bytes, level_lengths[level]);  // byteLength
        append_u64_le(bytes, level_lengths[level]);  // uncompressedByteLength
    }
    bytes.insert(bytes.end(), dfd_bytes.begin(), dfd_bytes.end());
    bytes.insert(bytes.end(), key_value_bytes.begin(), key_value_bytes.end());

    return {std::move(bytes), std::move(level_offsets), std::move(level_lengths), end};
}

}  // namespace

Ktx2Writer::Ktx2Writer(std::string path, const PackedLeanMap& layout, const WriteOptions& options,
                       bool check_layers, const char* layout_name)
    : file_(path, options.durability) {
    const Ktx2FilePlan plan = plan_ktx2_file(path, layout, check_layers, layout_name);
    // The level data goes straight into the mapped file; the mip padding between levels is left
    // as the zeros a newly reserved file reads as.
    std::uint8_t* output = file_.map(std::size_t(plan.size));
    std::memcpy(output, plan.head.data(), plan.head.size());
    for (std::size_t level = 0; level < plan.level_offsets.size(); ++level) {
        std::uint8_t* lean1 = output + plan.level_offsets[level];
        targets_.push_back({lean1, lean1 + plan.level_lengths[level] / 2});
    }
}

void Ktx2Writer::commit() {
    targets_.clear();
    file_.commit();
}

PackedBakeResult bake_to_ktx2(const std::string& path,
                              const std::variant<Image, UnormImage>& input, BakeSource source,
                              const BakeOptions& options, Storage storage,
                              const std::string& generator, const std::string& source_name,
                              const WriteOptions& write_options) {
    std::optional<Ktx2Writer> writer;
    const auto open_output = [&](const PackedLeanMap& layout) {
        writer.emplace(path, layout, write_options);
        return writer->targets();
    };
    PackedBakeResult baked = std::visit(
        [&](const auto& image) {
            return bake_packed_to(open_output, image, source, options, storage, generator,
                                  source_name);
        },
        input);
    writer->commit();
    return baked;
}

std::vector<std::uint8_t> write_ktx2_to_memory(const PackedLeanMap& map, const std::string& name) {
    const Ktx2FilePlan plan = plan_ktx2_file(name, map, true);
    std::vector<std::uint8_t> file(std::size_t(plan.size), 0);  // mip padding: zeros
    std::copy(plan.head.begin(), plan.head.end(), file.begin());
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
        const PackedLevel& packed = map.levels[level];
        const auto lean1 = file.begin() + std::ptrdiff_t(plan.level_offsets[level]);
        std::copy(packed.lean1.begin(), packed.lean1.end(), lean1);
        std::copy(packed.lean2.begin(), packed.lean2.end(),
                  lean1 + std::ptrdiff_t(plan.level_lengths[level] / 2));
    }
    return file;
}

namespace {

void write_ktx2_as(const std::string& path, const PackedLeanMap& map, const WriteOptions& options,
                   const char* layout_name) {
    Ktx2Writer writer(path, map, options, true, layout_name);
    const std::vector<PackedLevelTarget>& targets = writer.targets();
    // Copied from the map in chunks handed to the threads (no assembled copy of the whole file).
    struct Chunk {
        const std::uint8_t* source;
        std::uint8_t* destination;
        std::size_t size;
    };
    constexpr std::size_t kChunkBytes = std::size_t(4) << 20;
    std::vector<Chunk> chunks;
    for (std::size_t level = 0; level < map.levels.size(); ++level) {
        const PackedLevel& packed = map.levels[level];
        for (int layer = 0; layer < 2; ++layer) {
            const std::vector<std::uint8_t>& source = layer == 0 ? packed.lean1 : packed.lean2;
            std::uint8_t* destination = layer == 0 ? targets[level].lean1 : targets[level].lean2;
            for (std::size_t first = 0; first < source.size(); first += kChunkBytes) {
                chunks.push_back({source.data() + first, destination + first,
                                  std::min(kChunkBytes, source.size() - first)});
            }
        }
    }
    parallel_for_dynamic(int(chunks.size()), options.threads, 1, [&](int, int first, int last) {
        for (int i = first; i < last; ++i) {
            const Chunk& chunk = chunks[std::size_t(i)];
            std::memcpy(chunk.destination, chunk.source, chunk.size);
        }
    });
    writer.commit();
}

}  // namespace

void write_ktx2(const std::string& path, const PackedLeanMap& map, const WriteOptions& options) {
    write_ktx2_as(path, map, options, kLeanLayoutName);
}

void write_cross_term_ktx2(const std::string& path, const PackedLeanMap& map,
                           const WriteOptions& options) {
    write_ktx2_as(path, map, options, kCrossTermLayoutName);
}

namespace {

// The leanfade-specific header checks, run before the level index, DFD or key/value data are
// read (so that absurd sizes are refused before anything is allocated for them).
void validate_lean_header(const std::string& path, const Ktx2Info& info,
                          const ReadOptions& options) {
    const FormatInfo* format = find_format(info.vk_format);
    if (format == nullptr) {
        throw Error(path, "unsupported vkFormat " + std::to_string(info.vk_format) +
                              " (expected 37, 91, 97 or 109)");
    }
    if (info.type_size != format->type_size) {
        throw Error(
            path, "typeSize " + std::to_string(info.type_size) + " does not match " + format->name);
    }
    detail::check_dimensions(path, info.pixel_width, info.pixel_height, options.max_dimension);
    if (info.pixel_depth != 0) {
        throw Error(path, "pixelDepth " + std::to_string(info.pixel_depth) + " (a LEAN map is 2D)");
    }
    if (info.layer_count != kLayerCount) {
        throw Error(path, "layerCount " + std::to_string(info.layer_count) +
                              " (a LEAN map has 2 layers: lean1, lean2)");
    }
    if (info.face_count != 1) {
        throw Error(path, "faceCount " + std::to_string(info.face_count) + " (expected 1)");
    }
    if (info.supercompression_scheme != 0) {
        throw Error(path, "supercompressionScheme " + std::to_string(info.supercompression_scheme) +
                              " is not supported");
    }
    const std::uint32_t chain = full_chain_length(info.pixel_width, info.pixel_height);
    if (info.level_count == 0) {
        throw Error(path, "levelCount 0 (MIP levels generated at load) is not supported");
    }
    if (info.level_count > chain) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) + " exceeds the " +
                              std::to_string(chain) + " levels of a " +
                              std::to_string(info.pixel_width) + "x" +
                              std::to_string(info.pixel_height) + " MIP chain");
    }
    if (info.level_count < chain) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) +
                              " is a partial MIP chain (a LEAN map of " +
                              std::to_string(info.pixel_width) + "x" +
                              std::to_string(info.pixel_height) + " has all " +
                              std::to_string(chain) + " levels)");
    }
}

// Float storages can hold NaN and infinity, which no bake writes and no renderer can use: the
// first one is refused, naming its level, layer and texel.
void check_finite_texels(const std::string& path, const FormatInfo& format,
                         const PackedLevel& level, std::uint32_t level_number) {
    if (!format.is_float) return;
    const std::vector<std::uint8_t>* layers[2] = {&level.lean1, &level.lean2};
    for (int layer = 0; layer < 2; ++layer) {
        const std::vector<std::uint8_t>& bytes = *layers[layer];
        const std::size_t values = bytes.size() / format.type_size;
        for (std::size_t i = 0; i < values; ++i) {
            bool finite = true, nan = false;
            if (format.type_size == 2) {
                const std::uint16_t bits = detail::load_u16_le(bytes.data() + 2 * i);
                finite = (bits & 0x7C00u) != 0x7C00u;
                nan = !finite && (bits & 0x03FFu) != 0;
            } else {
                const std::uint32_t bits = load_u32_le(bytes.data() + 4 * i);
                finite = (bits & 0x7F800000u) != 0x7F800000u;
                nan = !finite && (bits & 0x007FFFFFu) != 0;
            }
            if (finite) continue;
            const std::size_t texel = i / 4;
            throw Error(path, std::string(nan ? "NaN" : "infinity") + " in level " +
                                  std::to_string(level_number) + " of lean" +
                                  std::to_string(layer + 1) + " at texel (" +
                                  std::to_string(texel % std::size_t(level.width)) + ", " +
                                  std::to_string(texel / std::size_t(level.width)) + ")");
        }
    }
}

// Every part of the file (the header with the level index, the data format descriptor, the
// key/value data, the supercompression global data and each level) must lie apart from every
// other: a level inside the header or two levels sharing bytes are refused.
void check_no_overlaps(const std::string& path, const Ktx2Info& info) {
    struct Part {
        std::uint64_t offset, length;
        std::string name;
    };
    std::vector<Part> parts = {
        {0, kHeaderSize + kLevelIndexEntrySize * std::uint64_t(info.levels.size()),
         "the header and level index"},
        {info.dfd_byte_offset, info.dfd_byte_length, "the data format descriptor"},
        {info.kvd_byte_offset, info.kvd_byte_length, "the key/value data"},
        {info.sgd_byte_offset, info.sgd_byte_length, "the supercompression global data"}};
    for (std::size_t level = 0; level < info.levels.size(); ++level) {
        parts.push_back({info.levels[level].byte_offset, info.levels[level].byte_length,
                         "level " + std::to_string(level) + " data"});
    }
    std::erase_if(parts, [](const Part& part) { return part.length == 0; });
    std::stable_sort(parts.begin(), parts.end(),
                     [](const Part& a, const Part& b) { return a.offset < b.offset; });
    for (std::size_t i = 1; i < parts.size(); ++i) {
        const Part& before = parts[i - 1];
        const Part& part = parts[i];
        if (part.offset < before.offset + before.length) {  // both inside the file: no overflow
            throw Error(path, part.name + " (offset " + std::to_string(part.offset) +
                                  ", length " + std::to_string(part.length) + ") overlaps " +
                                  before.name + " (offset " + std::to_string(before.offset) +
                                  ", length " + std::to_string(before.length) + ")");
        }
    }
}

// `strict`: also run validate_lean_header (read_ktx2).
Ktx2Info inspect_open_file(const detail::InputFile& file, const ReadOptions* strict) {
    const std::string& path = file.path();
    Ktx2Info info;
    info.path = path;
    info.file_size = file.size();

    std::array<std::uint8_t, kHeaderSize> header{};
    const std::size_t identifier_bytes = std::size_t(std::min<std::uint64_t>(file.size(), 12));
    file.read_at(0, header.data(), identifier_bytes, "truncated KTX2 identifier");
    if (std::memcmp(header.data(), kIdentifier.data(), identifier_bytes) != 0) {
        throw Error(path, "not a KTX 2.0 file (bad identifier)");
    }
    if (identifier_bytes < kIdentifier.size()) throw Error(path, "truncated KTX2 identifier");
    file.read_at(0, header.data(), kHeaderSize, "truncated KTX2 header");

    const std::uint8_t* field = header.data() + kIdentifier.size();
    info.vk_format = load_u32_le(field + 0);
    info.type_size = load_u32_le(field + 4);
    info.pixel_width = load_u32_le(field + 8);
    info.pixel_height = load_u32_le(field + 12);
    info.pixel_depth = load_u32_le(field + 16);
    info.layer_count = load_u32_le(field + 20);
    info.face_count = load_u32_le(field + 24);
    info.level_count = load_u32_le(field + 28);
    info.supercompression_scheme = load_u32_le(field + 32);
    info.dfd_byte_offset = load_u32_le(field + 36);
    info.dfd_byte_length = load_u32_le(field + 40);
    info.kvd_byte_offset = load_u32_le(field + 44);
    info.kvd_byte_length = load_u32_le(field + 48);
    info.sgd_byte_offset = load_u64_le(field + 52);
    info.sgd_byte_length = load_u64_le(field + 60);

    if (strict != nullptr) validate_lean_header(path, info, *strict);
    if (info.level_count > kMaxLevelCount) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) + " is more than " +
                              std::to_string(kMaxLevelCount));
    }
    // Any KTX2: at most one level per halving of the largest side; checked before the level
    // index is read, so that a count past the chain is named as such (not as the garbage
    // offsets the extra index entries would hold).
    const std::uint32_t chain =
        full_chain_length(std::max(info.pixel_width, info.pixel_depth), info.pixel_height);
    if (info.level_count > chain) {
        throw Error(path, "levelCount " + std::to_string(info.level_count) + " exceeds the " +
                              std::to_string(chain) + " levels of a " +
                              std::to_string(info.pixel_width) + "x" +
                              std::to_string(info.pixel_height) +
                              (info.pixel_depth > 1 ? "x" + std::to_string(info.pixel_depth) : "") +
                              " MIP chain");
    }
    const std::uint32_t index_entries = std::max<std::uint32_t>(1, info.level_count);
    std::vector<std::uint8_t> index(index_entries * kLevelIndexEntrySize);
    file.read_at(kHeaderSize, index.data(), index.size(), "truncated KTX2 level index");
    for (std::uint32_t level = 0; level < index_entries; ++level) {
        const std::uint8_t* entry = index.data() + level * kLevelIndexEntrySize;
        Ktx2Level level_info;
        level_info.width = level_size(info.pixel_width, level);
        level_info.height = level_size(info.pixel_height, level);
        level_info.byte_offset = load_u64_le(entry);
        level_info.byte_length = load_u64_le(entry + 8);
        level_info.uncompressed_byte_length = load_u64_le(entry + 16);
        if (!inside(level_info.byte_offset, level_info.byte_length, info.file_size)) {
            throw Error(path, "level " + std::to_string(level) + " data (offset " +
                                  std::to_string(level_info.byte_offset) + ", length " +
                                  std::to_string(level_info.byte_length) +
                                  ") runs past the end of the file (" +
                                  std::to_string(info.file_size) + " bytes)");
        }
        info.levels.push_back(level_info);
    }

    if (info.dfd_byte_length == 0) throw Error(path, "missing data format descriptor");
    if (!inside(info.dfd_byte_offset, info.dfd_byte_length, info.file_size)) {
        throw Error(path, "data format descriptor runs past the end of the file");
    }
    if (!inside(info.kvd_byte_offset, info.kvd_byte_length, info.file_size)) {
        throw Error(path, "key/value data runs past the end of the file");
    }
    if (!inside(info.sgd_byte_offset, info.sgd_byte_length, info.file_size)) {
        throw Error(path, "supercompression global data runs past the end of the file");
    }
    check_no_overlaps(path, info);

    std::vector<std::uint8_t> dfd(info.dfd_byte_length);
    file.read_at(info.dfd_byte_offset, dfd.data(), dfd.size(), "truncated data format descriptor");
    info.data_format = decode_data_format(path, dfd);

    std::vector<std::uint8_t> kvd(info.kvd_byte_length);
    file.read_at(info.kvd_byte_offset, kvd.data(), kvd.size(), "truncated key/value data");
    info.key_values = decode_key_values(path, kvd);
    return info;
}

void validate_data_format(const std::string& path, const Ktx2DataFormat& actual,
                          const FormatInfo& format) {
    const Ktx2DataFormat expected = expected_data_format(format);
    const auto fail = [&](const std::string& what) {
        throw Error(path, "data format descriptor does not describe " + std::string(format.name) +
                              " (" + what + ")");
    };
    if (actual.vendor_id != 0 || actual.descriptor_type != 0) fail("not a basic descriptor");
    if (actual.color_model != expected.color_model) fail("colour model is not RGBSDA");
    if (actual.transfer_function != expected.transfer_function) fail("transfer is not LINEAR");
    if (actual.bytes_plane[0] != expected.bytes_plane[0]) fail("bytesPlane0");
    for (int i = 0; i < 4; ++i) {
        if (actual.texel_block_dimensions[i] != 0) fail("texel block is not 1x1x1x1");
    }
    if (actual.samples.size() != expected.samples.size()) fail("sample count");
    for (std::size_t i = 0; i < expected.samples.size(); ++i) {
        const Ktx2Sample& a = actual.samples[i];
        const Ktx2Sample& e = expected.samples[i];
        if (a.bit_offset != e.bit_offset || a.bit_length != e.bit_length ||
            a.channel_id != e.channel_id || a.qualifiers != e.qualifiers ||
            a.sample_lower != e.sample_lower || a.sample_upper != e.sample_upper) {
            fail("sample " + std::to_string(i));
        }
    }
}

const std::string& required_key(const std::string& path, const Ktx2Info& info, const char* key) {
    const std::string* value = info.find(key);
    if (value == nullptr) throw Error(path, std::string("missing key ") + key);
    return *value;
}

PackedLeanMap read_open_file(const detail::InputFile& file, const ReadOptions& options,
                             const char* layout_name = kLeanLayoutName) {
    const std::string& path = file.path();
    const Ktx2Info info = inspect_open_file(file, &options);
    const FormatInfo* format = find_format(info.vk_format);
    for (std::uint32_t level = 0; level < info.level_count; ++level) {
        const Ktx2Level& entry = info.levels[level];
        const std::uint64_t expected = 2 * layer_bytes(*format, entry.width, entry.height);
        if (entry.byte_length != expected || entry.uncompressed_byte_length != expected) {
            throw Error(path, "level " + std::to_string(level) + " byteLength " +
                                  std::to_string(entry.byte_length) + " / uncompressed " +
                                  std::to_string(entry.uncompressed_byte_length) + ", expected " +
                                  std::to_string(expected));
        }
        if (entry.byte_offset % level_alignment(*format) != 0) {
            throw Error(path, "level " + std::to_string(level) + " offset " +
                                  std::to_string(entry.byte_offset) + " is not aligned to " +
                                  std::to_string(level_alignment(*format)) + " bytes");
        }
    }
    validate_data_format(path, info.data_format, *format);

    PackedLeanMap map;
    map.storage = format->storage;
    const std::string& layout = required_key(path, info, kLayoutKey);
    if (layout == kCrossTermLayoutName && layout != layout_name)
        throw Error(path, "is a cross-term texture (bake --cross-terms), not a LEAN map");
    if (layout == kLeanLayoutName && layout != layout_name)
        throw Error(path, "is a LEAN map, not a cross-term texture");
    if (layout != layout_name) {
        throw Error(path, "unsupported " + std::string(kLayoutKey) + " '" + escape_text(layout) +
                              "' (expected '" + layout_name + "')");
    }
    map.scale = parse_float(path, kScaleKey, required_key(path, info, kScaleKey));
    if (!(map.scale > 0.0f)) throw Error(path, std::string(kScaleKey) + " must be > 0");
    if (map.scale > kMaxLeanScale)
        throw Error(path, std::string(kScaleKey) + " " + format_float(map.scale) +
                              " exceeds the largest sc a bake writes (" +
                              format_float(kMaxLeanScale) + ": slopes are at most 1e6)");
    const std::string& baked = required_key(path, info, kRoughnessBakedKey);
    if (baked != "0" && baked != "1") {
        throw Error(path, "bad " + std::string(kRoughnessBakedKey) + " value '" +
                              escape_text(baked) +
                              "' (expected 0 or 1)");
    }
    map.roughness_baked = baked == "1";
    map.baked_shininess =
        parse_float(path, kBakedShininessKey, required_key(path, info, kBakedShininessKey));
    if (map.baked_shininess < 0.0f) {
        throw Error(path, std::string(kBakedShininessKey) + " must be >= 0");
    }
    const std::string& convention = required_key(path, info, kNormalConventionKey);
    if (convention == "opengl") {
        map.source_convention = NormalConvention::OpenGL;
    } else if (convention == "directx") {
        map.source_convention = NormalConvention::DirectX;
    } else {
        throw Error(path, "bad " + std::string(kNormalConventionKey) + " value '" +
                              escape_text(convention) + "' (expected opengl or directx)");
    }
    for (const auto& [key, count] :
         {std::pair{kPaddingTexelsKey, &map.normal_repairs.padding_texels},
          std::pair{kRaisedTexelsKey, &map.normal_repairs.raised_texels}}) {
        if (const std::string* text = info.find(key); text != nullptr) *count =
            parse_count(path, key, *text);
    }
    if (const std::string* warning = info.find(kConventionWarningKey); warning != nullptr) {
        if (*warning != "other")
            throw Error(path, "bad " + std::string(kConventionWarningKey) + " value '" +
                                  escape_text(*warning) + "' (expected other)");
        map.source_looks_flipped = true;
    }
    if (const std::string* orientation = info.find(kKeyOrientation);
        orientation != nullptr && *orientation != "rd") {
        throw Error(path, "unsupported KTXorientation '" + escape_text(*orientation) +
                              "' (rows must be stored top first: rd)");
    }
    if (const std::string* writer = info.find(kKeyWriter); writer != nullptr) {
        map.generator = *writer;
    }

    // Every level was checked to lie inside the file with its exact size: the allocations
    // below are bounded by the file size.
    for (std::uint32_t level = 0; level < info.level_count; ++level) {
        const Ktx2Level& entry = info.levels[level];
        const std::uint64_t layer_size = entry.byte_length / 2;
        PackedLevel packed;
        packed.width = int(entry.width);
        packed.height = int(entry.height);
        packed.lean1.resize(std::size_t(layer_size));
        packed.lean2.resize(std::size_t(layer_size));
        file.read_at(entry.byte_offset, packed.lean1.data(), packed.lean1.size(),
                     "truncated level data");
        file.read_at(entry.byte_offset + layer_size, packed.lean2.data(), packed.lean2.size(),
                     "truncated level data");
        check_finite_texels(path, *format, packed, level);
        map.levels.push_back(std::move(packed));
    }
    return map;
}

}  // namespace

Ktx2Info inspect_ktx2(const std::string& path) {
    const detail::InputFile file(path);
    return inspect_open_file(file, nullptr);
}

Ktx2Info inspect_ktx2_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name) {
    const detail::InputFile file(name, bytes.data(), bytes.size());
    return inspect_open_file(file, nullptr);
}

PackedLeanMap read_ktx2(const std::string& path, const ReadOptions& options) {
    const detail::InputFile file(path);
    return read_open_file(file, options);
}

PackedLeanMap read_cross_term_ktx2(const std::string& path, const ReadOptions& options) {
    const detail::InputFile file(path);
    return read_open_file(file, options, kCrossTermLayoutName);
}

PackedLeanMap read_ktx2_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& name,
                                    const ReadOptions& options) {
    const detail::InputFile file(name, bytes.data(), bytes.size());
    return read_open_file(file, options);
}

std::string describe(const Ktx2Info& info) {
    std::ostringstream out;
    out << "file: " << info.path << " (" << info.file_size << " bytes, KTX 2.0)\n";
    out << "vkFormat: " << info.vk_format << " (" << vk_format_name(info.vk_format)
        << "), typeSize " << info.type_size << "\n";
    out << "size: " << info.pixel_width << " x " << info.pixel_height << ", pixelDepth "
        << info.pixel_depth << ", layerCount " << info.layer_count << ", faceCount "
        << info.face_count << ", levelCount " << info.level_count << ", supercompressionScheme "
        << info.supercompression_scheme << "\n";
    out << "index: dfd " << info.dfd_byte_offset << " +" << info.dfd_byte_length << ", kvd "
        << info.kvd_byte_offset << " +" << info.kvd_byte_length << ", sgd " << info.sgd_byte_offset
        << " +" << info.sgd_byte_length << "\n";
    const Ktx2DataFormat& dfd = info.data_format;
    out << "data format: model " << dfd.color_model
        << (dfd.color_model == kDfdModelRgbsda ? " (RGBSDA)" : "") << ", primaries "
        << dfd.color_primaries << (dfd.color_primaries == kDfdPrimariesBt709 ? " (BT709)" : "")
        << ", transfer " << dfd.transfer_function
        << (dfd.transfer_function == kDfdTransferLinear ? " (linear)"
            : dfd.transfer_function == 2                ? " (sRGB)"
                                                        : "")
        << ", flags " << dfd.flags << ", bytesPlane0 " << dfd.bytes_plane[0] << ", "
        << dfd.samples.size() << " samples\n";
    for (std::size_t i = 0; i < dfd.samples.size(); ++i) {
        const Ktx2Sample& sample = dfd.samples[i];
        // RGBSDA channel ids: 0 red, 1 green, 2 blue, 13 stencil, 14 depth, 15 alpha.
        static constexpr const char* kChannelNames[16] = {
            "R", "G", "B", "3", "4", "5", "6", "7", "8", "9", "10", "11", "12", "S", "D", "A"};
        char bounds[64];
        std::snprintf(bounds, sizeof bounds, "lower 0x%08X, upper 0x%08X", sample.sample_lower,
                      sample.sample_upper);
        out << "  sample " << i << ": channel " << kChannelNames[sample.channel_id & 0xF]
            << ", bits " << sample.bit_offset << ".." << sample.bit_offset + sample.bit_length - 1
            << (sample.qualifiers & kDfdQualifierFloat ? ", float" : "")
            << (sample.qualifiers & kDfdQualifierSigned ? ", signed" : "") << ", " << bounds
            << "\n";
    }
    for (std::size_t level = 0; level < info.levels.size(); ++level) {
        const Ktx2Level& entry = info.levels[level];
        out << "level " << level << ": " << entry.width << " x " << entry.height << ", offset "
            << entry.byte_offset << ", length " << entry.byte_length << " (uncompressed "
            << entry.uncompressed_byte_length << ")\n";
    }
    out << "key/values (" << info.key_values.size() << "):\n";
    for (const auto& [key, value] : info.key_values) {
        out << "  " << escape_text(key, SIZE_MAX) << " = " << escape_text(value, SIZE_MAX) << "\n";
    }
    return out.str();
}

}  // namespace leanfade::io
