#include "input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/core/detail/memory.hpp"

namespace leanfade::io::detail {

InputFile::InputFile(std::string path) : path_(std::move(path)) {
    if (path_.empty()) throw Error("", "an input file name is empty");
    // O_NONBLOCK: opening a FIFO without a writer would otherwise wait forever (it is refused
    // below as not a regular file); it changes nothing for regular files.
    descriptor_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (descriptor_ < 0)
        throw Error(path_, std::string("cannot open (") + std::strerror(errno) + ")");
    struct stat status {};
    if (::fstat(descriptor_, &status) != 0) {
        const int error_number = errno;
        ::close(descriptor_);
        throw Error(path_, std::string("cannot stat (") + std::strerror(error_number) + ")");
    }
    if (S_ISDIR(status.st_mode)) {
        ::close(descriptor_);
        throw Error(path_, "is a directory");
    }
    if (!S_ISREG(status.st_mode)) {  // FIFO, socket, device: no size to check against
        ::close(descriptor_);
        throw Error(path_, "is not a regular file");
    }
#if !defined(LEANFADE_IO_OIIO_MODULE)
    if (const std::string output = claimed_output(status.st_dev, status.st_ino); !output.empty()) {
        ::close(descriptor_);
        throw Error(path_, claimed_output_cause(output));
    }
#endif
    size_ = std::uint64_t(status.st_size);
    if (size_ == 0) {
        ::close(descriptor_);
        throw Error(path_, "empty file");
    }
}

InputFile::InputFile(std::string path, const std::uint8_t* bytes, std::size_t size)
    : path_(std::move(path)), memory_(bytes), size_(size) {
    if (size_ == 0) throw Error(path_, "empty file");
}

InputFile::~InputFile() {
    if (descriptor_ >= 0) ::close(descriptor_);
}

void InputFile::read_at(std::uint64_t offset, void* destination, std::size_t size,
                        const std::string& truncated_cause) const {
    if (offset > size_ || size > size_ - offset) throw Error(path_, truncated_cause);
    if (memory_ != nullptr) {
        if (size > 0) std::memcpy(destination, memory_ + offset, size);
        return;
    }
    auto* bytes = static_cast<unsigned char*>(destination);
    while (size > 0) {
        const ssize_t count = ::pread(descriptor_, bytes, size, off_t(offset));
        if (count < 0) {
            if (errno == EINTR) continue;
            throw Error(path_, std::string("read error (") + std::strerror(errno) + ")");
        }
        if (count == 0) throw Error(path_, truncated_cause);  // shrank while reading
        bytes += count;
        offset += std::uint64_t(count);
        size -= std::size_t(count);
    }
}

std::vector<std::uint8_t> InputFile::read_all() const {
    std::vector<std::uint8_t> bytes;
    try {
        assign_large(bytes, static_cast<std::size_t>(size_), std::uint8_t(0));
    } catch (const std::bad_alloc&) {
        // One line naming the file (under `ulimit -v` this was "internal error: std::bad_alloc").
        throw Error(path_, "out of memory reading the file (" + std::to_string(size_) +
                               " bytes; lower the size limit or raise the memory limit)");
    }
    read_at(0, bytes.data(), bytes.size(), "file shrank while being read");
    return bytes;
}

SequentialReader::SequentialReader(const InputFile& file, std::size_t buffer_bytes)
    : file_(file), buffer_(buffer_bytes) {}

std::size_t SequentialReader::read(void* destination, std::size_t size) {
    auto* out = static_cast<std::uint8_t*>(destination);
    std::size_t copied = 0;
    while (copied < size && position_ < file_.size()) {
        if (position_ < buffer_start_ || position_ >= buffer_start_ + buffer_length_) {
            buffer_start_ = position_;
            buffer_length_ = std::size_t(
                std::min<std::uint64_t>(buffer_.size(), file_.size() - position_));
            file_.read_at(buffer_start_, buffer_.data(), buffer_length_,
                          "file shrank while being read");
        }
        const std::size_t offset = std::size_t(position_ - buffer_start_);
        const std::size_t count = std::min(size - copied, buffer_length_ - offset);
        std::memcpy(out + copied, buffer_.data() + offset, count);
        copied += count;
        position_ += count;
    }
    return copied;
}

void SequentialReader::skip(std::uint64_t count) {
    position_ = count > UINT64_MAX - position_ ? UINT64_MAX : position_ + count;
}

void check_dimensions(const std::string& path, std::int64_t width, std::int64_t height,
                      int max_dimension) {
    if (width <= 0 || height <= 0) {
        throw Error(path, std::string("image width or height is ") +
                              (width < 0 || height < 0 ? "negative" : "0") + " (" +
                              std::to_string(width) + "x" + std::to_string(height) + ")");
    }
    if (width > max_dimension || height > max_dimension) {
        throw Error(path, "image size " + std::to_string(width) + "x" + std::to_string(height) +
                              " exceeds the limit of " + std::to_string(max_dimension) +
                              " texels per side");
    }
}

void check_decoded_size(const std::string& path, const std::string& what,
                        std::uint64_t decoded_bytes, std::uint64_t pixel_data_bytes) {
    if (decoded_bytes <= kDecodedBytesWithoutEvidence) return;
    const std::uint64_t budget =
        pixel_data_bytes > UINT64_MAX / kMaxDecodedBytesPerFileByte
            ? UINT64_MAX
            : pixel_data_bytes * kMaxDecodedBytesPerFileByte;
    if (decoded_bytes <= budget) return;
    throw Error(path, what + " would decode to " + std::to_string(decoded_bytes) + " bytes from " +
                          std::to_string(pixel_data_bytes) + " bytes of pixel data (at most " +
                          std::to_string(kMaxDecodedBytesPerFileByte) +
                          " per byte above 32 MiB): truncated or a decompression bomb");
}

void check_finite(const std::string& path, const Image& image) {
    for (int y = 0; y < image.height; ++y) {
        const float* row = image.row(y);
        for (int i = 0; i < image.width * image.channels; ++i) {
            if (std::isfinite(row[i])) continue;
            const std::string where =
                "at texel (" + std::to_string(i / image.channels) + ", " + std::to_string(y) + ")";
            throw Error(path, (std::isnan(row[i]) ? "NaN " : "infinity ") + where);
        }
    }
}

void check_writable(const std::string& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0) throw Error(path, "cannot write an empty image");
    if (image.channels < 1 || image.channels > 4) {
        throw Error(path, "cannot write an image of " + std::to_string(image.channels) +
                              " channels (1 to 4)");
    }
    if (image.pixels.size() != image.texel_count() * std::size_t(image.channels)) {
        throw Error(path, "image pixel count does not match its size");
    }
}

}  // namespace leanfade::io::detail
