// Row-parallel loops under failure: a thread that cannot be started (an address-space limit, as
// under `ulimit -v`) and an exception in a worker are not aborts (docs/robustness.md). The
// limits are set in a forked child, so that the test runner keeps its own.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/parallel.hpp"

namespace leanfade {
namespace {

// Each row of [0, rows) once, from any number of threads.
bool every_row_once(const std::vector<std::atomic<int>>& seen) {
    for (const auto& s : seen)
        if (s.load() != 1) return false;
    return true;
}

#if !defined(__SANITIZE_ADDRESS__)
// Address space of this process now, bytes (/proc/self/statm: size in pages).
long long address_space_bytes() {
    std::ifstream statm("/proc/self/statm");
    long long pages = 0;
    statm >> pages;
    return pages * ::sysconf(_SC_PAGESIZE);
}

// Runs `body` in a forked child whose address space may grow by `headroom` bytes only: room for
// `headroom / 8 MiB` thread stacks at most. Returns the child's exit code, or 128 + the signal
// that ended it (SIGABRT = 134: std::terminate).
template <class Body>
int in_child_with_address_space_headroom(long long headroom, Body body) {
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const rlimit limit{rlim_t(address_space_bytes() + headroom),
                           rlim_t(address_space_bytes() + headroom)};
        if (::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(90);
        int code = 0;
        try {
            code = body();
        } catch (const Error&) {
            code = 91;
        } catch (...) {
            code = 92;  // anything else escaping the loop (std::system_error before the fix)
        }
        ::_exit(code);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

#endif

constexpr int kRows = 4000;

int rows_loop() {
    std::vector<std::atomic<int>> seen(kRows);
    parallel_for_rows(kRows, 16, [&](int first, int end) {
        for (int y = first; y < end; ++y) seen[std::size_t(y)].fetch_add(1);
    });
    return every_row_once(seen) ? 0 : 1;
}

int dynamic_loop() {
    std::vector<std::atomic<int>> seen(kRows);
    std::atomic<int> bad_worker{0};
    parallel_for_dynamic(kRows, 16, 7, [&](int worker, int first, int end) {
        if (worker < 0 || worker >= 16) bad_worker = 1;
        for (int y = first; y < end; ++y) seen[std::size_t(y)].fetch_add(1);
    });
    return every_row_once(seen) && bad_worker == 0 ? 0 : 1;
}

// Every number of threads that could start, 0 to 15 of the 15 workers asked for: the loops
// cover every row once. The same path as the system's refusals below, through the test limit
// (it runs in sanitizer builds too).
TEST(ParallelLimits, AnyNumberOfStartedThreadsCoversEveryRowOnce) {
    for (int started = 0; started <= 15; ++started) {
        const int previous = set_thread_start_limit_for_testing(started);
        EXPECT_EQ(rows_loop(), 0) << started;
        EXPECT_EQ(dynamic_loop(), 0) << started;
        set_thread_start_limit_for_testing(previous);
    }
}

// The system's own refusals. AddressSanitizer's allocator maps memory for every thread and
// aborts the process when it cannot, so an address-space limit cannot make a thread start fail
// under it: these two run in the ordinary builds (CI), the test above in all.
#if !defined(__SANITIZE_ADDRESS__)
// Two thread stacks fit (8 MiB each by default), the third cannot be mapped: the loop must
// finish on the threads it has (before: the started threads were destroyed while joinable,
// std::terminate).
TEST(ParallelLimits, ThreadsThatCannotStartLeaveTheWorkToTheOthers) {
    const long long room = 20ll << 20;
    EXPECT_EQ(in_child_with_address_space_headroom(room, rows_loop), 0);
    EXPECT_EQ(in_child_with_address_space_headroom(room, dynamic_loop), 0);
}

// No thread at all can be started: the calling thread does all the work (before: the
// std::system_error of std::thread escaped).
TEST(ParallelLimits, NoThreadAtAllRunsOnTheCallingThread) {
    const long long room = 1ll << 20;
    EXPECT_EQ(in_child_with_address_space_headroom(room, rows_loop), 0);
    EXPECT_EQ(in_child_with_address_space_headroom(room, dynamic_loop), 0);
}
#endif

// Without a limit the loops use their threads and give the same coverage.
TEST(ParallelLimits, UnlimitedLoopsCoverEveryRowOnce) {
    EXPECT_EQ(rows_loop(), 0);
    EXPECT_EQ(dynamic_loop(), 0);
}

TEST(ParallelLimits, AWorkersExceptionReachesTheCaller) {
    EXPECT_THROW(parallel_for_rows(1000, 8,
                                   [](int first, int) {
                                       if (first > 0) throw Error("row", "bad row");
                                   }),
                 Error);
    EXPECT_THROW(parallel_for_dynamic(1000, 8, 10,
                                      [](int, int first, int) {
                                          if (first == 500) throw std::runtime_error("x");
                                      }),
                 std::runtime_error);
}

TEST(ParallelLimits, ThreadCountsBeyondTheBoundAreRefused) {
    EXPECT_EQ(resolve_thread_count(kMaxThreads), kMaxThreads);
    EXPECT_GE(resolve_thread_count(0), 1);
    EXPECT_LE(resolve_thread_count(0), kMaxThreads);
    try {
        resolve_thread_count(10000);
        FAIL() << "10000 threads accepted";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "threads: at most 1024 worker threads, got 10000");
    }
    EXPECT_THROW(parallel_for_rows(100, 10000, [](int, int) {}), Error);
}

}  // namespace
}  // namespace leanfade
