#pragma once
// What the KTX2 reader, writer and description share (not installed): the file's constants, the
// LEAN map formats, the data format descriptor, key/value text and the checks before a write
// (ktx2.cpp). ktx2_write.cpp writes LEAN maps, ktx2_read.cpp inspects and reads them,
// ktx2_describe.cpp describes a file for people.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "input_file.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::io::ktx2_detail {

using detail::append_u32_le;
using detail::append_u64_le;
using detail::load_u32_le;
using detail::load_u64_le;

constexpr std::array<std::uint8_t, 12> kIdentifier = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                                      '0',  0xBB, '\r', '\n', 0x1A, '\n'};

constexpr std::size_t kHeaderSize = 80;  // identifier + 9 uint32 + 4 uint32 + 2 uint64
constexpr std::size_t kLevelIndexEntrySize = 24;

constexpr std::uint32_t kSchemeNone = 0;
constexpr std::uint32_t kSchemeZstandard = 2;

constexpr std::uint32_t kMaxLevelCount = 32;  // a uint32 size has at most 32 levels
// The array layers of a LEAN map's file: the layers of kLeanLayers a map always has (lean1,
// lean2), or all of them (with the plateau layer).
constexpr std::uint32_t kLayerCount = [] {
    std::uint32_t count = 0;
    for (const LeanLayerInfo& row : kLeanLayers) count += row.optional ? 0 : 1;
    return count;
}();
constexpr std::uint32_t kPlateauLayerCount = std::uint32_t(kLeanLayerCount);

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

constexpr const char* kKeySwizzle = "KTXswizzle";

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

const FormatInfo* find_format(std::uint32_t vk_format);

const FormatInfo& format_of(Storage storage);

std::uint64_t align_up(std::uint64_t value, std::uint64_t alignment);

// Alignment of level data: lcm(texel block size, 4); 1 for supercompressed data (KTX2 §3.9.7).
std::uint64_t level_alignment(const FormatInfo& format, bool supercompressed = false);

std::uint32_t full_chain_length(std::uint32_t width, std::uint32_t height);

std::uint32_t level_size(std::uint32_t size, std::uint32_t level);

// Bytes of one layer of one level.
std::uint64_t layer_bytes(const FormatInfo& format, std::uint32_t width, std::uint32_t height);

// True when [offset, offset + length) lies inside a file of `size` bytes (no overflow).
bool inside(std::uint64_t offset, std::uint64_t length, std::uint64_t size);

// The basic descriptor of `format`; a supercompressed file's has bytesPlane0 = 0 (its level data
// is "unsized", as the KTX2 specification and Khronos's validator ask).
Ktx2DataFormat expected_data_format(const FormatInfo& format, bool supercompressed = false);

std::vector<std::uint8_t> encode_data_format(const Ktx2DataFormat& data_format);

Ktx2DataFormat decode_data_format(const std::string& path, const std::vector<std::uint8_t>& bytes);

std::vector<std::pair<std::string, std::string>> decode_key_values(
    const std::string& path, const std::vector<std::uint8_t>& bytes);

std::string format_float(float value);

// A count of texels written by to_string: decimal digits only.
std::uint64_t parse_count(const std::string& path, const std::string& key, const std::string& text);

float parse_float(const std::string& path, const std::string& key, const std::string& text);

void append_key_value(std::vector<std::uint8_t>& out, const std::string& key,
                      const std::string& value);

// The LEANFADE keys of a map's metadata (scale, roughness baking, normal convention, repairs,
// the convention warning), unsorted; the layout key is the caller's.
std::vector<std::pair<std::string, std::string>> lean_metadata_keys(const PackedLeanMap& map);

// check_layers: the layers' byte counts too (not for a layout whose layers are written later).
void validate_for_write(const std::string& path, const PackedLeanMap& map, const FormatInfo& format,
                        bool check_layers);

const char* normal_convention_name(NormalConvention convention);

// A level of a plain 2D texture: its size in texels and its byte count (texels or blocks).
struct TextureLevelSize {
    int width = 0;
    int height = 0;
    std::size_t bytes = 0;
};

// The bytes a level of width x height texels holds in a format (texels or blocks).
using LevelByteCount = std::function<std::size_t(int width, int height)>;

// Throws leanfade::Error(name, cause) unless `levels` is a full MIP chain (level 0 of 1 to 65536
// texels a side, each level half the one above, floor, down to 1 x 1) whose levels hold
// level_bytes(width, height) bytes each; `unit` follows the byte count in the message ("" or
// " of BC5_UNORM blocks").
void check_mip_chain(const std::vector<TextureLevelSize>& levels, const LevelByteCount& level_bytes,
                     const std::string& unit, const std::string& name);

// A level read from a file: its size and bytes.
struct TextureLevelData {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> bytes;
};

// The levels of a plain 2D KTX2 texture (no depth, layers, faces or supercompression) of
// vkFormat `vk_format` (`format_name` in messages), each of level_bytes(width, height) bytes
// (`unit` as check_mip_chain's), after inspect_ktx2's structural checks. Throws
// leanfade::Error(path, cause).
std::vector<TextureLevelData> read_plain_2d_levels(const std::string& path,
                                                   std::uint32_t vk_format,
                                                   const std::string& format_name,
                                                   const LevelByteCount& level_bytes,
                                                   const std::string& unit);

// `bytes` written atomically to `path` (AtomicFile, options.durability).
void write_file_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes,
                           const WriteOptions& options);

// The key/value data of a plain texture (ktx2_texture.hpp): KTXorientation "rd", KTXwriter, the
// KTX keys `ktx_keys` (KTXswizzle, ...) and the caller's keys `extra` (none starting with "KTX",
// none empty or with a NUL byte, each once), sorted by key bytes (KTX2 §3.11). Throws
// leanfade::Error(name, cause).
std::vector<std::uint8_t> texture_key_value_data(
    const std::string& writer, const std::vector<std::pair<std::string, std::string>>& extra,
    const std::string& name, const std::vector<std::pair<std::string, std::string>>& ktx_keys = {});

}  // namespace leanfade::io::ktx2_detail
