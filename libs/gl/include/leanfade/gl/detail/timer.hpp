#pragma once
// Timing of GPU work for the benchmarks (`leanfade bench`): GL_TIME_ELAPSED timer queries where
// the driver's are meaningful, glFinish + std::chrono::steady_clock elsewhere, and the statistics
// of a set of frame times.
//
// Why two methods: timer queries measure the time the GPU spent between glBeginQuery and
// glEndQuery, without the CPU's submission cost and without stalling the pipeline, which is what
// the papers' frame rates reflect on a GPU. On software rasterisers (Mesa llvmpipe and softpipe)
// the query brackets only the command submission; the rasterisation runs on worker threads
// afterwards, so a full frame reads as a fraction of a millisecond. There the only honest clock
// is the CPU's: glFinish before and after the frame, with a steady clock in between.
#include <cstdint>
#include <string>
#include <vector>

#include "leanfade/gl/detail/context.hpp"
#include "leanfade/gl/detail/objects.hpp"

namespace leanfade::gl {

enum class TimingMethod {
    Auto,  // Gpu when the driver has GL_TIME_ELAPSED counter bits and is not a software renderer
    Gpu,   // GL_TIME_ELAPSED queries
    Cpu,   // glFinish, steady_clock, glFinish
    // glFinish, then the CPU time of the whole process (every llvmpipe thread) instead of the
    // clock: for software renderers on a shared machine, where other processes' load inflates
    // wall-clock times. Not a frame time (it leaves out waiting); only chosen when asked for.
    CpuTime,
};

// "auto", "gpu", "cpu", "cputime".
const char* to_string(TimingMethod method);
// Throws leanfade::Error(flag, cause) for an unknown name.
TimingMethod parse_timing_method(const std::string& text, const std::string& flag = "timing");

// True for renderers that rasterise on the CPU (GL_RENDERER containing llvmpipe, softpipe,
// swrast or SwiftShader, any case).
bool is_software_renderer(const std::string& renderer);

// GL_QUERY_COUNTER_BITS of GL_TIME_ELAPSED queries (0: the driver does not time).
int time_elapsed_counter_bits();

// The method a benchmark uses, and why, for its output.
struct TimingChoice {
    TimingMethod method = TimingMethod::Cpu;  // never Auto
    std::string description;                  // one line: the method and the reason
};

// Resolves `requested` on the current context: Auto -> Gpu when time_elapsed_counter_bits() > 0
// and the renderer is not a software one, otherwise Cpu. Gpu is honoured on any driver with
// counter bits (on a software renderer the description says that the figures under-report); a
// driver without them throws leanfade::Error(flag, cause).
TimingChoice choose_timing(TimingMethod requested, const Context& context,
                           const std::string& flag = "timing");

// Times a sequence of intervals of GL work, in milliseconds. begin() and end() bracket each
// interval (they must alternate, starting with begin()); collect() returns the durations of the
// intervals ended since the last collect(), in order.
// - Gpu: each interval is a GL_TIME_ELAPSED query (queries are pooled and reused); collect()
//   waits for their results. Intervals must not nest (a GL rule for queries of one target).
// - Cpu: begin() calls glFinish and reads the steady clock, end() calls glFinish and reads it
//   again; collect() only hands back the values. CpuTime: the same with the process's CPU time.
class IntervalTimer {
  public:
    explicit IntervalTimer(TimingMethod method);
    IntervalTimer(const IntervalTimer&) = delete;
    IntervalTimer& operator=(const IntervalTimer&) = delete;

    void begin();
    void end();
    std::vector<double> collect();

    TimingMethod method() const { return method_; }

  private:
    TimingMethod method_;
    bool open_ = false;
    std::vector<Query> queries_;  // Gpu: the pool; the first `used_` are in flight
    std::size_t used_ = 0;
    std::int64_t started_ns_ = 0;  // Cpu
    std::vector<double> cpu_ms_;   // Cpu: ended intervals
};

// Statistics of a set of durations (milliseconds). Percentiles interpolate linearly between
// order statistics (the "R-7" definition); an empty set gives all zeros.
struct SampleStats {
    int count = 0;
    double median = 0.0;
    double p25 = 0.0;
    double p75 = 0.0;
    double min = 0.0;
    double max = 0.0;
    double mean = 0.0;
};
SampleStats sample_stats(std::vector<double> values);
// The q-quantile (0 <= q <= 1) of a sorted, non-empty set.
double sorted_quantile(const std::vector<double>& sorted, double q);

}  // namespace leanfade::gl
