#pragma once
// What both platform layers share (platform_linux.cpp, platform_portable.cpp): POSIX.1 only.
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <memory>
#include <new>

namespace leanfade::platform {

// Copies the first `size` bytes of `from` (from offset 0) to `to` with pread and write, in 1 MiB
// pieces. Returns 0, or the errno value of the failure (EIO when `from` ends early).
inline int copy_with_read_and_write(int from, int to, std::uint64_t size) noexcept {
    constexpr std::size_t kPiece = std::size_t(1) << 20;
    const std::unique_ptr<char[]> buffer(new (std::nothrow) char[kPiece]);
    if (!buffer) return ENOMEM;
    std::uint64_t done = 0;
    while (done < size) {
        const std::uint64_t want = size - done < kPiece ? size - done : kPiece;
        const ssize_t got = ::pread(from, buffer.get(), std::size_t(want), off_t(done));
        if (got < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        if (got == 0) return EIO;
        for (ssize_t at = 0; at < got;) {
            const ssize_t written = ::write(to, buffer.get() + at, std::size_t(got - at));
            if (written < 0) {
                if (errno == EINTR) continue;
                return errno;
            }
            at += written;
        }
        done += std::uint64_t(got);
    }
    return 0;
}

}  // namespace leanfade::platform
