#include "leanfade/core/detail/memory.hpp"

#include <cstdint>

#include "leanfade/core/detail/platform.hpp"

namespace leanfade {

void advise_huge_pages(void* data, std::size_t bytes) {
    if (data == nullptr || bytes < kHugePageAdviceBytes) return;
    constexpr std::uintptr_t kPage = 4096;
    const auto begin = reinterpret_cast<std::uintptr_t>(data);
    const std::uintptr_t first = (begin + kPage - 1) & ~(kPage - 1);
    const std::uintptr_t last = (begin + bytes) & ~(kPage - 1);
    if (last > first) platform::advise_huge_pages(reinterpret_cast<void*>(first), last - first);
}

}  // namespace leanfade
