#include "leanfade/io/image_io.hpp"

#include <algorithm>
#include <cstring>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/io/atomic_file.hpp"

namespace leanfade::io {
namespace {

constexpr std::uint8_t kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
constexpr std::uint8_t kExrMagic[4] = {0x76, 0x2F, 0x31, 0x01};
constexpr std::uint8_t kKtx2Magic[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                         '0',  0xBB, '\r', '\n', 0x1A, '\n'};

// True when the file starts with the magic, or is a (truncated) prefix of it.
template <std::size_t N>
bool starts_like(const std::vector<std::uint8_t>& bytes, const std::uint8_t (&magic)[N]) {
    const std::size_t count = std::min(bytes.size(), N);
    return std::memcmp(bytes.data(), magic, count) == 0;
}

bool is_pfm(const std::vector<std::uint8_t>& bytes) {
    if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != 'F' && bytes[1] != 'f')) return false;
    return bytes.size() == 2 || bytes[2] == ' ' || bytes[2] == '\t' || bytes[2] == '\n' ||
           bytes[2] == '\r';
}

void write_all(const std::string& path, const std::vector<std::uint8_t>& bytes,
               Durability durability = Durability::Rename) {
    AtomicFile file(path, durability);
    file.write(bytes);
    file.commit();
}

}  // namespace

Image read_image(const std::string& path, const ReadOptions& options) {
    return read_image_from_memory(detail::InputFile(path).read_all(), path, options);
}

Image read_image_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& path,
                             const ReadOptions& options) {
    if (bytes.empty()) throw Error(path, "empty file");
    if (starts_like(bytes, kPngMagic)) {
        if (bytes.size() < sizeof kPngMagic) throw Error(path, "truncated PNG data");
        return detail::decode_png(path, bytes, options);
    }
    if (starts_like(bytes, kExrMagic)) {
        if (bytes.size() < sizeof kExrMagic) throw Error(path, "truncated OpenEXR data");
        return detail::decode_exr(path, bytes, options);
    }
    if (is_pfm(bytes)) return detail::decode_pfm(path, bytes, options);
    if (bytes.size() >= sizeof kKtx2Magic && starts_like(bytes, kKtx2Magic)) {
        throw Error(path, "is a KTX2 texture, not an image (expected PNG, OpenEXR or PFM)");
    }
    throw Error(path, "unknown image format (expected PNG, OpenEXR or PFM)");
}

void write_png(const std::string& path, const Image& image, int bits, const WriteOptions& options) {
    write_all(path, detail::encode_png(path, image, bits), options.durability);
}

void write_pfm(const std::string& path, const Image& image) {
    write_all(path, detail::encode_pfm(path, image));
}

void write_exr(const std::string& path, const Image& image) {
    write_all(path, detail::encode_exr(path, image));
}

Image flip(const Image& image) {
    Image flipped = image;
    const std::size_t row_floats = std::size_t(image.width) * std::size_t(image.channels);
    for (int y = 0; y < image.height; ++y) {
        std::copy_n(image.row(y), row_floats, flipped.row(image.height - 1 - y));
    }
    return flipped;
}

void flip_rows(std::vector<std::uint8_t>& bytes, std::size_t row_bytes) {
    if (row_bytes == 0) return;
    const std::size_t rows = bytes.size() / row_bytes;
    for (std::size_t top = 0, bottom = rows - (rows > 0 ? 1 : 0); top < bottom; ++top, --bottom) {
        std::swap_ranges(bytes.begin() + std::ptrdiff_t(top * row_bytes),
                         bytes.begin() + std::ptrdiff_t((top + 1) * row_bytes),
                         bytes.begin() + std::ptrdiff_t(bottom * row_bytes));
    }
}

}  // namespace leanfade::io
