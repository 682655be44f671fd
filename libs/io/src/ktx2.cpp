// KTX 2.0 (Khronos, https://registry.khronos.org/KTX/specs/2.0/ktxspec.v2.html) for LEAN maps:
// the formats, the data format descriptor and key/value text (ktx2_internal.hpp). All multi-byte
// fields are little-endian. File layout written (ktx2_write.cpp):
//   header (80 bytes) | level index (24 bytes per level) | DFD | key/value data |
//   padding | level n-1 | ... | level 0
#include "leanfade/io/ktx2.hpp"

#include "ktx2_internal.hpp"

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
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

namespace leanfade::io {

namespace ktx2_detail {

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

std::uint64_t level_alignment(const FormatInfo& format, bool supercompressed) {
    if (supercompressed) return 1;
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

std::uint64_t layer_bytes(const FormatInfo& format, std::uint32_t width, std::uint32_t height) {
    return std::uint64_t(width) * height * format.texel_bytes;
}

bool inside(std::uint64_t offset, std::uint64_t length, std::uint64_t size) {
    return offset <= size && length <= size - offset;
}

Ktx2DataFormat expected_data_format(const FormatInfo& format, bool supercompressed) {
    Ktx2DataFormat data_format;
    data_format.descriptor_block_size = kDfdBlockHeaderSize + 4 * kDfdSampleSize;
    data_format.total_size = 4 + data_format.descriptor_block_size;
    data_format.version_number = kDfdVersion13;
    data_format.color_model = kDfdModelRgbsda;
    data_format.color_primaries = kDfdPrimariesBt709;
    data_format.transfer_function = kDfdTransferLinear;
    data_format.bytes_plane[0] = supercompressed ? 0 : format.texel_bytes;
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
                throw Error(
                    path, "key/value data holds the key '" + escape_text(key) + "' more than once");
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

std::uint64_t parse_count(const std::string& path, const std::string& key,
                          const std::string& text) {
    std::uint64_t value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size()) {
        throw Error(
            path, "bad " + key + " value '" + escape_text(text) + "' (expected a count of texels)");
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

std::vector<std::pair<std::string, std::string>> lean_metadata_keys(const PackedLeanMap& map) {
    std::vector<std::pair<std::string, std::string>> keys = {
        {kScaleKey, format_float(map.scale)},
        {kRoughnessBakedKey, map.roughness_baked ? "1" : "0"},
        {kBakedShininessKey, format_float(map.baked_shininess)},
        {kNormalConventionKey, normal_convention_name(map.source_convention)},
    };
    if (map.normal_repairs.padding_texels > 0)
        keys.emplace_back(kPaddingTexelsKey, std::to_string(map.normal_repairs.padding_texels));
    if (map.normal_repairs.raised_texels > 0)
        keys.emplace_back(kRaisedTexelsKey, std::to_string(map.normal_repairs.raised_texels));
    if (map.source_looks_flipped) keys.emplace_back(kConventionWarningKey, "other");
    if (map.has_plateau()) keys.emplace_back(kPlateauEpsilonKey, format_float(map.plateau_epsilon));
    return keys;
}

void validate_for_write(const std::string& path, const PackedLeanMap& map, const FormatInfo& format,
                        bool check_layers) {
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
        for (const LeanLayerInfo& row : kLeanLayers) {
            if (!check_layers || !map.has_layer(row.layer)) continue;
            const std::size_t bytes = level.slice(row.layer).size();
            if (bytes != expected)
                throw Error(path, "level " + std::to_string(i) + ": " + std::string(row.label) +
                                      " holds " + std::to_string(bytes) + " bytes, expected " +
                                      std::to_string(expected));
        }
    }
    if (!(std::isfinite(map.scale) && map.scale > 0.0f)) {
        throw Error(path, "LEAN scale " + format_float(map.scale) + " is not finite and > 0");
    }
    if (map.encoding == LeanEncoding::Signed && map.storage != Storage::Float16 &&
        map.storage != Storage::Float32)
        throw Error(path, std::string("the signed encoding needs a float storage, not ") +
                              to_string(map.storage));
    if (!(std::isfinite(map.plateau_epsilon) && map.plateau_epsilon >= 0.0f)) {
        throw Error(path, "plateau epsilon " + format_float(map.plateau_epsilon) +
                              " is not finite and >= 0");
    }
    if (!(std::isfinite(map.baked_shininess) && map.baked_shininess >= 0.0f)) {
        throw Error(path, "baked shininess " + format_float(map.baked_shininess) +
                              " is not finite and >= 0");
    }
}

const char* normal_convention_name(NormalConvention convention) {
    return convention == NormalConvention::DirectX ? "directx" : "opengl";
}

}  // namespace ktx2_detail

using namespace ktx2_detail;

const char* lean_layout_name(LeanEncoding encoding, bool plateau) {
    if (encoding == LeanEncoding::Signed)
        return plateau ? kLeanSignedPlateauLayoutName : kLeanSignedLayoutName;
    return plateau ? kLeanPlateauLayoutName : kLeanLayoutName;
}

bool is_lean_layout_name(std::string_view layout) {
    for (const LeanEncoding encoding : {LeanEncoding::Offset, LeanEncoding::Signed})
        for (const bool plateau : {false, true})
            if (layout == lean_layout_name(encoding, plateau)) return true;
    return false;
}

std::uint32_t vk_format_of(Storage storage) {
    return format_of(storage).vk_format;
}

const char* vk_format_name(std::uint32_t vk_format) {
    const FormatInfo* format = find_format(vk_format);
    if (format != nullptr) return format->name;
    // Formats other writers' files commonly hold (`leanfade info` names them; only the four
    // above are LEAN maps).
    struct Named {
        std::uint32_t number;
        const char* name;
    };
    static constexpr Named kOthers[] = {
        {0, "VK_FORMAT_UNDEFINED (supercompressed: see the DFD)"},
        {9, "VK_FORMAT_R8_UNORM"},
        {16, "VK_FORMAT_R8G8_UNORM"},
        {23, "VK_FORMAT_R8G8B8_UNORM"},
        {29, "VK_FORMAT_R8G8B8_SRGB"},
        {43, "VK_FORMAT_R8G8B8A8_SRGB"},
        {70, "VK_FORMAT_R16_UNORM"},
        {76, "VK_FORMAT_R16_SFLOAT"},
        {77, "VK_FORMAT_R16G16_UNORM"},
        {83, "VK_FORMAT_R16G16_SFLOAT"},
        {100, "VK_FORMAT_R32_SFLOAT"},
        {103, "VK_FORMAT_R32G32_SFLOAT"},
        {106, "VK_FORMAT_R32G32B32_SFLOAT"},
        {122, "VK_FORMAT_B10G11R11_UFLOAT_PACK32"},
        {123, "VK_FORMAT_E5B9G9R9_UFLOAT_PACK32"},
        {131, "VK_FORMAT_BC1_RGB_UNORM_BLOCK"},
        {133, "VK_FORMAT_BC1_RGBA_UNORM_BLOCK"},
        {137, "VK_FORMAT_BC3_UNORM_BLOCK"},
        {139, "VK_FORMAT_BC4_UNORM_BLOCK"},
        {141, "VK_FORMAT_BC5_UNORM_BLOCK"},
        {143, "VK_FORMAT_BC6H_UFLOAT_BLOCK"},
        {145, "VK_FORMAT_BC7_UNORM_BLOCK"},
        {146, "VK_FORMAT_BC7_SRGB_BLOCK"},
        {147, "VK_FORMAT_ETC2_R8G8B8_UNORM_BLOCK"},
        {151, "VK_FORMAT_ETC2_R8G8B8A8_UNORM_BLOCK"},
        {157, "VK_FORMAT_ASTC_4x4_UNORM_BLOCK"},
        {158, "VK_FORMAT_ASTC_4x4_SRGB_BLOCK"},
    };
    for (const Named& other : kOthers)
        if (other.number == vk_format) return other.name;
    return "unknown";
}

const char* supercompression_name(std::uint32_t scheme) {
    switch (scheme) {
        case 0: return "none";
        case 1: return "BasisLZ";
        case 2: return "Zstandard";
        case 3: return "ZLIB";
    }
    return "unknown";
}

const std::string* Ktx2Info::find(const std::string& key) const {
    for (const auto& [entry_key, value] : key_values) {
        if (entry_key == key) return &value;
    }
    return nullptr;
}

}  // namespace leanfade::io
