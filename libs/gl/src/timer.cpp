// GL_TIME_ELAPSED queries or glFinish + steady_clock, and frame-time statistics.
#include "leanfade/gl/detail/timer.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <numeric>

#include "leanfade/core/error.hpp"

namespace leanfade::gl {
namespace {

std::int64_t now_ns(TimingMethod method) {
    if (method == TimingMethod::CpuTime) {
        timespec t{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
        return std::int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
    }
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

std::string lower(std::string text) {
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

}  // namespace

const char* to_string(TimingMethod method) {
    switch (method) {
        case TimingMethod::Auto:
            return "auto";
        case TimingMethod::Gpu:
            return "gpu";
        case TimingMethod::Cpu:
            return "cpu";
        case TimingMethod::CpuTime:
            return "cputime";
    }
    return "?";
}

TimingMethod parse_timing_method(const std::string& text, const std::string& flag) {
    for (TimingMethod m :
         {TimingMethod::Auto, TimingMethod::Gpu, TimingMethod::Cpu, TimingMethod::CpuTime})
        if (text == to_string(m)) return m;
    throw Error::setting(flag, "expected auto, gpu, cpu or cputime, got '" + text + "'");
}

bool is_software_renderer(const std::string& renderer) {
    const std::string r = lower(renderer);
    for (const char* name : {"llvmpipe", "softpipe", "swrast", "swiftshader"})
        if (r.find(name) != std::string::npos) return true;
    return false;
}

int time_elapsed_counter_bits() {
    GLint bits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
    return bits;
}

TimingChoice choose_timing(TimingMethod requested, const Context& context,
                           const std::string& flag) {
    const int bits = time_elapsed_counter_bits();
    const bool software = is_software_renderer(context.renderer());
    const std::string queries =
        "GL_TIME_ELAPSED queries (" + std::to_string(bits) + "-bit counter)";
    const std::string finish = "glFinish + steady_clock";
    TimingChoice choice;
    switch (requested) {
        case TimingMethod::Gpu:
            if (bits <= 0)
                throw Error::setting(flag, "gpu timing needs GL_TIME_ELAPSED queries, and " +
                                               context.renderer() + " has no timer counter bits");
            choice.method = TimingMethod::Gpu;
            choice.description = queries + ", forced" +
                                 (software ? "; on a software renderer they time only the "
                                             "submission and under-report"
                                           : "");
            return choice;
        case TimingMethod::Cpu:
            choice.method = TimingMethod::Cpu;
            choice.description = finish + ", forced";
            return choice;
        case TimingMethod::CpuTime:
            choice.method = TimingMethod::CpuTime;
            choice.description =
                "glFinish + process CPU time (every thread; leaves out waiting and other "
                "processes' load: a cost, not a frame time), forced";
            return choice;
        case TimingMethod::Auto:
            break;
    }
    if (bits > 0 && !software) {
        choice.method = TimingMethod::Gpu;
        choice.description = queries;
    } else {
        choice.method = TimingMethod::Cpu;
        choice.description =
            finish + (software ? " (software renderer: its GL_TIME_ELAPSED queries time only "
                                 "the submission and under-report)"
                               : " (the driver has no GL_TIME_ELAPSED counter bits)");
    }
    return choice;
}

IntervalTimer::IntervalTimer(TimingMethod method) : method_(method) {
    if (method == TimingMethod::Auto)
        throw Error("timer", "resolve the timing method with choose_timing() first");
}

void IntervalTimer::begin() {
    if (open_) throw Error("timer", "begin() called twice without end()");
    open_ = true;
    if (method_ == TimingMethod::Gpu) {
        if (used_ == queries_.size()) queries_.push_back(create_query(GL_TIME_ELAPSED));
        glBeginQuery(GL_TIME_ELAPSED, queries_[used_].get());
    } else {
        glFinish();
        started_ns_ = now_ns(method_);
    }
}

void IntervalTimer::end() {
    if (!open_) throw Error("timer", "end() called without begin()");
    open_ = false;
    if (method_ == TimingMethod::Gpu) {
        glEndQuery(GL_TIME_ELAPSED);
        ++used_;
    } else {
        glFinish();
        cpu_ms_.push_back(double(now_ns(method_) - started_ns_) * 1e-6);
    }
}

std::vector<double> IntervalTimer::collect() {
    if (open_) throw Error("timer", "collect() called inside an interval");
    std::vector<double> result;
    if (method_ == TimingMethod::Gpu) {
        result.reserve(used_);
        for (std::size_t i = 0; i < used_; ++i) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(queries_[i].get(), GL_QUERY_RESULT, &ns);  // waits
            result.push_back(double(ns) * 1e-6);
        }
        used_ = 0;
    } else {
        result.swap(cpu_ms_);
    }
    return result;
}

double sorted_quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    const double position = std::clamp(q, 0.0, 1.0) * double(sorted.size() - 1);
    const std::size_t lo = std::size_t(std::floor(position));
    const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    const double t = position - double(lo);
    return sorted[lo] + t * (sorted[hi] - sorted[lo]);
}

SampleStats sample_stats(std::vector<double> values) {
    SampleStats s;
    if (values.empty()) return s;
    std::sort(values.begin(), values.end());
    s.count = int(values.size());
    s.median = sorted_quantile(values, 0.5);
    s.p25 = sorted_quantile(values, 0.25);
    s.p75 = sorted_quantile(values, 0.75);
    s.min = values.front();
    s.max = values.back();
    s.mean = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
    return s;
}

}  // namespace leanfade::gl
