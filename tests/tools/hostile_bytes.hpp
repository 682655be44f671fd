#pragma once
// Byte-level helpers of the hostile-file tests of the command line (test_cli_hostile.cpp,
// test_cli_hostile_files.cpp): files as bytes, big- and little-endian fields, PNG chunks with
// their CRC, zlib streams, and a valid LEAN map to break.
#include <tinyexr.h>
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::test {

using Bytes = std::vector<std::uint8_t>;

// A hostile file of a few KiB must not make leanfade hold more than this (the PNG bomb of
// HostileFiles/png_bomb made it hold 2 GiB before the guard); generous for sanitizer builds.
inline constexpr long kMaxRssKib = 512 * 1024;

inline void write_bytes(const std::filesystem::path& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) throw Error(path.string(), "test cannot write the file");
}

inline Bytes read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

inline std::string q(const std::filesystem::path& path) {
    return shell_quote(path.string());
}

inline std::uint32_t load_be32(const Bytes& bytes, std::size_t offset) {
    return (std::uint32_t(bytes.at(offset)) << 24) | (std::uint32_t(bytes.at(offset + 1)) << 16) |
           (std::uint32_t(bytes.at(offset + 2)) << 8) | std::uint32_t(bytes.at(offset + 3));
}
inline void store_be32(Bytes& bytes, std::size_t offset, std::uint32_t value) {
    for (int i = 0; i < 4; ++i)
        bytes.at(offset + std::size_t(i)) = std::uint8_t(value >> (24 - 8 * i));
}
inline std::uint32_t load_le32(const Bytes& bytes, std::size_t offset) {
    std::uint32_t value = 0;
    for (int i = 3; i >= 0; --i) value = (value << 8) | bytes.at(offset + std::size_t(i));
    return value;
}
inline void store_le32(Bytes& bytes, std::size_t offset, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) bytes.at(offset + std::size_t(i)) = std::uint8_t(value >> (8 * i));
}
inline std::uint64_t load_le64(const Bytes& bytes, std::size_t offset) {
    std::uint64_t value = 0;
    for (int i = 7; i >= 0; --i) value = (value << 8) | bytes.at(offset + std::size_t(i));
    return value;
}
inline void store_le64(Bytes& bytes, std::size_t offset, std::uint64_t value) {
    for (int i = 0; i < 8; ++i) bytes.at(offset + std::size_t(i)) = std::uint8_t(value >> (8 * i));
}

// Appends a PNG chunk: length, type, data and the CRC of type and data.
inline void append_chunk(Bytes& png, const char* type, const Bytes& data) {
    const std::size_t start = png.size();
    png.resize(start + 4);
    store_be32(png, start, std::uint32_t(data.size()));
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data.begin(), data.end());
    const auto crc = std::uint32_t(::crc32(0, png.data() + start + 4, uInt(data.size() + 4)));
    png.resize(png.size() + 4);
    store_be32(png, png.size() - 4, crc);
}

inline Bytes zlib_compress(const Bytes& data) {
    uLongf size = compressBound(uLong(data.size()));
    Bytes out(size);
    if (compress(out.data(), &size, data.data(), uLong(data.size())) != Z_OK)
        throw Error("zlib", "test cannot compress");
    out.resize(size);
    return out;
}

// An OpenEXR file of `image` with `header`, as tinyexr writes it.
inline Bytes exr_bytes(const EXRImage& image, const EXRHeader& header) {
    unsigned char* memory = nullptr;
    const char* message = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&image, &header, &memory, &message);
    if (size == 0) {
        FreeEXRErrorMessage(message);
        throw Error("exr", "tinyexr cannot write the test image");
    }
    const std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
    return Bytes(memory, memory + size);
}

// The bytes of a valid 16 x 16 LEAN map (5 levels) in `storage`, baked in-process.
inline Bytes lean_map_bytes(const std::filesystem::path& dir, Storage storage) {
    BakeOptions options;
    options.threads = 1;
    const BakeResult baked =
        bake_lean_map(make_builtin_height("bumps", 16, 5), BakeSource::Height, options);
    const std::filesystem::path path = dir / "valid.tmp.ktx2";
    io::write_ktx2(path.string(), pack_lean_map(baked.map, storage, "test"));
    Bytes bytes = read_bytes(path);
    std::filesystem::remove(path);
    return bytes;
}

}  // namespace leanfade::test
