// Bake throughput against the copy bandwidth of this machine.
#include "cli_bench_bake.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/detail/procedural.hpp"

namespace leanfade::cli {
namespace {

// Worker threads of a bake: the bound of `leanfade bake --threads`.
constexpr int kMaxBakeThreads = 256;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

constexpr int kTileSize = 1024;

}  // namespace

Image tiled_bumps_height(int size) {
    const int tile_size = std::min(size, kTileSize);
    const Image tile = make_builtin_height("bumps", tile_size, 1);
    if (tile_size == size) return tile;
    Image image(size, size, 1);
    for (int y = 0; y < size; ++y) {
        const float* src = tile.row(y % tile_size);
        float* dst = image.row(y);
        for (int x = 0; x < size; x += tile_size)
            std::memcpy(dst + x, src, std::size_t(std::min(tile_size, size - x)) * sizeof(float));
    }
    return image;
}

Image tiled_bumps_normals(int size) {
    const int tile_size = std::min(size, kTileSize);
    const Image slopes =
        slopes_from_height(make_builtin_height("bumps", tile_size, 1), BakeOptions{}).slopes;
    Image image(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float bx = slopes.at(x % tile_size, y % tile_size, 0);
            const float by = slopes.at(x % tile_size, y % tile_size, 1);
            const float inv = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
            image.at(x, y, 0) = 0.5f * bx * inv + 0.5f;
            image.at(x, y, 1) = 0.5f * by * inv + 0.5f;
            image.at(x, y, 2) = 0.5f * inv + 0.5f;
        }
    return image;
}

double measure_copy_bandwidth(std::size_t bytes, int threads, int repeats) {
    const std::size_t chunks = 256;
    const std::size_t chunk = (bytes + chunks - 1) / chunks;
    const std::size_t total = chunk * chunks;
    std::unique_ptr<char[]> src(new char[total]);
    std::unique_ptr<char[]> dst(new char[total]);
    // Touch every page first, so the timed copies see no page faults.
    parallel_for_rows(int(chunks), threads, [&](int first, int end) {
        for (int c = first; c < end; ++c) {
            std::memset(src.get() + std::size_t(c) * chunk, c & 0x7F, chunk);
            std::memset(dst.get() + std::size_t(c) * chunk, 0, chunk);
        }
    });
    double best = 0.0;
    for (int r = 0; r < std::max(1, repeats); ++r) {
        const Clock::time_point start = Clock::now();
        parallel_for_rows(int(chunks), threads, [&](int first, int end) {
            std::memcpy(dst.get() + std::size_t(first) * chunk,
                        src.get() + std::size_t(first) * chunk, std::size_t(end - first) * chunk);
        });
        const double seconds = seconds_since(start);
        if (seconds > 0.0) best = std::max(best, 2.0 * double(total) / seconds);
    }
    // Keep the copy observable.
    volatile char sink = dst[total / 2];
    (void)sink;
    return best;
}

namespace {

// One input kind and size: an untimed bake (allocating the output), then the timed ones.
BakeBenchRow bake_row(const std::string& input, int size, const BakeOptions& options, int runs,
                      const std::function<void(const std::string&)>& say) {
    say("baking a " + std::to_string(size) + "^2 " + input + " map");
    const bool normal = input == "normal";
    const Image image = normal ? tiled_bumps_normals(size) : tiled_bumps_height(size);
    const BakeSource source = normal ? BakeSource::Normal : BakeSource::Height;
    const BakeSettings settings{.options = options,
                                .storage = StoragePolicy::fixed(Storage::Unorm16),
                                .generator = "bench",
                                .keep_empty_plateau = true};
    // Each timed bake takes the buffers of the one before: the output is allocated once.
    const auto bake_again = [&](PackedBakeResult& baked) {
        PackedMapSink memory(std::move(baked.packed.levels));
        baked = bake(BakeInput(image, source), settings, memory);
    };
    PackedBakeResult baked;
    bake_again(baked);
    BakeBenchRow row;
    row.input = input;
    row.size = size;
    row.runs = runs > 0 ? runs : (size <= 2048 ? 5 : (size <= 4096 ? 3 : 2));
    std::vector<double> seconds;
    for (int r = 0; r < row.runs; ++r) {
        const Clock::time_point start = Clock::now();
        bake_again(baked);
        seconds.push_back(seconds_since(start));
    }
    std::sort(seconds.begin(), seconds.end());
    const std::size_t n = seconds.size();
    row.median_seconds = n % 2 == 1 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
    row.min_seconds = seconds.front();
    row.input_bytes = image.pixels.size() * sizeof(float);
    for (const PackedLevel& level : baked.packed.levels)
        row.output_bytes += level.lean1.size() + level.lean2.size();
    const double bytes = double(row.input_bytes + row.output_bytes);
    row.megabytes_per_second = bytes / row.median_seconds / 1e6;
    row.texels_per_second = double(size) * double(size) / row.median_seconds;
    return row;
}

}  // namespace

BakeBenchResult run_bake_bench(const std::vector<std::string>& inputs,
                               const std::vector<int>& sizes, int threads, int runs,
                               const std::function<void(const std::string&)>& progress) {
    for (const std::string& input : inputs)
        if (input != "normal" && input != "height")
            throw Error("--bake-input", "expected normal or height, got '" + input + "'");
    for (int size : sizes)
        if (size < 4 || size > kDefaultMaxImageDimension)
            throw Error("--bake-sizes", "sizes must be in [4, " +
                                            std::to_string(kDefaultMaxImageDimension) + "], got " +
                                            std::to_string(size));
    if (runs < 0 || runs > 1000) throw Error("--bake-runs", "must be in [0, 1000]");
    // The bound of `leanfade bake --threads`: more threads than that only measure thread starts.
    if (threads < 0 || threads > kMaxBakeThreads)
        throw Error("--threads", "must be in [0, " + std::to_string(kMaxBakeThreads) +
                                     "] (0 = all hardware threads), got " +
                                     std::to_string(threads));
    const std::function<void(const std::string&)> say = [&](const std::string& text) {
        if (progress) progress(text);
    };
    BakeBenchResult result;
    result.threads = resolve_thread_count(threads);
    result.simd = bake_simd_active();
    result.copy_bytes = std::size_t(512) << 20;
    say("measuring the copy bandwidth");
    result.copy_bytes_per_second = measure_copy_bandwidth(result.copy_bytes, threads, 5);

    BakeOptions options;
    options.threads = threads;
    // The two layers lean1 and lean2 (docs/perf.md: the plateau layer's cost is measured apart).
    options.plateau_epsilon = 0.0f;
    for (const std::string& input : inputs)
        for (int size : sizes) result.rows.push_back(bake_row(input, size, options, runs, say));
    const double bandwidth = result.copy_bytes_per_second;
    for (BakeBenchRow& row : result.rows) {
        const double bytes = double(row.input_bytes + row.output_bytes);
        row.floor_seconds = bandwidth > 0.0 ? bytes / bandwidth : 0.0;
        row.floor_ratio = row.floor_seconds > 0.0 ? row.median_seconds / row.floor_seconds : 0.0;
    }
    return result;
}

}  // namespace leanfade::cli
