// Replaces the global operator new of the io test executable to record the largest single
// request, so that the decompression-bomb tests can check that no huge buffer was requested.
#include <atomic>
#include <cstdlib>
#include <new>

#include "io_test_helpers.hpp"

namespace {
std::atomic<std::size_t> largest_request{0};
std::atomic<std::size_t> request_limit{0};  // 0: none

void* allocate(std::size_t size) {
    const std::size_t limit = request_limit.load(std::memory_order_relaxed);
    if (limit != 0 && size > limit) throw std::bad_alloc();
    std::size_t previous = largest_request.load(std::memory_order_relaxed);
    while (size > previous &&
           !largest_request.compare_exchange_weak(previous, size, std::memory_order_relaxed)) {
    }
    if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
    throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) {
    return allocate(size);
}
void* operator new[](std::size_t size) {
    return allocate(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return allocate(size);
    } catch (const std::bad_alloc&) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
    return operator new(size, tag);
}
void operator delete(void* memory) noexcept {
    std::free(memory);
}
void operator delete[](void* memory) noexcept {
    std::free(memory);
}
void operator delete(void* memory, std::size_t) noexcept {
    std::free(memory);
}
void operator delete[](void* memory, std::size_t) noexcept {
    std::free(memory);
}
void operator delete(void* memory, const std::nothrow_t&) noexcept {
    std::free(memory);
}
void operator delete[](void* memory, const std::nothrow_t&) noexcept {
    std::free(memory);
}

namespace leanfade::io::test {
void reset_largest_allocation() {
    largest_request.store(0);
}
std::size_t largest_allocation() {
    return largest_request.load();
}
void set_allocation_limit(std::size_t bytes) {
    request_limit.store(bytes);
}
}  // namespace leanfade::io::test
