#pragma once
// Internal: codecs behind image_io.hpp. Decoders take the file (PNG) or its bytes and throw
// leanfade::Error(path, cause); encoders return the complete file's bytes (written atomically by
// the caller). Rows are top first, values as stored (see image_io.hpp).
#include <cstdint>
#include <string>
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

Image decode_exr(const std::string& path, const std::vector<std::uint8_t>& bytes,
                 const ReadOptions& options);
std::vector<std::uint8_t> encode_exr(const std::string& path, const Image& image);

Image decode_pfm(const std::string& path, const std::vector<std::uint8_t>& bytes,
                 const ReadOptions& options);
std::vector<std::uint8_t> encode_pfm(const std::string& path, const Image& image);

}  // namespace leanfade::io::detail
