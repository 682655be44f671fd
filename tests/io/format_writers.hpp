#pragma once
// Test files of the formats read through OpenImageIO, made in code: JPEG, TGA, TIFF, BMP, HDR,
// WebP and OpenEXR (B44, DWAA, ...) written by OpenImageIO's own writers; DDS (BC1-BC5 blocks
// crafted here) and PSD (raw image data), which it does not write, encoded here byte by byte.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"

namespace leanfade::io::test {

// Writes `image` (values in [0,1] for integer formats) with OpenImageIO's writer of the format of
// the file extension `extension` ("jpg", "tga", ...), to `path`, as `type` samples. `attributes`:
// e.g. {"compression", "dwaa"}; "quality" is an integer. `channel_names` replaces R, G, B, A.
inline void write_with_openimageio(
    const std::string& path, const std::string& extension, const Image& image, OIIO::TypeDesc type,
    const std::vector<std::pair<std::string, std::string>>& attributes = {},
    const std::vector<std::string>& channel_names = {}) {
    // Written as a file named like the format, then renamed (the reader must go by content).
    const std::string staged = path + ".staged." + extension;
    auto output = OIIO::ImageOutput::create(staged);
    if (!output) throw Error(path, "no OpenImageIO writer for " + extension);
    OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
    if (!channel_names.empty()) spec.channelnames = channel_names;
    if (image.channels == 4 || image.channels == 2) spec.alpha_channel = image.channels - 1;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // colour written as given, not divided by alpha
    for (const auto& [name, value] : attributes) {
        if (name == "quality") {
            spec.attribute(name, std::stoi(value));
        } else {
            spec.attribute(name, value);
        }
    }
    if (!output->open(staged, spec)) throw Error(path, output->geterror());
    if (!output->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()))
        throw Error(path, output->geterror());
    output->close();
    if (std::rename(staged.c_str(), path.c_str()) != 0) throw Error(path, "rename failed");
}

// ---- DDS ----

inline void put_u32(std::vector<std::uint8_t>& bytes, std::size_t offset, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) bytes.at(offset + std::size_t(i)) = std::uint8_t(value >> (8 * i));
}

constexpr std::uint32_t kDdsFourCcFlag = 0x4;
constexpr std::uint32_t kDdsNormalFlag = 0x80000000u;

// A DDS header (128 bytes, plus the 20-byte DX10 header when dxgi_format != 0) for one 2D
// texture of one MIP level, followed by `blocks`.
inline std::vector<std::uint8_t> dds_file(int width, int height, const char* four_cc,
                                          std::uint32_t pixel_flags,
                                          const std::vector<std::uint8_t>& blocks,
                                          std::uint32_t dxgi_format = 0) {
    const std::size_t header_bytes = 128 + (dxgi_format != 0 ? 20 : 0);
    std::vector<std::uint8_t> bytes(header_bytes + blocks.size(), 0);
    std::memcpy(bytes.data(), "DDS ", 4);
    put_u32(bytes, 4, 124);
    put_u32(bytes, 8, 0x1007 | 0x80000);  // caps, height, width, pixel format, linear size
    put_u32(bytes, 12, std::uint32_t(height));
    put_u32(bytes, 16, std::uint32_t(width));
    put_u32(bytes, 20, std::uint32_t(blocks.size()));
    put_u32(bytes, 76, 32);
    put_u32(bytes, 80, pixel_flags);
    std::memcpy(&bytes[84], four_cc, 4);
    put_u32(bytes, 108, 0x1000);  // DDSCAPS_TEXTURE
    if (dxgi_format != 0) {
        put_u32(bytes, 128, dxgi_format);
        put_u32(bytes, 132, 3);  // 2D texture
        put_u32(bytes, 140, 1);  // array size
    }
    std::copy(blocks.begin(), blocks.end(), bytes.begin() + std::ptrdiff_t(header_bytes));
    return bytes;
}

// A BC4 block (also BC3's alpha block and each half of BC5) of 16 texels, each endpoint 0 or 1:
// texel i (row-major in the 4x4 block) is `values[select[i]]`. Endpoints are exact in every
// decoder (value0 > value1 chooses the 8-value mode; equal endpoints make the 6-value mode,
// where indices 0 and 1 still give the endpoints).
inline void append_bc4_block(std::vector<std::uint8_t>& out, std::uint8_t value0,
                             std::uint8_t value1, const std::vector<int>& select) {
    out.push_back(value0);
    out.push_back(value1);
    std::uint64_t indices = 0;
    for (std::size_t i = 0; i < 16; ++i) indices |= std::uint64_t(select.at(i) & 1) << (3 * i);
    for (int i = 0; i < 6; ++i) out.push_back(std::uint8_t(indices >> (8 * i)));
}

// A BC1 colour block with endpoints colour0 > colour1 (RGB565), each texel one of the two.
inline void append_bc1_block(std::vector<std::uint8_t>& out, std::uint16_t colour0,
                             std::uint16_t colour1, const std::vector<int>& select) {
    out.push_back(std::uint8_t(colour0 & 0xFF));
    out.push_back(std::uint8_t(colour0 >> 8));
    out.push_back(std::uint8_t(colour1 & 0xFF));
    out.push_back(std::uint8_t(colour1 >> 8));
    std::uint32_t indices = 0;
    for (std::size_t i = 0; i < 16; ++i) indices |= std::uint32_t(select.at(i) & 1) << (2 * i);
    for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(indices >> (8 * i)));
}

// ---- PSD ----

// A PSD of `image` (1 channel: grayscale; 3 or 4: RGB, the 4th an alpha channel) with raw
// (uncompressed) 8- or 16-bit planar image data, big-endian.
inline std::vector<std::uint8_t> psd_file(const Image& image, int bits) {
    std::vector<std::uint8_t> bytes;
    const auto be16 = [&](std::uint32_t v) {
        bytes.push_back(std::uint8_t(v >> 8));
        bytes.push_back(std::uint8_t(v));
    };
    const auto be32 = [&](std::uint32_t v) {
        be16(v >> 16);
        be16(v & 0xFFFF);
    };
    bytes.insert(bytes.end(), {'8', 'B', 'P', 'S'});
    be16(1);                              // version
    bytes.insert(bytes.end(), 6, 0);      // reserved
    be16(std::uint32_t(image.channels));  // channels
    be32(std::uint32_t(image.height));
    be32(std::uint32_t(image.width));
    be16(std::uint32_t(bits));
    be16(image.channels >= 3 ? 3 : 1);  // RGB or grayscale
    be32(0);                            // colour mode data
    be32(0);                            // image resources
    be32(0);                            // layer and mask information
    be16(0);                            // raw image data
    const float top = bits == 16 ? 65535.0f : 255.0f;
    for (int c = 0; c < image.channels; ++c)
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const auto v = std::uint32_t(image.at(x, y, c) * top + 0.5f);
                if (bits == 16) {
                    be16(v);
                } else {
                    bytes.push_back(std::uint8_t(v));
                }
            }
    return bytes;
}

}  // namespace leanfade::io::test
