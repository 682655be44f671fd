#pragma once
// Internal: codecs behind image_io.hpp. Decoders take the file (PNG) or its bytes and throw
// leanfade::Error(path, cause); encoders return the complete file's bytes (written atomically by
// the caller). Rows are top first, values as stored (see image_io.hpp).
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::io::detail {

// Streams the file through a small buffer (the file is never held in memory as a whole).
class InputFile;
Image decode_png(const InputFile& file, const ReadOptions& options);
// The same values as integer samples (8- or 16-bit, as stored).
UnormImage decode_png_unorm(const InputFile& file, const ReadOptions& options);
std::vector<std::uint8_t> encode_png(const std::string& path, const Image& image, int bits);
// An 8-bit RGBA PNG of `image`'s bytes as they are.
std::vector<std::uint8_t> encode_png_rgba8(const std::string& path, const Rgba8Image& image);

Image decode_exr(const std::string& path, const std::vector<std::uint8_t>& bytes,
                 const ReadOptions& options);
// The size of an OpenEXR file's data window against options.max_dimension, from the header's
// attributes read from the file, before the file is read into memory. A header it cannot walk
// (an attribute name of more than 255 bytes, more than 4096 attributes before the data window)
// is left to decode_exr.
void check_exr_size(const InputFile& file, const ReadOptions& options);
std::vector<std::uint8_t> encode_exr(const std::string& path, const Image& image);

// The channels of a file to return, in order (indices into `names`), from their names (the part
// after the last '.', so that "N.X" is "X"): R (or Y), G, B, A; or X, Y, Z, A when the names
// include X and Z or "X", "Y", "Z" (a normal's components: Y is then y, not luminance). Other
// names follow in file order; past 4 channels only the named ones are kept, and a file with no
// such subset of 1-4 channels is refused.
std::vector<int> order_channels(const std::string& path, const std::vector<std::string>& names,
                                const std::string& format_name);

// OpenEXR files whose compression tinyexr cannot decode (PXR24, B44, B44A, DWAA, DWAB) are
// decoded by OpenImageIO (the OpenEXR library), from the whole file's bytes, after decode_exr
// checked their header (size, chunk table, decoded size). Channels as decode_exr orders them.
Image decode_exr_with_openimageio(const std::string& path, const std::vector<std::uint8_t>& bytes,
                                  const ReadOptions& options);

// The formats read through OpenImageIO (oiio_image.cpp), each by the one reader of its format:
// a file is never offered to OpenImageIO's other readers.
struct OiioFormat {
    const char* plugin;  // OpenImageIO's reader ("jpeg", "targa", "dds", ...)
    const char* name;    // for messages ("JPEG", "TGA", ...)
};
// Every format of recognise_oiio_format, for messages.
const std::vector<std::string>& oiio_format_names();
// The format of a file whose first bytes are `head` (up to 32), recognised by its content; or
// nullptr. Throws "truncated <format> data" for a file too short to hold its signature.
const OiioFormat* recognise_oiio_format(const InputFile& file,
                                        const std::vector<std::uint8_t>& head);
// Decodes a file of that format (through the OpenImageIO module, below), from its bytes read
// into memory. The header is checked first, through the file itself (OpenImageIO's reader
// opened on it; DDS, PSD and WebP fields read here), before the file is read into memory: the
// size against options.max_dimension, the decoded bytes against the file's size. TGA and JPEG
// data that ends early is refused (OpenImageIO 2.4 decodes it without an error). DDS normal
// maps stored as two channels (BC5, DXT5 "nm" with x in alpha, RXGB) come back as RGB with the
// third component reconstructed, z = sqrt(1 - x^2 - y^2). compact: 8- and 16-bit samples as a
// UnormImage; options.drop_alpha: RGBA -> RGB. An allocation failure is an Error naming the file.
std::variant<Image, UnormImage> decode_oiio(const InputFile& file, const OiioFormat& format,
                                            const ReadOptions& options, bool compact);

// The OpenImageIO module: oiio_image.cpp (with channel_order.cpp, input_file.cpp and core's
// image.cpp and memory.cpp) built as a shared object of its own, which oiio_formats.cpp loads on
// first use, so that OpenImageIO's dependencies load only for the files that need them.
// `decode` decodes a whole file's bytes of `format`, as decode_oiio describes, throwing
// leanfade::Error(path, cause).
// `check_header` opens the file (or its bytes in memory) with the format's reader and applies
// the same header checks as `decode`, reading only what the reader reads to open it (its
// header), never the pixel data.
struct OiioModule {
    std::variant<Image, UnormImage> (*decode)(const std::vector<std::uint8_t>& bytes,
                                              const std::string& path, const OiioFormat& format,
                                              const ReadOptions& options, bool compact);
    void (*check_header)(const InputFile& file, const OiioFormat& format,
                         const ReadOptions& options);
};
using OiioModuleEntry = const OiioModule* (*)();
inline constexpr const char* kOiioModuleFileName = "libleanfade_io_oiio.so";
inline constexpr const char* kOiioModuleEntryName = "leanfade_io_oiio_module";

Image decode_pfm(const std::string& path, const std::vector<std::uint8_t>& bytes,
                 const ReadOptions& options);
// A PFM's width and height against options.max_dimension, from its first 4 KiB, before the file
// is read into memory (a header longer than that is left to decode_pfm).
void check_pfm_size(const InputFile& file, const ReadOptions& options);
std::vector<std::uint8_t> encode_pfm(const std::string& path, const Image& image);

}  // namespace leanfade::io::detail
