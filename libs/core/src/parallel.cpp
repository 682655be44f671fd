#include "leanfade/core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <thread>
#include <vector>

namespace leanfade {

int resolve_thread_count(int requested) {
    if (requested > 0) return requested;
    const unsigned hw = std::thread::hardware_concurrency();
    return hw == 0 ? 1 : int(hw);
}

void parallel_for_rows(int row_count, int threads, const std::function<void(int, int)>& body) {
    if (row_count <= 0) return;
    const int workers = std::clamp(resolve_thread_count(threads), 1, row_count);
    // Small jobs are not worth a thread start (~20 us).
    if (workers == 1 || row_count < 8) {
        body(0, row_count);
        return;
    }
    std::vector<std::thread> pool;
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(workers));
    pool.reserve(std::size_t(workers - 1));
    auto run = [&](int w) {
        const int first = int(std::int64_t(row_count) * w / workers);
        const int end = int(std::int64_t(row_count) * (w + 1) / workers);
        try {
            body(first, end);
        } catch (...) {
            errors[std::size_t(w)] = std::current_exception();
        }
    };
    for (int w = 1; w < workers; ++w) pool.emplace_back(run, w);
    run(0);
    for (auto& t : pool) t.join();
    for (auto& e : errors)
        if (e) std::rethrow_exception(e);
}

void parallel_for_dynamic(int row_count, int threads, int grain,
                          const std::function<void(int, int, int)>& body) {
    if (row_count <= 0) return;
    grain = std::max(1, grain);
    const int chunks = (row_count - 1) / grain + 1;
    const int workers = std::clamp(resolve_thread_count(threads), 1, chunks);
    if (workers == 1) {
        body(0, 0, row_count);
        return;
    }
    std::atomic<int> next{0};
    std::atomic<bool> failed{false};
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(workers));
    auto run = [&](int w) {
        try {
            while (!failed.load(std::memory_order_relaxed)) {
                const int chunk = next.fetch_add(1, std::memory_order_relaxed);
                if (chunk >= chunks) break;
                const int first = chunk * grain;
                body(w, first, std::min(row_count, first + grain));
            }
        } catch (...) {
            errors[std::size_t(w)] = std::current_exception();
            failed = true;
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(std::size_t(workers - 1));
    for (int w = 1; w < workers; ++w) pool.emplace_back(run, w);
    run(0);
    for (auto& t : pool) t.join();
    for (auto& e : errors)
        if (e) std::rethrow_exception(e);
}

}  // namespace leanfade
