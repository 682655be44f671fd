// Plain 2D RGBA8 textures with MIPs as KTX 2.0 (leanfade/io/ktx2_texture.hpp).
#include "leanfade/io/ktx2_texture.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <iterator>

#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/io/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::io {
namespace {

using detail::append_u32_le;
using detail::append_u64_le;

constexpr std::array<std::uint8_t, 12> kIdentifier = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                                      '0',  0xBB, '\r', '\n', 0x1A, '\n'};
constexpr std::size_t kHeaderSize = 80;
constexpr std::size_t kLevelIndexEntrySize = 24;

// The Basic Data Format Descriptor of R8G8B8A8_UNORM, linear (KDFWG 1.3, as ktx2.cpp writes for
// its 8-bit LEAN maps): 24-byte block header, 4 samples of 16 bytes.
std::vector<std::uint8_t> rgba8_data_format() {
    std::vector<std::uint8_t> bytes;
    const std::uint32_t block_size = 24 + 4 * 16;
    append_u32_le(bytes, 4 + block_size);            // dfdTotalSize
    append_u32_le(bytes, 0);                         // vendorId 0, descriptorType 0
    append_u32_le(bytes, 2u | (block_size << 16));   // versionNumber 2 (1.3), descriptorBlockSize
    append_u32_le(bytes, 1u | (1u << 8) | (1u << 16));  // RGBSDA, BT709 primaries, LINEAR
    append_u32_le(bytes, 0);                         // texel block 1x1x1x1 (stored minus 1)
    append_u32_le(bytes, 4);                         // bytesPlane0 = 4
    append_u32_le(bytes, 0);
    for (std::uint32_t channel = 0; channel < 4; ++channel) {
        const std::uint32_t id = channel < 3 ? channel : 15;  // R, G, B, A
        append_u32_le(bytes, (channel * 8) | (7u << 16) | (id << 24));
        append_u32_le(bytes, 0);    // sample position
        append_u32_le(bytes, 0);    // sampleLower
        append_u32_le(bytes, 255);  // sampleUpper
    }
    return bytes;
}

void append_key_value(std::vector<std::uint8_t>& out, const std::string& key,
                      const std::string& value) {
    const auto length = std::uint32_t(key.size() + 1 + value.size() + 1);
    append_u32_le(out, length);
    out.insert(out.end(), key.begin(), key.end());
    out.push_back(0);
    out.insert(out.end(), value.begin(), value.end());
    out.push_back(0);
    while (out.size() % 4 != 0) out.push_back(0);
}

void check_chain(const std::vector<Rgba8Level>& levels, const std::string& name) {
    if (levels.empty()) throw Error(name, "a texture needs at least one level");
    const Rgba8Level& top = levels.front();
    if (top.width < 1 || top.height < 1 || top.width > 65536 || top.height > 65536)
        throw Error(name, "level 0 must be 1 to 65536 texels on a side, got " +
                              std::to_string(top.width) + "x" + std::to_string(top.height));
    int w = top.width, h = top.height;
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const Rgba8Level& level = levels[l];
        if (level.width != w || level.height != h)
            throw Error(name, "level " + std::to_string(l) + " must be " + std::to_string(w) +
                                  "x" + std::to_string(h));
        if (level.texels.size() != std::size_t(w) * std::size_t(h) * 4)
            throw Error(name, "level " + std::to_string(l) + " must hold " +
                                  std::to_string(std::size_t(w) * std::size_t(h) * 4) + " bytes");
        if (w == 1 && h == 1 && l + 1 != levels.size())
            throw Error(name, "levels after the 1x1 level");
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    if (levels.back().width != 1 || levels.back().height != 1)
        throw Error(name, "the MIP chain must go down to 1x1");
}

}  // namespace

std::vector<std::uint8_t> encode_ktx2_rgba8(const std::vector<Rgba8Level>& levels,
                                            const std::string& writer, const std::string& name) {
    check_chain(levels, name);
    const auto level_count = std::uint32_t(levels.size());
    std::vector<std::uint8_t> key_values;
    append_key_value(key_values, "KTXorientation", "rd");  // sorted by key bytes
    append_key_value(key_values, "KTXwriter", writer);
    const std::vector<std::uint8_t> dfd = rgba8_data_format();
    const std::uint64_t dfd_offset = kHeaderSize + kLevelIndexEntrySize * level_count;
    const std::uint64_t kvd_offset = dfd_offset + dfd.size();

    // Level data from the smallest level to the largest, each 4-byte aligned (lcm(4, 4)).
    std::vector<std::uint64_t> offsets(level_count);
    std::uint64_t end = kvd_offset + key_values.size();
    for (std::uint32_t l = level_count; l-- > 0;) {
        end = (end + 3) / 4 * 4;
        offsets[l] = end;
        end += levels[l].texels.size();
    }

    std::vector<std::uint8_t> bytes(kIdentifier.begin(), kIdentifier.end());
    append_u32_le(bytes, kVkFormatR8G8B8A8Unorm);
    append_u32_le(bytes, 1);  // typeSize
    append_u32_le(bytes, std::uint32_t(levels.front().width));
    append_u32_le(bytes, std::uint32_t(levels.front().height));
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
        append_u64_le(bytes, offsets[l]);
        append_u64_le(bytes, levels[l].texels.size());
        append_u64_le(bytes, levels[l].texels.size());
    }
    bytes.insert(bytes.end(), dfd.begin(), dfd.end());
    bytes.insert(bytes.end(), key_values.begin(), key_values.end());
    bytes.resize(std::size_t(end), 0);
    for (std::uint32_t l = 0; l < level_count; ++l)
        std::copy(levels[l].texels.begin(), levels[l].texels.end(),
                  bytes.begin() + std::ptrdiff_t(offsets[l]));
    return bytes;
}

void write_ktx2_rgba8(const std::string& path, const std::vector<Rgba8Level>& levels,
                      const std::string& writer, const WriteOptions& options) {
    const std::vector<std::uint8_t> bytes = encode_ktx2_rgba8(levels, writer, path);
    AtomicFile file(path, options.durability);
    file.write(bytes);
    file.commit();
}

std::vector<Rgba8Level> read_ktx2_rgba8(const std::string& path) {
    const Ktx2Info info = inspect_ktx2(path);
    if (info.vk_format != kVkFormatR8G8B8A8Unorm)
        throw Error(path, std::string("expected VK_FORMAT_R8G8B8A8_UNORM, got ") +
                              vk_format_name(info.vk_format));
    if (info.pixel_depth != 0 || info.layer_count > 1 || info.face_count != 1 ||
        info.supercompression_scheme != 0)
        throw Error(path, "expected a plain 2D texture (no depth, layers, faces or "
                          "supercompression)");
    std::ifstream in(path, std::ios::binary);
    std::vector<Rgba8Level> levels;
    for (const Ktx2Level& entry : info.levels) {
        Rgba8Level level;
        level.width = int(entry.width);
        level.height = int(entry.height);
        const std::uint64_t size = std::uint64_t(entry.width) * entry.height * 4;
        if (entry.byte_length != size)
            throw Error(path, "a level of " + std::to_string(entry.width) + "x" +
                                  std::to_string(entry.height) + " texels must hold " +
                                  std::to_string(size) + " bytes");
        level.texels.resize(std::size_t(size));
        in.seekg(std::streamoff(entry.byte_offset));
        in.read(reinterpret_cast<char*>(level.texels.data()), std::streamsize(size));
        if (!in) throw Error(path, "cannot read a level's texels");
        levels.push_back(std::move(level));
    }
    return levels;
}

}  // namespace leanfade::io
