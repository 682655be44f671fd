// Bake throughput: a 4096^2 16-bit normal map, core (slopes, moments, MIPs, packing) and
// end-to-end (PNG decode -> KTX2 written), 1 and 2 threads, next to this machine's memory
// bandwidth (a copy loop in the same run) and `nvcompress -rgb` (Debian libnvtt-bin) when found.
//
// Bytes-moved floor of the core: read the decoded input once (16.8 Mtexel x 3 floats) and write
// the two packed layers with their MIP chains once (~358 MB at 16 bits), at the measured
// bandwidth. Numbers are recorded in docs/perf.md.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/procedural.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"

namespace {

namespace fs = std::filesystem;
using namespace leanfade;

int bench_size() {
    const char* env = std::getenv("LEANFADE_BENCH_SIZE");
    return env ? std::atoi(env) : 4096;
}

fs::path work_dir() {
    static const fs::path dir = [] {
        fs::path d = fs::temp_directory_path() / ("leanfade-bench-" + std::to_string(getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

// A 16-bit RGB normal map from the "noise" set, written once per run.
const std::string& input_png() {
    static const std::string path = [] {
        const int n = bench_size();
        BakeOptions options;
        const Image slopes = slopes_from_height(make_builtin_height("noise", n, 3), options).slopes;
        Image normals(n, n, 3);
        for (std::size_t i = 0; i < slopes.texel_count(); ++i) {
            const float bx = slopes.pixels[2 * i], by = slopes.pixels[2 * i + 1];
            const float inv = 1.0f / std::sqrt(bx * bx + by * by + 1.0f);
            normals.pixels[3 * i] = 0.5f * bx * inv + 0.5f;
            normals.pixels[3 * i + 1] = 0.5f * by * inv + 0.5f;
            normals.pixels[3 * i + 2] = 0.5f * inv + 0.5f;
        }
        const std::string p = (work_dir() / "normals16.png").string();
        io::write_png(p, normals, 16);
        return p;
    }();
    return path;
}

const Image& decoded_input() {
    static const Image image = io::read_image(input_png());
    return image;
}

std::size_t packed_bytes(const PackedLeanMap& map) {
    std::size_t total = 0;
    for (const auto& l : map.levels) total += l.lean1.size() + l.lean2.size();
    return total;
}

void BM_MemoryCopy(benchmark::State& state) {
    const std::size_t bytes = std::size_t(512) << 20;
    std::vector<char> a(bytes, 1), b(bytes, 0);
    for (auto _ : state) {
        std::memcpy(b.data(), a.data(), bytes);
        benchmark::DoNotOptimize(b.data());
        benchmark::ClobberMemory();
    }
    // A copy reads and writes every byte.
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(2 * bytes));
}
BENCHMARK(BM_MemoryCopy)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

void BM_BakeCore(benchmark::State& state) {
    const Image& input = decoded_input();
    BakeOptions options;
    options.threads = int(state.range(0));
    std::size_t moved = 0;
    for (auto _ : state) {
        const BakeResult r = bake_lean_map(input, BakeSource::Normal, options);
        const PackedLeanMap packed = pack_lean_map(r.map, Storage::Unorm16, "bench");
        moved = input.pixels.size() * sizeof(float) + packed_bytes(packed);
        benchmark::DoNotOptimize(packed.levels.data());
    }
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(moved));
    state.counters["texels_per_s"] = benchmark::Counter(
        double(input.texel_count()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BakeCore)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BakeEndToEnd(benchmark::State& state) {
    BakeOptions options;
    options.threads = int(state.range(0));
    const std::string out = (work_dir() / "out.ktx2").string();
    for (auto _ : state) {
        const Image input = io::read_image(input_png());
        const BakeResult r = bake_lean_map(input, BakeSource::Normal, options);
        io::write_ktx2(out, pack_lean_map(r.map, Storage::Unorm16, "bench"));
    }
    state.counters["texels_per_s"] =
        benchmark::Counter(double(bench_size()) * bench_size() * double(state.iterations()),
                           benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BakeEndToEnd)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Nvcompress(benchmark::State& state) {
    if (std::system("command -v nvcompress >/dev/null 2>&1") != 0) {
        state.SkipWithError("nvcompress not installed (Debian libnvtt-bin)");
        return;
    }
    const std::string cmd = "nvcompress -normal -rgb -nomips '" + input_png() + "' '" +
                            (work_dir() / "out.dds").string() + "' >/dev/null 2>&1";
    const std::string cmd_mips = "nvcompress -normal -rgb '" + input_png() + "' '" +
                                 (work_dir() / "out.dds").string() + "' >/dev/null 2>&1";
    const std::string& chosen = state.range(0) ? cmd_mips : cmd;
    for (auto _ : state) {
        if (std::system(chosen.c_str()) != 0) {
            state.SkipWithError("nvcompress failed");
            return;
        }
    }
}
// Arg 1: with its MIP chain (like our bake); 0: top level only.
BENCHMARK(BM_Nvcompress)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    std::error_code ec;
    fs::remove_all(work_dir(), ec);
    return 0;
}
