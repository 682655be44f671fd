#pragma once
// Row-parallel loops. Work is split into contiguous row ranges; as long as the body writes only
// its own rows, results are identical for any thread count.
#include <functional>

namespace leanfade {

// requested <= 0 means "all hardware threads"; the result is at least 1.
int resolve_thread_count(int requested);

// Calls body(first_row, end_row) over [0, row_count) split across `threads` threads (blocking).
void parallel_for_rows(int row_count, int threads, const std::function<void(int, int)>& body);

}  // namespace leanfade
