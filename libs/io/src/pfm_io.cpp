// Portable Float Map: "PF" (RGB) or "Pf" (gray), then width, height and a scale whose sign gives
// the byte order (negative = little-endian), each separated by white space, one white-space byte,
// then 32-bit floats with the rows bottom first.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string_view>

#include "formats.hpp"
#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"

namespace leanfade::io::detail {
namespace {

bool is_space(std::uint8_t byte) {
    return byte == ' ' || byte == '\t' || byte == '\n' || byte == '\r';
}

class HeaderParser {
  public:
    HeaderParser(const std::string& path, const std::vector<std::uint8_t>& bytes)
        : path_(path), bytes_(bytes) {}

    // Skips white space, returns the next token (at most 64 bytes).
    std::string_view token(const char* what) {
        while (position_ < bytes_.size() && is_space(bytes_[position_])) ++position_;
        const std::size_t start = position_;
        while (position_ < bytes_.size() && !is_space(bytes_[position_])) {
            if (position_ - start >= 64) throw Error(path_, std::string("bad PFM ") + what);
            ++position_;
        }
        if (position_ == start || position_ == bytes_.size()) {
            throw Error(path_, std::string("truncated PFM header (missing ") + what + ")");
        }
        return {reinterpret_cast<const char*>(bytes_.data() + start), position_ - start};
    }

    std::int64_t integer(const char* what) {
        const std::string_view text = token(what);
        std::int64_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size()) {
            throw Error(path_, std::string("bad PFM ") + what + " '" + escape_text(text) + "'");
        }
        return value;
    }

    double real(const char* what) {
        const std::string_view text = token(what);
        double value = 0.0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size()) {
            throw Error(path_, std::string("bad PFM ") + what + " '" + escape_text(text) + "'");
        }
        return value;
    }

    // The single white-space byte that ends the header; returns the offset of the pixel data.
    std::size_t end_of_header() {
        if (position_ >= bytes_.size()) throw Error(path_, "truncated PFM header");
        return position_ + 1;  // token() stopped on a white-space byte
    }

  private:
    const std::string& path_;
    const std::vector<std::uint8_t>& bytes_;
    std::size_t position_ = 2;  // after "PF" / "Pf"
};

}  // namespace

void check_pfm_size(const InputFile& file, const ReadOptions& options) {
    std::vector<std::uint8_t> head(std::size_t(std::min<std::uint64_t>(file.size(), 4096)));
    file.read_at(0, head.data(), head.size(), "file shrank while being read");
    HeaderParser parser(file.path(), head);
    std::int64_t width = 0, height = 0;
    try {
        width = parser.integer("width");
        height = parser.integer("height");
    } catch (const Error&) {
        if (head.size() < file.size()) return;  // a longer header: decode_pfm reads it whole
        throw;
    }
    check_dimensions(file.path(), width, height, options.max_dimension);
}

Image decode_pfm(const std::string& path, const std::vector<std::uint8_t>& bytes,
                 const ReadOptions& options) {
    const int channels = bytes[1] == 'F' ? 3 : 1;
    HeaderParser parser(path, bytes);
    const std::int64_t width = parser.integer("width");
    const std::int64_t height = parser.integer("height");
    const double scale = parser.real("scale");
    const std::size_t data_offset = parser.end_of_header();
    check_dimensions(path, width, height, options.max_dimension);
    if (!(std::isfinite(scale) && scale != 0.0))
        throw Error(path, "bad PFM scale (0 or not finite)");
    const bool little_endian = scale < 0.0;

    const std::uint64_t needed = std::uint64_t(width) * std::uint64_t(height) * channels * 4;
    const std::uint64_t available = bytes.size() - data_offset;
    if (available < needed) {
        throw Error(path, "truncated PFM data (" + std::to_string(available) + " of " +
                              std::to_string(needed) + " bytes)");
    }

    Image image(int(width), int(height), channels);
    const std::size_t row_values = std::size_t(width) * std::size_t(channels);
    for (int file_row = 0; file_row < image.height; ++file_row) {
        const std::uint8_t* source =
            bytes.data() + data_offset + std::size_t(file_row) * row_values * 4;
        float* destination = image.row(image.height - 1 - file_row);
        for (std::size_t i = 0; i < row_values; ++i) {
            const std::uint8_t* b = source + 4 * i;
            const std::uint32_t bits =
                little_endian ? load_u32_le(b)
                              : (std::uint32_t(b[0]) << 24) | (std::uint32_t(b[1]) << 16) |
                                    (std::uint32_t(b[2]) << 8) | std::uint32_t(b[3]);
            destination[i] = float_from_bits(bits);
        }
    }
    check_finite(path, image);
    return image;
}

std::vector<std::uint8_t> encode_pfm(const std::string& path, const Image& image) {
    check_writable(path, image);
    check_finite(path, image);
    const int out_channels = image.channels == 1 ? 1 : 3;
    const std::string header = std::string(out_channels == 1 ? "Pf" : "PF") + "\n" +
                               std::to_string(image.width) + " " + std::to_string(image.height) +
                               "\n-1.0\n";
    std::vector<std::uint8_t> bytes(header.begin(), header.end());
    bytes.reserve(header.size() + image.texel_count() * std::size_t(out_channels) * 4);
    for (int file_row = 0; file_row < image.height; ++file_row) {
        const int y = image.height - 1 - file_row;
        for (int x = 0; x < image.width; ++x) {
            for (int c = 0; c < out_channels; ++c) {
                const float value = c < image.channels ? image.at(x, y, c) : 0.0f;
                append_u32_le(bytes, bits_from_float(value));
            }
        }
    }
    return bytes;
}

}  // namespace leanfade::io::detail
