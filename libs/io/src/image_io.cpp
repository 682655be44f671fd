#include "leanfade/io/image_io.hpp"

#include <algorithm>
#include <cstring>
#include <new>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

namespace leanfade::io {
namespace {

constexpr std::uint8_t kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
constexpr std::uint8_t kExrMagic[4] = {0x76, 0x2F, 0x31, 0x01};
constexpr std::uint8_t kKtx2Magic[12] = {0xAB, 'K',  'T',  'X',  ' ',  '2',
                                         '0',  0xBB, '\r', '\n', 0x1A, '\n'};

// True when the file starts with the magic, or is a (truncated) prefix of it.
template <std::size_t N>
bool starts_like(const std::vector<std::uint8_t>& head, const std::uint8_t (&magic)[N]) {
    const std::size_t count = std::min(head.size(), N);
    return std::memcmp(head.data(), magic, count) == 0;
}

bool is_pfm(const std::vector<std::uint8_t>& head) {
    if (head.size() < 2 || head[0] != 'P' || (head[1] != 'F' && head[1] != 'f')) return false;
    return head.size() == 2 || head[2] == ' ' || head[2] == '\t' || head[2] == '\n' ||
           head[2] == '\r';
}

// RGBA -> RGB (ReadOptions::drop_alpha for the float formats).
Image without_alpha(Image image) {
    if (image.channels != 4) return image;
    Image opaque(image.width, image.height, image.channels - 1);
    const std::size_t texels = image.texel_count();
    for (std::size_t i = 0; i < texels; ++i)
        for (int c = 0; c < opaque.channels; ++c)
            opaque.pixels[i * std::size_t(opaque.channels) + std::size_t(c)] =
                image.pixels[i * std::size_t(image.channels) + std::size_t(c)];
    return opaque;
}

// "PNG, OpenEXR, PFM, JPEG, ... or WebP": every format read_image reads.
std::string expected_formats() {
    std::vector<std::string> names{"PNG", "OpenEXR", "PFM"};
    for (const std::string& name : detail::oiio_format_names()) names.push_back(name);
    return name_list(names);
}

// Recognises the format by its first bytes (TGA: its header's values or its footer). PNG is
// streamed from the file; OpenEXR and PFM are decoded from the whole file's bytes (`whole` when
// the caller has them, else read here); the other formats are read by OpenImageIO from the file.
// compact: PNG and other 8/16-bit samples as a UnormImage instead of floats.
std::variant<Image, UnormImage> decode(const detail::InputFile& file,
                                       const std::vector<std::uint8_t>* whole,
                                       const ReadOptions& options, bool compact) {
    const std::string& path = file.path();
    std::vector<std::uint8_t> head(std::size_t(std::min<std::uint64_t>(file.size(), 32)));
    file.read_at(0, head.data(), head.size(), "file shrank while being read");
    if (starts_like(head, kPngMagic)) {
        if (head.size() < sizeof kPngMagic) throw Error(path, "truncated PNG data");
        if (compact) return detail::decode_png_unorm(file, options);
        return detail::decode_png(file, options);
    }
    const auto bytes = [&] { return whole != nullptr ? *whole : file.read_all(); };
    const auto opaque = [&](Image image) {
        return options.drop_alpha ? without_alpha(std::move(image)) : image;
    };
    if (starts_like(head, kExrMagic)) {
        if (head.size() < sizeof kExrMagic) throw Error(path, "truncated OpenEXR data");
        detail::check_exr_size(file, options);  // before the file is read into memory
        return opaque(detail::decode_exr(path, bytes(), options));
    }
    if (is_pfm(head)) {
        detail::check_pfm_size(file, options);
        return opaque(detail::decode_pfm(path, bytes(), options));
    }
    if (head.size() >= sizeof kKtx2Magic && starts_like(head, kKtx2Magic)) {
        throw Error(path, "is a KTX2 texture, not an image (expected " + expected_formats() + ")");
    }
    if (const detail::OiioFormat* format = detail::recognise_oiio_format(file, head)) {
        return detail::decode_oiio(file, *format, options, compact);
    }
    throw Error(path, "unknown image format (expected " + expected_formats() + ")");
}

// decode, with an allocation failure anywhere in it (the file's bytes, a decoder's buffers, the
// image) as one line naming the file: under `ulimit -v` it was "internal error: std::bad_alloc".
std::variant<Image, UnormImage> guarded_decode(const detail::InputFile& file,
                                               const std::vector<std::uint8_t>* whole,
                                               const ReadOptions& options, bool compact) {
    try {
        return decode(file, whole, options, compact);
    } catch (const std::bad_alloc&) {
        throw Error(file.path(), "out of memory reading the image (" + std::to_string(file.size()) +
                                     "-byte file; lower the size limit or raise the memory limit)");
    }
}

void write_all(const std::string& path, const std::vector<std::uint8_t>& bytes,
               Durability durability = Durability::Rename) {
    AtomicFile file(path, durability);
    file.write(bytes);
    file.commit();
}

}  // namespace

Image read_image(const std::string& path, const ReadOptions& options) {
    const detail::InputFile file(path);
    return std::get<Image>(guarded_decode(file, nullptr, options, false));
}

std::variant<Image, UnormImage> read_image_compact(const std::string& path,
                                                   const ReadOptions& options) {
    const detail::InputFile file(path);
    return guarded_decode(file, nullptr, options, true);
}

std::variant<Image, UnormImage> read_image_compact_from_memory(
    const std::vector<std::uint8_t>& bytes, const std::string& path, const ReadOptions& options) {
    if (bytes.empty()) throw Error(path, "empty file");
    const detail::InputFile file(path, bytes.data(), bytes.size());
    return guarded_decode(file, &bytes, options, true);
}

Image read_image_from_memory(const std::vector<std::uint8_t>& bytes, const std::string& path,
                             const ReadOptions& options) {
    if (bytes.empty()) throw Error(path, "empty file");
    const detail::InputFile file(path, bytes.data(), bytes.size());
    return std::get<Image>(guarded_decode(file, &bytes, options, false));
}

const std::vector<std::pair<std::string, Supercompression>>& supercompression_names() {
    static const std::vector<std::pair<std::string, Supercompression>> names = {
        {"zstd", Supercompression::Zstandard}, {"none", Supercompression::None}};
    return names;
}

const char* to_string(Supercompression supercompression) {
    return supercompression == Supercompression::Zstandard ? "zstd" : "none";
}

void write_png(const std::string& path, const Image& image, int bits, const WriteOptions& options) {
    write_all(path, detail::encode_png(path, image, bits), options.durability);
}

std::vector<std::uint8_t> encode_png_rgba8(const Rgba8Image& image, const std::string& name) {
    return detail::encode_png_rgba8(name, image);
}

void write_png_rgba8(const std::string& path, const Rgba8Image& image, const WriteOptions& options) {
    write_all(path, detail::encode_png_rgba8(path, image), options.durability);
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
