// The platform layer on Linux (leanfade/core/detail/platform.hpp): transparent huge pages, output files
// mapped into memory, folder trees removed with getdents64, file copies in the kernel.
#include "leanfade/core/detail/platform.hpp"

#include <fcntl.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "platform_common.hpp"

namespace leanfade::platform {
namespace {

// getdents64 records (the kernel's layout).
struct DirectoryEntry64 {
    std::uint64_t inode;
    std::int64_t offset;
    unsigned short length;
    unsigned char type;
    char name[1];
};

bool is_dot_or_dot_dot(const char* name) {
    return name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'));
}

// Removes `name` in `folder_fd` and, when it is a folder, what it holds (at most `depth` levels
// down). Async-signal-safe: no allocation, only system calls.
void remove_tree_at(int folder_fd, const char* name, int depth) {
    if (::unlinkat(folder_fd, name, 0) == 0) return;
    if (depth <= 0) return;
    const int fd = ::openat(folder_fd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return;
    alignas(8) char buffer[4096];
    // Entries removed while listing may hide others: list again until a pass removes nothing.
    for (int pass = 0; pass < 64; ++pass) {
        bool removed_any = false;
        ::lseek(fd, 0, SEEK_SET);
        for (;;) {
            const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
            if (n <= 0) break;
            for (long at = 0; at < n;) {
                const auto* entry = reinterpret_cast<const DirectoryEntry64*>(buffer + at);
                at += entry->length;
                if (is_dot_or_dot_dot(entry->name)) continue;
                remove_tree_at(fd, entry->name, depth - 1);
                removed_any = true;
            }
        }
        if (!removed_any) break;
    }
    ::close(fd);
    ::unlinkat(folder_fd, name, AT_REMOVEDIR);
}

}  // namespace

void advise_huge_pages(void* data, std::size_t bytes) noexcept {
    ::madvise(data, bytes, MADV_HUGEPAGE);
}

OutputMapping map_output_file(int descriptor, std::size_t size) noexcept {
    OutputMapping mapping;
    // Reserve the blocks first: a full disk must be an error here, not a SIGBUS while the caller
    // fills the mapping.
    const int reserve_error = ::posix_fallocate(descriptor, 0, off_t(size));
    if (reserve_error != 0) {
        mapping.reserve_failed = true;
        mapping.error_number = reserve_error;
        return mapping;
    }
    void* bytes = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED, descriptor, 0);
    if (bytes == MAP_FAILED) {
        mapping.error_number = errno;
        return mapping;
    }
    mapping.bytes = static_cast<std::uint8_t*>(bytes);
    return mapping;
}

int finish_output_mapping(int, const OutputMapping& mapping, std::size_t size, bool) noexcept {
    // The mapped pages are the file's page cache: kept or not, unmapping is all there is to do
    // (an fsync after it covers them; an uncommitted file is removed).
    if (mapping.bytes != nullptr) ::munmap(mapping.bytes, size);
    return 0;
}

bool removes_folder_trees_on_signals() noexcept {
    return true;
}

int copy_file_contents(int from, int to, std::uint64_t size) noexcept {
    struct stat source {};
    if (::fstat(from, &source) != 0) return errno;
    if (std::uint64_t(source.st_size) < size) return EIO;
    // The whole file with shared blocks (copy-on-write) where the file system has them.
    if (std::uint64_t(source.st_size) == size && ::ioctl(to, FICLONE, from) == 0) return 0;
    // The destination's blocks reserved first, as for a mapped output: a full disk fails here,
    // and the file system allocates one extent at once instead of at writeback (ext4's delayed
    // allocation would otherwise allocate when a rename replaces the previous output).
    if (size > 0) {
        const int reserve_error = ::posix_fallocate(to, 0, off_t(size));
        if (reserve_error != 0 && reserve_error != EOPNOTSUPP && reserve_error != EINVAL)
            return reserve_error;
    }
    loff_t in = 0, out = 0;
    std::uint64_t left = size;
    while (left > 0) {
        const ssize_t copied = ::copy_file_range(from, &in, to, &out, std::size_t(std::min<std::uint64_t>(left, 1u << 30)), 0);
        if (copied < 0) {
            if (errno == EINTR) continue;
            // Not between these files (another file system on old kernels, a special file):
            // what is left goes through read and write.
            if (left == size && (errno == EXDEV || errno == EINVAL || errno == ENOSYS ||
                                 errno == EOPNOTSUPP))
                return copy_with_read_and_write(from, to, size);
            return errno;
        }
        if (copied == 0) return EIO;  // the source ended early
        left -= std::uint64_t(copied);
    }
    return 0;
}

void remove_tree_signal_safe(const char* path, int depth) noexcept {
    remove_tree_at(AT_FDCWD, path, depth);
}

}  // namespace leanfade::platform
