#pragma once
// Row-parallel loops. Work is split into contiguous row ranges; as long as the body writes only
// its own rows, results are identical for any thread count.
#include <functional>

namespace leanfade {

// requested <= 0 means "all hardware threads"; the result is at least 1.
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
