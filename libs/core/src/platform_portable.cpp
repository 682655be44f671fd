// The portable platform layer (leanfade/core/detail/platform.hpp): ordinary allocation and writes,
// standard C and C++ only, plus POSIX.1 write, unlink and rmdir.
#include "leanfade/core/detail/platform.hpp"

#include "platform_common.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>

namespace leanfade::platform {

void advise_huge_pages(void*, std::size_t) noexcept {}

OutputMapping map_output_file(int, std::size_t size) noexcept {
    OutputMapping mapping;
    // calloc: zeros, like the new pages of a file, without touching them first where the
    // allocator gets them from the system.
    mapping.bytes = static_cast<std::uint8_t*>(std::calloc(size, 1));
    if (mapping.bytes == nullptr) mapping.error_number = ENOMEM;
    return mapping;
}

int finish_output_mapping(int descriptor, const OutputMapping& mapping, std::size_t size,
                          bool keep) noexcept {
    int result = 0;
    if (keep && mapping.bytes != nullptr) {
        const std::uint8_t* at = mapping.bytes;
        std::size_t left = size;
        while (left > 0) {
            const ssize_t written = ::write(descriptor, at, left);
            if (written < 0) {
                if (errno == EINTR) continue;
                result = errno;
                break;
            }
            at += written;
            left -= std::size_t(written);
        }
    }
    std::free(mapping.bytes);
    return result;
}

bool removes_folder_trees_on_signals() noexcept {
    return false;
}

int copy_file_contents(int from, int to, std::uint64_t size) noexcept {
    return copy_with_read_and_write(from, to, size);
}

void remove_tree_signal_safe(const char* path, int) noexcept {
    if (::unlink(path) != 0) ::rmdir(path);
}

}  // namespace leanfade::platform
