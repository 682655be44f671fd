#include "leanfade/core/detail/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "leanfade/core/error.hpp"

namespace leanfade {
namespace {

std::atomic<int> thread_start_limit{-1};  // set_thread_start_limit_for_testing

// Starts run(w) on a thread for w = 1, 2, ... count - 1, as many as the system allows: when a
// thread cannot be started (a process or memory limit), the ones started are kept and the
// number started is returned; the caller does the rest of the work itself. Never throws.
template <class Run>
int start_workers(std::vector<std::thread>& pool, int count, const Run& run) {
    try {
        pool.reserve(std::size_t(count - 1));
    } catch (...) {
        return 1;
    }
    const int limit = thread_start_limit.load();
    for (int w = 1; w < count; ++w) {
        if (limit >= 0 && w > limit) return w;  // as if the system refused this thread
        try {
            pool.emplace_back(run, w);
        } catch (...) {  // std::system_error (EAGAIN) or std::bad_alloc
            return w;
        }
    }
    return count;
}

void join_all(std::vector<std::thread>& pool) {
    for (auto& t : pool) t.join();
}

void rethrow_first(const std::vector<std::exception_ptr>& errors) {
    for (const auto& e : errors)
        if (e) std::rethrow_exception(e);
}

}  // namespace

int set_thread_start_limit_for_testing(int limit) {
    return thread_start_limit.exchange(limit);
}

int resolve_thread_count(int requested) {
    if (requested > kMaxThreads)
        throw Error::setting("threads", "at most " + std::to_string(kMaxThreads) +
                                            " worker threads, got " + std::to_string(requested));
    if (requested > 0) return requested;
    const unsigned hw = std::thread::hardware_concurrency();
    return hw == 0 ? 1 : int(std::min(hw, unsigned(kMaxThreads)));
}

void parallel_for_rows(int row_count, int threads, const std::function<void(int, int)>& body) {
    if (row_count <= 0) return;
    const int workers = std::clamp(resolve_thread_count(threads), 1, row_count);
    // Small jobs are not worth a thread start (~20 us).
    if (workers == 1 || row_count < 8) {
        body(0, row_count);
        return;
    }
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(workers));
    auto run = [&](int w) {
        const int first = int(std::int64_t(row_count) * w / workers);
        const int end = int(std::int64_t(row_count) * (w + 1) / workers);
        try {
            body(first, end);
        } catch (...) {
            errors[std::size_t(w)] = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    const int started = start_workers(pool, workers, run);
    // The ranges of the workers that could not be started, then the first: the same split, so
    // the same result, on fewer threads.
    for (int w = started; w < workers; ++w) run(w);
    run(0);
    join_all(pool);
    rethrow_first(errors);
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
    start_workers(pool, workers, run);  // the chunks are shared: fewer threads take them all
    run(0);
    join_all(pool);
    rethrow_first(errors);
}

}  // namespace leanfade
