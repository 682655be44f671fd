#include "leanfade/io/detail/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <system_error>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/platform.hpp"

namespace leanfade::io {
namespace {

std::atomic<unsigned long> temporary_counter{0};

std::string errno_text(int error_number) {
    return std::strerror(error_number);
}

std::string folder_of(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

// Makes the rename durable. Best effort: a folder that cannot be opened or synced (some file
// systems refuse) does not make an already renamed file a failed write.
void sync_folder(const std::string& folder) {
    const int descriptor = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (descriptor < 0) return;
    ::fsync(descriptor);
    ::close(descriptor);
}

}  // namespace

std::string temporary_path_for(const std::string& path) {
    return path + ".tmp-" + std::to_string(::getpid()) + "-" +
           std::to_string(temporary_counter.fetch_add(1)) + "-" + temporary_run_id();
}

AtomicFile::AtomicFile(std::string path, Durability durability)
    : path_(std::move(path)), durability_(durability) {
    if (path_.empty()) throw Error(path_, "empty output path");
    temporary_path_ = temporary_path_for(path_);
    // Registered before it exists: a signal between the two finds nothing to remove.
    registration_ = TemporaryRegistration(temporary_path_);
    descriptor_ = ::open(temporary_path_.c_str(),
                         O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC /* mmap needs read */, 0666);
    if (descriptor_ < 0) {
        // Named after the output, never its temporary (a full cache's warning named one).
        throw Error(path_,
                    "cannot create a temporary file in its folder (" + errno_text(errno) + ")");
    }
}

AtomicFile::~AtomicFile() {
    if (mapping_ != nullptr) {
        platform::OutputMapping mapping;
        mapping.bytes = mapping_;
        platform::finish_output_mapping(descriptor_, mapping, mapping_size_, false);
    }
    if (descriptor_ >= 0) ::close(descriptor_);
    if (!committed_) ::unlink(temporary_path_.c_str());
    registration_.release();
}

void AtomicFile::write(const void* data, std::size_t size) {
    if (descriptor_ < 0) throw Error(path_, "write after commit");
    if (mapping_ != nullptr) throw Error(path_, "write to a mapped file");
    written_ = true;
    const auto* bytes = static_cast<const unsigned char*>(data);
    while (size > 0) {
        const ssize_t written = ::write(descriptor_, bytes, size);
        if (written < 0) {
            if (errno == EINTR) continue;
            throw Error(path_, "write failed (" + errno_text(errno) + ")");
        }
        bytes += written;
        size -= std::size_t(written);
    }
}

void AtomicFile::write_at(std::uint64_t offset, const void* data, std::size_t size) {
    if (descriptor_ < 0) throw Error(path_, "write after commit");
    if (mapping_ != nullptr) throw Error(path_, "write to a mapped file");
    const off_t end = ::lseek(descriptor_, 0, SEEK_CUR);
    if (end < 0 || offset > std::uint64_t(end) || size > std::uint64_t(end) - offset)
        throw Error(path_, "write_at outside the bytes written");
    const auto* bytes = static_cast<const unsigned char*>(data);
    while (size > 0) {
        const ssize_t written = ::pwrite(descriptor_, bytes, size, off_t(offset));
        if (written < 0) {
            if (errno == EINTR) continue;
            throw Error(path_, "write failed (" + errno_text(errno) + ")");
        }
        bytes += written;
        offset += std::uint64_t(written);
        size -= std::size_t(written);
    }
}

std::uint8_t* AtomicFile::map(std::size_t size) {
    if (descriptor_ < 0) throw Error(path_, "map after commit");
    if (mapping_ != nullptr || written_) throw Error(path_, "map of a file already written");
    if (size == 0) return nullptr;
    if (size > std::size_t(std::numeric_limits<off_t>::max())) {
        throw Error(path_, "cannot reserve " + std::to_string(size) + " bytes (too large)");
    }
    // Linux reserves the blocks first: a full disk must be an error here, not a SIGBUS while the
    // caller fills the mapping (leanfade/core/detail/platform.hpp).
    const platform::OutputMapping mapping = platform::map_output_file(descriptor_, size);
    if (mapping.reserve_failed) {
        throw Error(path_, "cannot reserve " + std::to_string(size) + " bytes (" +
                               errno_text(mapping.error_number) + ")");
    }
    if (mapping.bytes == nullptr) {
        throw Error(path_, "cannot map the output file (" + errno_text(mapping.error_number) + ")");
    }
    mapping_ = mapping.bytes;
    mapping_size_ = size;
    return mapping_;
}

void AtomicFile::copy_from(const std::string& source, std::uint64_t size) {
    if (descriptor_ < 0) throw Error(path_, "copy after commit");
    if (mapping_ != nullptr || written_) throw Error(path_, "copy into a file already written");
    const int from = ::open(source.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (from < 0) throw Error(source, "cannot open (" + errno_text(errno) + ")");
    struct stat status {};
    const bool stated = ::fstat(from, &status) == 0;
    const int stat_error = errno;
    if (!stated || !S_ISREG(status.st_mode) || std::uint64_t(status.st_size) != size) {
        ::close(from);
        if (!stated) throw Error(source, "cannot read its size (" + errno_text(stat_error) + ")");
        if (!S_ISREG(status.st_mode)) throw Error(source, "is not a regular file");
        throw Error(source, "holds " + std::to_string(status.st_size) + " bytes, not " +
                                std::to_string(size));
    }
    written_ = true;
    const int error_number = platform::copy_file_contents(from, descriptor_, size);
    ::close(from);
    if (error_number != 0)
        throw Error(path_, "cannot copy " + source + " (" + errno_text(error_number) + ")");
}

void AtomicFile::commit() {
    if (descriptor_ < 0) throw Error(path_, "commit called twice");
    // Linux: the mapped pages are the file's page cache, the fsync covers them; portable: the
    // buffer is written here.
    if (mapping_ != nullptr) {
        platform::OutputMapping mapping;
        mapping.bytes = mapping_;
        mapping_ = nullptr;
        const int error_number =
            platform::finish_output_mapping(descriptor_, mapping, mapping_size_, true);
        if (error_number != 0)
            throw Error(path_, "write failed (" + errno_text(error_number) + ")");
    }
    if (durability_ == Durability::Flush && ::fsync(descriptor_) != 0) {
        throw Error(path_, "fsync failed (" + errno_text(errno) + ")");
    }
    const int descriptor = descriptor_;
    descriptor_ = -1;
    if (::close(descriptor) != 0) throw Error(path_, "close failed (" + errno_text(errno) + ")");
    if (std::rename(temporary_path_.c_str(), path_.c_str()) != 0) {
        throw Error(path_, "cannot replace the file (" + errno_text(errno) + ")");
    }
    committed_ = true;
    registration_.release();
    if (durability_ == Durability::Flush) sync_folder(folder_of(path_));
}

void ensure_not_same_file(const std::string& output, const std::string& input) {
    std::error_code error;
    if (!std::filesystem::exists(output, error) || !std::filesystem::exists(input, error)) return;
    if (std::filesystem::equivalent(output, input, error) && !error) {
        throw Error(output, "is the same file as the input " + input);
    }
}

}  // namespace leanfade::io
