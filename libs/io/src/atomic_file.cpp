#include "leanfade/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "leanfade/core/error.hpp"

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

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    if (path_.empty()) throw Error(path_, "empty output path");
    temporary_path_ = path_ + ".tmp-" + std::to_string(::getpid()) + "-" +
                      std::to_string(temporary_counter.fetch_add(1));
    descriptor_ = ::open(temporary_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (descriptor_ < 0) {
        throw Error(path_, "cannot create temporary file " + temporary_path_ + " (" +
                               errno_text(errno) + ")");
    }
}

AtomicFile::~AtomicFile() {
    if (descriptor_ >= 0) ::close(descriptor_);
    if (!committed_) ::unlink(temporary_path_.c_str());
}

void AtomicFile::write(const void* data, std::size_t size) {
    if (descriptor_ < 0) throw Error(path_, "write after commit");
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

void AtomicFile::commit() {
    if (descriptor_ < 0) throw Error(path_, "commit called twice");
    if (::fsync(descriptor_) != 0) throw Error(path_, "fsync failed (" + errno_text(errno) + ")");
    const int descriptor = descriptor_;
    descriptor_ = -1;
    if (::close(descriptor) != 0) throw Error(path_, "close failed (" + errno_text(errno) + ")");
    if (std::rename(temporary_path_.c_str(), path_.c_str()) != 0) {
        throw Error(path_, "cannot replace the file (" + errno_text(errno) + ")");
    }
    committed_ = true;
    sync_folder(folder_of(path_));
}

void ensure_not_same_file(const std::string& output, const std::string& input) {
    std::error_code error;
    if (!std::filesystem::exists(output, error) || !std::filesystem::exists(input, error)) return;
    if (std::filesystem::equivalent(output, input, error) && !error) {
        throw Error(output, "is the same file as the input " + input);
    }
}

}  // namespace leanfade::io
