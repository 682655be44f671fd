#pragma once
// Internal: read-only random access to an input file (or to a file's bytes already in memory),
// and small helpers shared by the readers. Every failure throws leanfade::Error(path, cause).
// Inputs are opened read-only and never modified.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "leanfade/core/image.hpp"

namespace leanfade::io::detail {

class InputFile {
  public:
    // Throws "cannot open (<reason>)", "is a directory", "is not a regular file" (FIFO, device,
    // socket: never waits on one) or "empty file".
    explicit InputFile(std::string path);
    // The bytes of a file already in memory, named `path` in errors; they must outlive this
    // object. Throws "empty file" for no bytes, like the file constructor.
    InputFile(std::string path, const std::uint8_t* bytes, std::size_t size);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;

    const std::string& path() const noexcept { return path_; }
    std::uint64_t size() const noexcept { return size_; }

    // Reads exactly `size` bytes at `offset`; throws `truncated_cause` when the file is shorter.
    void read_at(std::uint64_t offset, void* destination, std::size_t size,
                 const std::string& truncated_cause) const;
    std::vector<std::uint8_t> read_all() const;
    // The open descriptor of a file (-1 for bytes in memory), for readers that read the header
    // through it (oiio_image.cpp); and the bytes in memory (nullptr for a file).
    int descriptor() const noexcept { return descriptor_; }
    const std::uint8_t* memory() const noexcept { return memory_; }

  private:
    std::string path_;
    int descriptor_ = -1;
    const std::uint8_t* memory_ = nullptr;  // in-memory input, or nullptr for a file
    std::uint64_t size_ = 0;
};

// Sequential reads of an InputFile through a small buffer, for decoders that stream (PNG): the
// file is never held in memory as a whole.
class SequentialReader {
  public:
    explicit SequentialReader(const InputFile& file, std::size_t buffer_bytes = 256 * 1024);
    // Copies up to `size` bytes from the current position and advances; returns how many (fewer
    // only at the end of the file). Throws what InputFile::read_at throws on a read error.
    std::size_t read(void* destination, std::size_t size);
    // Moves the position by `count` bytes (it may pass the end: reads then return 0).
    void skip(std::uint64_t count);
    std::uint64_t position() const noexcept { return position_; }
    std::uint64_t remaining() const noexcept {
        return position_ < file_.size() ? file_.size() - position_ : 0;
    }

  private:
    const InputFile& file_;
    std::vector<std::uint8_t> buffer_;
    std::uint64_t buffer_start_ = 0;   // file offset of buffer_[0]
    std::size_t buffer_length_ = 0;    // valid bytes in buffer_
    std::uint64_t position_ = 0;
};

// Throws Error(path, ...) unless 1 <= width, height <= max_dimension. Call it on header values
// before allocating any pixel memory (decompression-bomb guard).
void check_dimensions(const std::string& path, std::int64_t width, std::int64_t height,
                      int max_dimension);

// The memory bound of decoding (docs/robustness.md). The size check above bounds the texels, not
// the bytes a small file can make a decoder allocate: a 1-bit palette PNG of 87 bytes declares
// 11585² texels, which decode to 1.6 GB of RGBA floats. A decoded image (the float image a reader
// returns, or a decoder's own buffers when larger) of more than kDecodedBytesWithoutEvidence must
// come from enough file data: at most kMaxDecodedBytesPerFileByte decoded bytes per byte of
// (compressed) pixel data. 4128 = 1032 (deflate's largest expansion) x 4 (an 8-bit sample
// decoded to a 4-byte float): an image of real content at any size passes, data that would
// expand further (a near-empty palette image decoded to RGBA floats) is a decompression bomb.
inline constexpr std::uint64_t kDecodedBytesWithoutEvidence = std::uint64_t(32) << 20;
inline constexpr std::uint64_t kMaxDecodedBytesPerFileByte = 4128;

// Throws Error(path, "<what> would decode to N bytes from M bytes of pixel data (at most 4128 per
// byte above 32 MiB): truncated or a decompression bomb") when the rule above refuses it.
void check_decoded_size(const std::string& path, const std::string& what,
                        std::uint64_t decoded_bytes, std::uint64_t pixel_data_bytes);

// Throws Error(path, "NaN at texel (x, y)") or "infinity at texel (x, y)" on the first
// non-finite value (rows top first).
void check_finite(const std::string& path, const Image& image);

// Throws Error(path, ...) unless 1 <= image.channels <= 4 and the pixel count matches the size.
void check_writable(const std::string& path, const Image& image);

inline std::uint16_t load_u16_le(const std::uint8_t* bytes) {
    return std::uint16_t(bytes[0] | (bytes[1] << 8));
}
inline std::uint32_t load_u32_le(const std::uint8_t* bytes) {
    return std::uint32_t(bytes[0]) | (std::uint32_t(bytes[1]) << 8) |
           (std::uint32_t(bytes[2]) << 16) | (std::uint32_t(bytes[3]) << 24);
}
inline std::uint64_t load_u64_le(const std::uint8_t* bytes) {
    return std::uint64_t(load_u32_le(bytes)) | (std::uint64_t(load_u32_le(bytes + 4)) << 32);
}
inline void append_u32_le(std::vector<std::uint8_t>& out, std::uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(std::uint8_t(value >> shift));
}
inline void append_u64_le(std::vector<std::uint8_t>& out, std::uint64_t value) {
    for (int shift = 0; shift < 64; shift += 8) out.push_back(std::uint8_t(value >> shift));
}
inline float float_from_bits(std::uint32_t bits) {
    float value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}
inline std::uint32_t bits_from_float(float value) {
    std::uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return bits;
}

}  // namespace leanfade::io::detail
