#pragma once
// `leanfade bench --bake`: bake throughput of the CPU baker (bake_packed, the fused fast path of
// libs/core) against this machine's memory bandwidth, measured by a copy loop in the same run.
// GL-free.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "leanfade/core/image.hpp"

namespace leanfade::cli {

// A size x size height map: the built-in "bumps" set (seed 1) at min(size, 1024) texels, tiled
// (it is tileable), so that large inputs cost no more to make than the 1024 set.
Image tiled_bumps_height(int size);
// The same bumps as a 3-channel normal map (encoded 0.5 n + 0.5, floats), tiled likewise.
Image tiled_bumps_normals(int size);

// Copy bandwidth: the best of `repeats` parallel memcpy runs of `bytes` (threads as
// resolve_thread_count), counting the bytes read plus the bytes written, in bytes per second.
double measure_copy_bandwidth(std::size_t bytes, int threads, int repeats);

struct BakeBenchRow {
    std::string input;  // "normal" (3 floats per texel) or "height" (1 float)
    int size = 0;       // texels per side of the top level
    int runs = 0;       // timed bakes
    double median_seconds = 0.0;
    double min_seconds = 0.0;
    std::size_t input_bytes = 0;        // the float input read
    std::size_t output_bytes = 0;       // both packed layers, every level, written
    double megabytes_per_second = 0.0;  // (input + output) / median, MB = 1e6 bytes
    double texels_per_second = 0.0;     // top-level texels / median
    double floor_seconds = 0.0;         // (input + output) / copy bandwidth
    double floor_ratio = 0.0;           // median / floor
};

struct BakeBenchResult {
    int threads = 0;
    bool simd = false;           // AVX2 kernels in use
    std::size_t copy_bytes = 0;  // size of the copied buffer
    double copy_bytes_per_second = 0.0;
    std::string storage = "16";  // packed storage
    std::vector<BakeBenchRow> rows;
};

// Times bake_packed_into (16-bit UNORM, repeat wrap) for each input kind ("normal", "height") and
// size: one untimed bake, then `runs` timed ones (0: 5 up to 2048, 3 at 4096, 2 above).
// progress(text) reports each step. Throws leanfade::Error(flag, cause) for bad arguments.
BakeBenchResult run_bake_bench(const std::vector<std::string>& inputs,
                               const std::vector<int>& sizes, int threads, int runs,
                               const std::function<void(const std::string&)>& progress = {});

}  // namespace leanfade::cli
