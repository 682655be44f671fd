// PNG through libpng. libpng reports errors by calling an error function that must not return; we
// longjmp back to a setjmp in small functions that own no C++ object with a destructor (so no
// destructor is ever skipped), then turn the saved message into a leanfade::Error. No C++
// exception ever crosses a libpng frame.
#include <png.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <type_traits>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/shading.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/png_io.hpp"

namespace leanfade::io::detail {
namespace {

constexpr char kTruncatedMessage[] = "truncated PNG data";

// Everything the libpng callbacks touch: plain data only.
struct PngContext {
    std::jmp_buf jump;
    char message[256];
    bool truncated;
    bool read_failed;           // the file could not be read: `read_error` holds the cause
    char read_error[256];
    // Reading: the file, streamed through a small buffer.
    SequentialReader* input;
    // Writing: a malloc'd growing buffer, freed by the owner.
    unsigned char* output;
    std::size_t output_size;
    std::size_t output_capacity;
};

void on_png_error(png_structp png, png_const_charp message) {
    auto* context = static_cast<PngContext*>(png_get_error_ptr(png));
    std::snprintf(context->message, sizeof context->message, "%s",
                  message != nullptr ? message : "unknown libpng error");
    std::longjmp(context->jump, 1);
}

void on_png_warning(png_structp, png_const_charp) {}  // never print

void read_from_file(png_structp png, png_bytep destination, png_size_t length) {
    auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
    std::size_t count = 0;
    try {
        count = context->input->read(destination, length);
    } catch (const Error& error) {
        std::snprintf(context->read_error, sizeof context->read_error, "%s",
                      error.cause().c_str());
        context->read_failed = true;
    }
    // No C++ object is alive here: png_error longjmps out through libpng.
    if (context->read_failed) png_error(png, "read error");
    if (count < length) {
        context->truncated = true;
        png_error(png, kTruncatedMessage);
    }
}

void write_to_memory(png_structp png, png_bytep source, png_size_t length) {
    auto* context = static_cast<PngContext*>(png_get_io_ptr(png));
    if (length > context->output_capacity - context->output_size) {
        std::size_t capacity = std::max<std::size_t>(context->output_capacity * 2, 4096);
        while (capacity - context->output_size < length) capacity *= 2;
        void* grown = std::realloc(context->output, capacity);
        if (grown == nullptr) png_error(png, "out of memory");
        context->output = static_cast<unsigned char*>(grown);
        context->output_capacity = capacity;
    }
    std::memcpy(context->output + context->output_size, source, length);
    context->output_size += length;
}

void flush_nothing(png_structp) {}

struct PngHeader {
    png_uint_32 width;
    png_uint_32 height;
    int channels;
    int bit_depth;
    std::size_t row_bytes;
    bool interlaced;
};

// Reads the chunks before the pixels and sets up the expansions. False after a libpng error.
bool read_png_header(png_structp png, png_infop info, PngContext& context, bool drop_alpha,
                     PngHeader& header) {
    if (setjmp(context.jump) != 0) return false;
    png_read_info(png, info);
    const int color_type = png_get_color_type(png, info);
    const int bit_depth = png_get_bit_depth(png, info);
    if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (drop_alpha && (color_type & PNG_COLOR_MASK_COLOR) != 0)
        png_set_strip_alpha(png);
    else if (png_get_valid(png, info, PNG_INFO_tRNS) != 0)
        png_set_tRNS_to_alpha(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    header.width = png_get_image_width(png, info);
    header.height = png_get_image_height(png, info);
    header.channels = png_get_channels(png, info);
    header.bit_depth = png_get_bit_depth(png, info);
    header.row_bytes = png_get_rowbytes(png, info);
    header.interlaced = png_get_interlace_type(png, info) != PNG_INTERLACE_NONE;
    return true;
}

// Samples of one decoded row (8-bit, or 16-bit big-endian as PNG stores them) to floats in [0, 1].
void convert_row(const std::uint8_t* source, float* destination, std::size_t values,
                 int bit_depth) {
    if (bit_depth == 8) {
        for (std::size_t i = 0; i < values; ++i) destination[i] = source[i] / 255.0f;
    } else {
        for (std::size_t i = 0; i < values; ++i) {
            const unsigned value = (unsigned(source[2 * i]) << 8) | source[2 * i + 1];
            destination[i] = float(value) / 65535.0f;
        }
    }
}

// Samples of one decoded row to integers (16-bit big-endian as PNG stores them to native).
void convert_row(const std::uint8_t* source, std::uint16_t* destination, std::size_t values,
                 int bit_depth) {
    if (bit_depth == 8) {
        for (std::size_t i = 0; i < values; ++i) destination[i] = source[i];
    } else {
        for (std::size_t i = 0; i < values; ++i)
            destination[i] = std::uint16_t((unsigned(source[2 * i]) << 8) | source[2 * i + 1]);
    }
}

// Where decoded rows go: a float Image or a UnormImage (plain pointers: used under setjmp).
struct RowTarget {
    Image* floats;
    UnormImage* unorm;
    void put(png_uint_32 y, const std::uint8_t* row, std::size_t values, int bit_depth) const {
        if (floats != nullptr)
            convert_row(row, floats->row(int(y)), values, bit_depth);
        else
            convert_row(row, unorm->row(int(y)), values, bit_depth);
    }
};

// A non-interlaced image, one row at a time straight into `target` (no buffer of all samples).
bool read_png_rows_into(png_structp png, png_infop info, PngContext& context,
                        const PngHeader& header, std::uint8_t* row, const RowTarget& target) {
    if (setjmp(context.jump) != 0) return false;
    const std::size_t values_per_row = std::size_t(header.width) * std::size_t(header.channels);
    for (png_uint_32 y = 0; y < header.height; ++y) {
        png_read_row(png, row, nullptr);
        target.put(y, row, values_per_row, header.bit_depth);
    }
    png_read_end(png, info);
    return true;
}

bool read_png_rows(png_structp png, png_infop info, PngContext& context, png_bytepp rows) {
    if (setjmp(context.jump) != 0) return false;
    png_read_image(png, rows);
    png_read_end(png, info);
    return true;
}

struct PngImageLayout {
    png_uint_32 width;
    png_uint_32 height;
    int bit_depth;
    int color_type;
};

bool write_png_rows(png_structp png, png_infop info, PngContext& context,
                    const PngImageLayout& layout, png_bytepp rows, png_textp text,
                    int text_count) {
    if (setjmp(context.jump) != 0) return false;
    png_set_write_fn(png, &context, write_to_memory, flush_nothing);
    png_set_IHDR(png, info, layout.width, layout.height, layout.bit_depth, layout.color_type,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    // tEXt chunks before IDAT, so that a streamed read has them once the header is read.
    if (text_count > 0) png_set_text(png, info, text, text_count);
    // zlib's fastest level: a 4096² 16-bit RGBA slice (the PNG pair of a bake) encodes
    // 2.5x faster than at the default level 6, for files 4 % larger (docs/perf.md).
    png_set_compression_level(png, 1);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, info);
    return true;
}

class PngReadStruct {
  public:
    explicit PngReadStruct(PngContext& context) {
        png_ =
            png_create_read_struct(PNG_LIBPNG_VER_STRING, &context, on_png_error, on_png_warning);
        if (png_ != nullptr) info_ = png_create_info_struct(png_);
#ifdef PNG_IGNORE_ADLER32
        // zlib's Adler-32 of the image data is a second checksum of bytes the CRC-32 of every
        // IDAT chunk already covers (libpng still refuses a chunk whose CRC is wrong); skipping
        // it saves a pass over the decompressed data.
        if (png_ != nullptr) png_set_option(png_, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
#endif
    }
    ~PngReadStruct() {
        png_destroy_read_struct(&png_, info_ != nullptr ? &info_ : nullptr, nullptr);
    }
    PngReadStruct(const PngReadStruct&) = delete;
    PngReadStruct& operator=(const PngReadStruct&) = delete;
    bool valid() const { return png_ != nullptr && info_ != nullptr; }
    png_structp png() const { return png_; }
    png_infop info() const { return info_; }

  private:
    png_structp png_ = nullptr;
    png_infop info_ = nullptr;
};

class PngWriteStruct {
  public:
    explicit PngWriteStruct(PngContext& context) : context_(context) {
        png_ =
            png_create_write_struct(PNG_LIBPNG_VER_STRING, &context, on_png_error, on_png_warning);
        if (png_ != nullptr) info_ = png_create_info_struct(png_);
    }
    ~PngWriteStruct() {
        png_destroy_write_struct(&png_, info_ != nullptr ? &info_ : nullptr);
        std::free(context_.output);
    }
    PngWriteStruct(const PngWriteStruct&) = delete;
    PngWriteStruct& operator=(const PngWriteStruct&) = delete;
    bool valid() const { return png_ != nullptr && info_ != nullptr; }
    png_structp png() const { return png_; }
    png_infop info() const { return info_; }

  private:
    PngContext& context_;
    png_structp png_ = nullptr;
    png_infop info_ = nullptr;
};

// Sum of the IDAT chunks' data lengths (as far as the file holds them), walking the chunks after
// the signature up to IEND or the end of the file.
std::uint64_t compressed_pixel_bytes(const InputFile& file) {
    std::uint64_t total = 0;
    SequentialReader reader(file, 64 * 1024);
    reader.skip(8);
    std::uint8_t chunk[8];
    while (reader.remaining() >= 8) {
        reader.read(chunk, 8);
        const std::uint64_t length = (std::uint64_t(chunk[0]) << 24) |
                                     (std::uint64_t(chunk[1]) << 16) |
                                     (std::uint64_t(chunk[2]) << 8) | std::uint64_t(chunk[3]);
        const std::uint8_t* type = chunk + 4;
        const std::uint64_t available = reader.remaining();
        if (std::memcmp(type, "IDAT", 4) == 0) total += std::min(length, available);
        if (std::memcmp(type, "IEND", 4) == 0 || length + 4 >= available) break;
        reader.skip(length + 4);
    }
    return total;
}

// Deflate expands at most 1032 times (a 258-byte match in 2 bits), so IDAT data of n bytes holds
// at most 1032 n bytes of rows. A file declaring more pixels than that is truncated or a
// decompression bomb: refused before libpng allocates rows for its declared size. Applied only
// when the rows would take more than 16 MiB; smaller files get libpng's own, more specific,
// diagnosis after the (harmless) allocation.
void check_compressed_size(const std::string& path, const InputFile& file,
                           const std::uint8_t* bytes, std::uint64_t width, std::uint64_t height) {
    int samples = 0;
    switch (bytes[25]) {  // IHDR colour type
        case 0:
            samples = 1;
            break;  // gray
        case 2:
            samples = 3;
            break;  // RGB
        case 3:
            samples = 1;
            break;  // palette
        case 4:
            samples = 2;
            break;  // gray + alpha
        case 6:
            samples = 4;
            break;  // RGBA
        default:
            return;  // libpng refuses it
    }
    const std::uint64_t bits_per_pixel = std::uint64_t(samples) * bytes[24];  // IHDR bit depth
    // A lower bound for any filter and interlace method: the pixels alone, without filter bytes.
    const std::uint64_t pixel_bytes = width * height * bits_per_pixel / 8;
    if (pixel_bytes <= (std::uint64_t(1) << 24)) return;
    const std::uint64_t compressed = compressed_pixel_bytes(file);
    constexpr std::uint64_t kMaxDeflateRatio = 1032;
    if (pixel_bytes > kMaxDeflateRatio * compressed + 1024) {
        throw Error(path, "PNG pixel data too short for its " + std::to_string(width) + "x" +
                              std::to_string(height) + " size (" + std::to_string(compressed) +
                              " compressed bytes cannot hold " + std::to_string(pixel_bytes) +
                              "): truncated or a decompression bomb");
    }
}

[[noreturn]] void throw_png_error(const std::string& path, const PngContext& context) {
    if (context.read_failed) throw Error(path, context.read_error);
    if (context.truncated) throw Error(path, kTruncatedMessage);
    throw Error(path, std::string("corrupt PNG data (") + context.message + ")");
}

}  // namespace

namespace {

// Decodes into an Image or a UnormImage (Decoded), the rows streamed from the file.
template <class Decoded>
Decoded decode_png_as(const InputFile& file, const ReadOptions& options,
                      std::vector<PngText>* text = nullptr) {
    const std::string& path = file.path();
    // The first chunk is IHDR (8-byte signature, 4-byte length, "IHDR", width, height, both
    // big-endian, bit depth, colour type): check the declared size before libpng allocates
    // anything for it.
    constexpr std::size_t kIhdrEnd = 24, kColourTypeEnd = 26;
    std::uint8_t bytes[kColourTypeEnd] = {};
    const std::size_t prefix = std::size_t(std::min<std::uint64_t>(file.size(), kColourTypeEnd));
    file.read_at(0, bytes, prefix, kTruncatedMessage);
    if (prefix >= kIhdrEnd && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
        const auto big_endian = [&](std::size_t offset) {
            return (std::int64_t(bytes[offset]) << 24) | (std::int64_t(bytes[offset + 1]) << 16) |
                   (std::int64_t(bytes[offset + 2]) << 8) | std::int64_t(bytes[offset + 3]);
        };
        check_dimensions(path, big_endian(16), big_endian(20), options.max_dimension);
        // Shorter files: libpng reports the truncated header.
        if (prefix >= kColourTypeEnd) {
            check_compressed_size(path, file, bytes, std::uint64_t(big_endian(16)),
                                  std::uint64_t(big_endian(20)));
        }
    }

    SequentialReader input(file);
    PngContext context{};
    context.input = &input;
    PngReadStruct reader(context);
    if (!reader.valid()) throw Error(path, "cannot initialise libpng");
    png_set_read_fn(reader.png(), &context, read_from_file);

    PngHeader header{};
    if (!read_png_header(reader.png(), reader.info(), context, options.drop_alpha, header)) {
        throw_png_error(path, context);
    }
    check_dimensions(path, header.width, header.height, options.max_dimension);
    if (text != nullptr) {  // the tEXt, zTXt and iTXt chunks before the image data
        png_textp chunks = nullptr;
        const int count = png_get_text(reader.png(), reader.info(), &chunks, nullptr);
        for (int i = 0; i < count; ++i) {
            text->push_back({chunks[i].key != nullptr ? chunks[i].key : "",
                             chunks[i].text != nullptr
                                 ? std::string(chunks[i].text, chunks[i].text_length)
                                 : std::string()});
        }
    }
    if (header.channels < 1 || header.channels > 4 ||
        (header.bit_depth != 8 && header.bit_depth != 16)) {
        throw Error(path, "unsupported PNG layout (" + std::to_string(header.channels) +
                              " channels of " + std::to_string(header.bit_depth) + " bits)");
    }
    // The decoded size, after the expansions (palette to RGB or RGBA, 1/2/4-bit gray to 8 bits),
    // counted as the float image read_image returns (read_image_compact applies the same rule,
    // so both reads of a file agree): bounded by the compressed data (check_decoded_size).
    const std::uint64_t decoded_bytes = std::uint64_t(header.width) * header.height *
                                        std::uint64_t(header.channels) * sizeof(float);
    if (decoded_bytes > kDecodedBytesWithoutEvidence) {
        check_decoded_size(path,
                           "PNG of " + std::to_string(header.width) + "x" +
                               std::to_string(header.height) + " (" +
                               std::to_string(header.channels) + " channels once expanded)",
                           decoded_bytes, compressed_pixel_bytes(file));
    }

    Decoded image = [&] {
        if constexpr (std::is_same_v<Decoded, Image>) {
            return Image(int(header.width), int(header.height), header.channels);
        } else {
            return UnormImage(int(header.width), int(header.height), header.channels,
                              header.bit_depth == 8 ? 255 : 65535);
        }
    }();
    RowTarget target{nullptr, nullptr};
    if constexpr (std::is_same_v<Decoded, Image>)
        target.floats = &image;
    else
        target.unorm = &image;
    const std::size_t values_per_row = std::size_t(header.width) * std::size_t(header.channels);
    if (!header.interlaced) {
        std::vector<std::uint8_t> row(header.row_bytes);
        if (!read_png_rows_into(reader.png(), reader.info(), context, header, row.data(),
                                target)) {
            throw_png_error(path, context);
        }
        return image;
    }
    // Adam7: libpng fills every row over seven passes, so all rows are kept until the end.
    std::vector<std::uint8_t> samples(header.row_bytes * header.height);
    std::vector<png_bytep> rows(header.height);
    for (png_uint_32 y = 0; y < header.height; ++y) rows[y] = samples.data() + y * header.row_bytes;
    if (!read_png_rows(reader.png(), reader.info(), context, rows.data())) {
        throw_png_error(path, context);
    }
    for (png_uint_32 y = 0; y < header.height; ++y)
        target.put(y, rows[y], values_per_row, header.bit_depth);
    return image;
}

}  // namespace

Image decode_png(const InputFile& file, const ReadOptions& options) {
    return decode_png_as<Image>(file, options);
}

UnormImage decode_png_unorm(const InputFile& file, const ReadOptions& options) {
    return decode_png_as<UnormImage>(file, options);
}

namespace {

std::vector<std::uint8_t> encode_png_text(const std::string& path, const Image& image, int bits,
                                          const std::vector<PngText>& text) {
    if (bits != 8 && bits != 16) {
        throw Error(path, "unsupported PNG bit depth " + std::to_string(bits) + " (8 or 16)");
    }
    check_writable(path, image);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        if (std::isnan(image.pixels[i])) {
            const std::size_t texel = i / std::size_t(image.channels);
            throw Error(path, "NaN at texel (" + std::to_string(texel % std::size_t(image.width)) +
                                  ", " + std::to_string(texel / std::size_t(image.width)) + ")");
        }
    }

    const std::size_t values_per_row = std::size_t(image.width) * std::size_t(image.channels);
    const std::size_t row_bytes = values_per_row * std::size_t(bits / 8);
    std::vector<std::uint8_t> samples(row_bytes * std::size_t(image.height));
    std::vector<png_bytep> rows(std::size_t(image.height));
    const float max_value = bits == 8 ? 255.0f : 65535.0f;
    for (int y = 0; y < image.height; ++y) {
        std::uint8_t* destination = samples.data() + std::size_t(y) * row_bytes;
        rows[std::size_t(y)] = destination;
        const float* source = image.row(y);
        for (std::size_t i = 0; i < values_per_row; ++i) {
            const auto value = unsigned(std::lround(std::clamp(source[i], 0.0f, 1.0f) * max_value));
            if (bits == 8) {
                destination[i] = std::uint8_t(value);
            } else {
                destination[2 * i] = std::uint8_t(value >> 8);
                destination[2 * i + 1] = std::uint8_t(value & 0xFF);
            }
        }
    }

    static constexpr int kColorTypes[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                           PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGBA};
    const PngImageLayout layout{png_uint_32(image.width), png_uint_32(image.height), bits,
                                kColorTypes[image.channels - 1]};
    std::vector<png_text> chunks(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i].key.empty() || text[i].key.size() > 79)
            throw Error(path, "PNG text keyword '" + text[i].key + "' not 1-79 characters");
        chunks[i] = png_text{};
        chunks[i].compression = PNG_TEXT_COMPRESSION_NONE;
        chunks[i].key = const_cast<char*>(text[i].key.c_str());
        chunks[i].text = const_cast<char*>(text[i].value.c_str());
        chunks[i].text_length = text[i].value.size();
    }
    PngContext context{};
    PngWriteStruct writer(context);
    if (!writer.valid()) throw Error(path, "cannot initialise libpng");
    if (!write_png_rows(writer.png(), writer.info(), context, layout, rows.data(), chunks.data(),
                        int(chunks.size()))) {
        throw Error(path, std::string("cannot encode PNG (") + context.message + ")");
    }
    return std::vector<std::uint8_t>(context.output, context.output + context.output_size);
}

}  // namespace

std::vector<std::uint8_t> encode_png(const std::string& path, const Image& image, int bits) {
    return encode_png_text(path, image, bits, {});
}

std::vector<std::uint8_t> encode_png_rgba8(const std::string& path, const Rgba8Image& image) {
    if (image.width < 1 || image.height < 1 ||
        image.texels.size() != std::size_t(image.width) * std::size_t(image.height) * 4)
        throw Error(path, "an RGBA8 image of " + std::to_string(image.width) + "x" +
                              std::to_string(image.height) + " texels must hold " +
                              std::to_string(std::size_t(image.width) * std::size_t(image.height) * 4) +
                              " bytes");
    std::vector<png_bytep> rows(std::size_t(image.height));
    for (int y = 0; y < image.height; ++y)
        rows[std::size_t(y)] = const_cast<png_bytep>(image.texels.data()) +
                               std::size_t(y) * std::size_t(image.width) * 4;
    const PngImageLayout layout{png_uint_32(image.width), png_uint_32(image.height), 8,
                                PNG_COLOR_TYPE_RGBA};
    PngContext context{};
    PngWriteStruct writer(context);
    if (!writer.valid()) throw Error(path, "cannot initialise libpng");
    if (!write_png_rows(writer.png(), writer.info(), context, layout, rows.data(), nullptr, 0))
        throw Error(path, std::string("cannot encode PNG (") + context.message + ")");
    return std::vector<std::uint8_t>(context.output, context.output + context.output_size);
}

}  // namespace leanfade::io::detail

// ---- Public: PNGs with text, LEAN maps as a PNG pair ------------------------------------------

namespace leanfade::io {
namespace {

// The keys of the KTX2 file's metadata (ktx2.hpp, docs/ktx2.md), plus the layer of this file.
constexpr const char* kLayerKey = "LEANFADElayer";
constexpr const char* kSoftwareKey = "Software";  // a PNG's standard keyword

// Shortest decimal that reads back as the same float.
std::string exact_text(float value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

const std::string* find_text(const std::vector<PngText>& text, const char* key) {
    for (const PngText& t : text)
        if (t.key == key) return &t.value;
    return nullptr;
}

const std::string& require_text(const std::string& path, const std::vector<PngText>& text,
                                const char* key) {
    const std::string* value = find_text(text, key);
    if (value == nullptr)
        throw Error(path, std::string("no '") + key +
                              "' text chunk: not a LEAN map PNG from `leanfade bake`");
    return *value;
}

float parse_float_text(const std::string& path, const char* key, const std::string& value) {
    float result = 0.0f;
    const auto parsed = std::from_chars(value.data(), value.data() + value.size(), result);
    if (parsed.ec != std::errc() || parsed.ptr != value.data() + value.size() ||
        !std::isfinite(result))
        throw Error(path,
                    std::string("malformed '") + key + "' text chunk '" + escape_text(value) + "'");
    return result;
}

bool ends_with_lower(const std::string& s, const std::string& suffix) {
    if (s.size() < suffix.size()) return false;
    for (std::size_t i = 0; i < suffix.size(); ++i) {
        const char c = s[s.size() - suffix.size() + i];
        if (char(std::tolower(static_cast<unsigned char>(c))) != suffix[i]) return false;
    }
    return true;
}

}  // namespace

void write_png_with_text(const std::string& path, const Image& image, int bits,
                         const std::vector<PngText>& text, const WriteOptions& options) {
    const std::vector<std::uint8_t> bytes = detail::encode_png_text(path, image, bits, text);
    AtomicFile file(path, options.durability);
    file.write(bytes);
    file.commit();
}

UnormImage read_png_with_text(const std::string& path, std::vector<PngText>& text,
                              const ReadOptions& options) {
    const detail::InputFile file(path);
    std::uint8_t signature[8] = {};
    if (file.size() >= 8) file.read_at(0, signature, 8, "truncated PNG data");
    if (png_sig_cmp(signature, 0, 8) != 0) throw Error(path, "not a PNG file");
    text.clear();
    return detail::decode_png_as<UnormImage>(file, options, &text);
}

std::string lean_png_pair_base(const std::string& path) {
    for (const char* suffix : {kLeanPngSuffixes[0], kLeanPngSuffixes[1], kPlateauPngSuffix})
        if (ends_with_lower(path, suffix))
            return path.substr(0, path.size() - std::strlen(suffix));
    return {};
}

void write_lean_png_pair(const std::string& lean1_path, const std::string& lean2_path,
                         const PackedLeanMap& packed, const WriteOptions& options,
                         const std::string& plateau_path) {
    const std::string paths[3] = {lean1_path, lean2_path, plateau_path};
    if (packed.has_plateau() && plateau_path.empty())
        throw Error(lean1_path, "the LEAN map's plateau layer needs a third file");
    if (packed.storage != Storage::Unorm8 && packed.storage != Storage::Unorm16)
        throw Error(lean1_path, std::string("a PNG holds 8- or 16-bit UNORM values, not storage ") +
                                    to_string(packed.storage) + "; write a KTX2 file");
    if (packed.levels.empty()) throw Error(lean1_path, "the LEAN map has no level");
    const int bits = packed.storage == Storage::Unorm8 ? 8 : 16;
    const PackedLevel& top = packed.levels.front();
    const int layer_count = packed.layer_count();  // the first rows of kLeanLayers
    for (int layer = 0; layer < layer_count; ++layer) {
        Image image(top.width, top.height, 4);
        for (int y = 0; y < top.height; ++y)
            for (int x = 0; x < top.width; ++x) {
                const glm::vec4 t = fetch_packed_texel(packed, 0, layer, x, y);
                for (int c = 0; c < 4; ++c) image.at(x, y, c) = t[c];
            }
        std::vector<PngText> text = {
            {kLayoutKey, packed.has_plateau() ? kLeanPlateauLayoutName : kLeanLayoutName},
            {kLayerKey, std::string(kLeanLayers[std::size_t(layer)].name)},
            {kScaleKey, exact_text(packed.scale)},
            {kRoughnessBakedKey, packed.roughness_baked ? "1" : "0"},
            {kBakedShininessKey,
             exact_text(packed.roughness_baked ? packed.baked_shininess : 0.0f)},
            {kNormalConventionKey, to_string(packed.source_convention)},
            {kSoftwareKey, packed.generator}};
        if (packed.has_plateau())
            text.push_back({kPlateauEpsilonKey, exact_text(packed.plateau_epsilon)});
        write_png_with_text(paths[layer], image, bits, text, options);
    }
}

PackedLeanMap read_lean_png_pair(const std::string& path, const ReadOptions& options) {
    const std::string base = lean_png_pair_base(path);
    if (base.empty())
        throw Error(path, "a LEAN map PNG pair is named NAME.lean1.png and NAME.lean2.png");
    std::string paths[3];
    UnormImage layers[3];
    std::vector<PngText> text[3];
    float scale = 0.0f;
    int layer_count = 2;  // 3 when lean1's layout names the plateau layer
    for (int layer = 0; layer < layer_count; ++layer) {
        paths[layer] = base + (layer < 2 ? kLeanPngSuffixes[layer] : kPlateauPngSuffix);
        const std::string& p = paths[layer];
        layers[layer] = read_png_with_text(p, text[layer], options);
        const std::string& layout = require_text(p, text[layer], kLayoutKey);
        if (layer == 0 && layout == kLeanPlateauLayoutName) layer_count = 3;
        const char* expected = layer_count == 3 ? kLeanPlateauLayoutName : kLeanLayoutName;
        if (layout != expected)
            throw Error(p, "layout '" + escape_text(layout) + "' is not '" + expected + "'");
        const std::string_view layer_name = kLeanLayers[std::size_t(layer)].name;
        if (require_text(p, text[layer], kLayerKey) != layer_name)
            throw Error(p, std::string("holds layer '") +
                               escape_text(*find_text(text[layer], kLayerKey)) + "', expected " +
                               std::string(layer_name));
        if (layers[layer].channels != 4)
            throw Error(p, "a LEAN map PNG is RGBA, this one has " +
                               std::to_string(layers[layer].channels) + " channels");
        const float sc = parse_float_text(p, kScaleKey, require_text(p, text[layer], kScaleKey));
        if (!(sc > 0.0f)) throw Error(p, "sc must be > 0, got " + exact_text(sc));
        if (sc > kMaxLeanScale)
            throw Error(p, "sc " + exact_text(sc) + " exceeds the largest sc a bake writes (" +
                               exact_text(kMaxLeanScale) + ": slopes are at most 1e6)");
        if (layer > 0 && sc != scale)
            throw Error(p, "sc " + exact_text(sc) + " differs from " + paths[0] + "'s " +
                               exact_text(scale));
        scale = sc;
        if (layer > 0 && (layers[0].width != layers[layer].width ||
                          layers[0].height != layers[layer].height ||
                          layers[0].max_value != layers[layer].max_value))
            throw Error(p, "size or bit depth differs from " + paths[0] + "'s");
    }
    float plateau_epsilon = 0.0f;
    if (layer_count == 3) {
        plateau_epsilon = parse_float_text(paths[2], kPlateauEpsilonKey,
                                           require_text(paths[2], text[2], kPlateauEpsilonKey));
        if (!(plateau_epsilon > 0.0f))
            throw Error(paths[2], std::string(kPlateauEpsilonKey) + " must be > 0");
    }

    LeanMap map;
    map.scale = scale;
    const std::vector<PngText>& meta = text[0];
    map.roughness_baked = require_text(paths[0], meta, kRoughnessBakedKey) == "1";
    map.baked_shininess = parse_float_text(paths[0], kBakedShininessKey,
                                           require_text(paths[0], meta, kBakedShininessKey));
    const std::string& convention = require_text(paths[0], meta, kNormalConventionKey);
    if (convention != to_string(NormalConvention::OpenGL) &&
        convention != to_string(NormalConvention::DirectX))
        throw Error(paths[0],
                    "normal convention '" + escape_text(convention) + "' is not opengl or directx");
    map.source_convention = convention == to_string(NormalConvention::OpenGL)
                                ? NormalConvention::OpenGL
                                : NormalConvention::DirectX;
    // The packed values are affine in the moments, so filtering them is filtering the moments
    // (docs/math.md §3): each level is unpacked from the filtered values, then packed again.
    const std::vector<Image> chains[2] = {build_mip_chain(layers[0].to_float()),
                                          build_mip_chain(layers[1].to_float())};
    for (std::size_t l = 0; l < chains[0].size(); ++l) {
        const Image& lean1 = chains[0][l];
        const Image& lean2 = chains[1][l];
        MomentLevel level;
        level.width = lean1.width;
        level.height = lean1.height;
        const std::size_t texels = lean1.texel_count();
        level.normal.resize(texels);
        level.mean.resize(texels);
        level.second.resize(texels);
        for (std::size_t i = 0; i < texels; ++i) {
            const float* a = &lean1.pixels[4 * i];
            const float* b = &lean2.pixels[4 * i];
            const auto m = shading::lf_unpack(glm::vec4(a[0], a[1], a[2], a[3]),
                                              glm::vec4(b[0], b[1], b[2], b[3]), scale,
                                              lean_offset(LeanEncoding::Offset));
            level.normal[i] = m.normal;
            level.mean[i] = m.mean;
            level.second[i] = m.second;
        }
        map.levels.push_back(std::move(level));
    }
    const std::string* software = find_text(meta, kSoftwareKey);
    PackedLeanMap packed =
        pack_lean_map(map, layers[0].max_value == 255 ? Storage::Unorm8 : Storage::Unorm16,
                      software != nullptr ? *software : std::string());
    if (layer_count == 3) {
        // The stored values are affine in (f, f Bs, f |Bs|^2): the layer's chain is the finest
        // level decoded, filtered, and packed again (the finest level to its own codes).
        Image decoded = layers[2].to_float();
        for (std::size_t t = 0; t < decoded.texel_count(); ++t) {
            float* v = &decoded.pixels[4 * t];
            const glm::vec4 d = decode_plateau_texel(glm::vec4(v[0], v[1], v[2], v[3]), scale,
                                                     lean_offset(LeanEncoding::Offset));
            for (int c = 0; c < 4; ++c) v[c] = d[c];
        }
        set_plateau_layer(packed, build_mip_chain(decoded), plateau_epsilon);
    }
    return packed;
}

}  // namespace leanfade::io
