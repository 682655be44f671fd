#pragma once
// Row-parallel loops. Work is split into contiguous row ranges; as long as the body writes only
// its own rows, results are identical for any thread count.
//
// Failures: an exception thrown by the body in any thread is carried to the caller (the first
// worker's, by worker index) once every thread has finished. A thread that cannot be started (a
// process or address-space limit) is not an error: the loop runs on the threads it could start,
// the calling thread taking the work of the others, with the same result.
#include <functional>

namespace leanfade {

// For tests: from now on, every loop of this process can start at most `limit` threads besides
// the calling one, as if the system refused the next (-1: no limit, the default). It exercises
// the same path as a real refusal where one cannot be produced (under AddressSanitizer, whose
// allocator aborts when the address space runs out). Returns the previous limit.
int set_thread_start_limit_for_testing(int limit);

// The most worker threads a loop takes (a request beyond it is refused, not clamped).
inline constexpr int kMaxThreads = 1024;

// requested <= 0 means "all hardware threads" (at most kMaxThreads); the result is at least 1.
// Throws leanfade::Error("threads", cause) for requested > kMaxThreads.
int resolve_thread_count(int requested);

// Calls body(first_row, end_row) over [0, row_count) split across `threads` threads (blocking).
void parallel_for_rows(int row_count, int threads, const std::function<void(int, int)>& body);

// Dynamic schedule for uneven or contended work: chunks [first, end) of at most `grain` rows of
// [0, row_count) are handed out in increasing order to up to `threads` workers as they become
// free, so a worker slowed down by other load takes fewer. Calls body(worker, first, end), worker
// in [0, resolve_thread_count(threads)); the chunks of one worker come in increasing order. As
// above, results are identical for any thread count as long as the body writes only its rows.
void parallel_for_dynamic(int row_count, int threads, int grain,
                          const std::function<void(int, int, int)>& body);

}  // namespace leanfade
