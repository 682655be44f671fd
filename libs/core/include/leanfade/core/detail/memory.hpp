#pragma once
// Large buffers. Touching a new buffer for the first time faults every 4 KiB page in; for the
// hundreds of megabytes of a 4096² bake that is a large share of the time. Buffers of a few MiB
// and more are therefore advised to use transparent huge pages (2 MiB, Linux) before their first
// touch: 512 times fewer page faults (docs/perf.md). Elsewhere, and in the portable build
// (leanfade/core/detail/platform.hpp), these are ordinary allocations.
#include <cstddef>
#include <vector>

namespace leanfade {

// Smallest buffer worth advising, in bytes.
inline constexpr std::size_t kHugePageAdviceBytes = std::size_t(4) << 20;

// Advises [data, data + bytes) to use transparent huge pages (whole 4 KiB pages inside the range
// only). Best effort: does nothing below kHugePageAdviceBytes, off Linux, in the portable build,
// or when refused.
void advise_huge_pages(void* data, std::size_t bytes);

// v.assign(count, fill), with a new allocation advised for huge pages before it is filled when
// it is large and the current capacity is too small. Trivially copyable T.
template <class T>
void assign_large(std::vector<T>& v, std::size_t count, const T& fill) {
    if (count * sizeof(T) >= kHugePageAdviceBytes && v.capacity() < count) {
        std::vector<T>().swap(v);
        v.reserve(count);
        advise_huge_pages(v.data(), count * sizeof(T));
    }
    v.assign(count, fill);
}

}  // namespace leanfade
