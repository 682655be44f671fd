// Bake throughput: a 4096^2 16-bit normal map, core (slopes, moments, MIPs, packing) and
// end-to-end (PNG decode -> KTX2 written), 1 and 2 threads, next to this machine's memory
// bandwidth (copy, read and write loops in the same run) and `nvcompress -rgb` (Debian
// libnvtt-bin) on the same PNG when it is installed.
//
// Bytes-moved floor of the core: read the decoded input once (16.8 Mtexel x 3 floats = 201 MB)
// and write the two packed layers with their MIP chains once (~358 MB at 16 bits), at the copy
// bandwidth (BM_MemoryCopy counts read + written bytes). Numbers are recorded in docs/perf.md.
//
// BM_BakeCore bakes into the same PackedBakeResult every iteration (as BM_MemoryCopy copies
// into the same buffer); BM_BakeCoreFresh allocates the output every time, as a one-off bake
// does; BM_BakeCoreReference is the reference path (bake_lean_map + pack_lean_map) that the
// fast path replaced, for the before / after comparison in one run. LEANFADE_BENCH_SIZE
// changes the size.
#include <map>
#include <sys/wait.h>
#include <sys/resource.h>
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/basis_universal.hpp"
#include "leanfade/io/detail/block_compression.hpp"
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
    for (const auto& l : map.levels) total += l.lean1.size() + l.lean2.size() + l.plateau.size();
    return total;
}

constexpr std::size_t kBandwidthBytes = std::size_t(512) << 20;

void BM_MemoryCopy(benchmark::State& state) {
    std::vector<char> a(kBandwidthBytes, 1), b(kBandwidthBytes, 0);
    for (auto _ : state) {
        std::memcpy(b.data(), a.data(), kBandwidthBytes);
        benchmark::DoNotOptimize(b.data());
        benchmark::ClobberMemory();
    }
    // A copy reads and writes every byte.
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(2 * kBandwidthBytes));
}
BENCHMARK(BM_MemoryCopy)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

// Read-only and write-only bandwidth, for the breakdown of the floor in docs/perf.md.
void BM_MemoryRead(benchmark::State& state) {
    std::vector<std::uint64_t> a(kBandwidthBytes / 8, 1);
    for (auto _ : state) {
        std::uint64_t sum = 0;
        for (std::size_t i = 0; i < a.size(); i += 4) sum += a[i] ^ a[i + 1] ^ a[i + 2] ^ a[i + 3];
        benchmark::DoNotOptimize(sum);
    }
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(kBandwidthBytes));
}
BENCHMARK(BM_MemoryRead)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

void BM_MemoryWrite(benchmark::State& state) {
    std::vector<char> a(kBandwidthBytes, 1);
    int value = 0;
    for (auto _ : state) {
        std::memset(a.data(), ++value, kBandwidthBytes);
        benchmark::DoNotOptimize(a.data());
        benchmark::ClobberMemory();
    }
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(kBandwidthBytes));
}
BENCHMARK(BM_MemoryWrite)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

// The core's bytes-moved floor in bytes: the decoded input read once, `packed` bytes written once.
std::size_t floor_bytes(const Image& input, std::size_t packed) {
    return input.pixels.size() * sizeof(float) + packed;
}

// One bake of the core benchmarks: `input` into `result`, 16-bit, reusing its buffers; the two
// layers lean1 and lean2 only unless plateau_epsilon > 0 (the plateau layer of two-lobe LEAN,
// which `leanfade bake` adds by default: BM_BakeCoreWithPlateau).
void bake_core(PackedBakeResult& result, const Image& input, int threads,
               float plateau_epsilon = 0.0f, SpikeFit spike = SpikeFit::Auto) {
    BakeOptions options;
    options.threads = threads;
    options.plateau_epsilon = plateau_epsilon;
    options.spike_fit = spike;
    bake_packed_into(result, input, BakeSource::Normal, options, Storage::Unorm16, "bench");
    benchmark::DoNotOptimize(result.packed.levels.data());
}

void set_core_counters(benchmark::State& state, const Image& input, std::size_t packed) {
    const std::size_t moved = floor_bytes(input, packed);
    state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(moved));
    state.counters["texels_per_s"] = benchmark::Counter(
        double(input.texel_count()) * double(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["simd"] = bake_simd_active() ? 1 : 0;
}

// The core bake at state.range(0) threads with the plateau layer's settings (bake_core).
void run_bake_core(benchmark::State& state, float plateau_epsilon, SpikeFit spike) {
    const Image& input = decoded_input();
    PackedBakeResult result;
    const int threads = int(state.range(0));
    // Untimed first bake: allocates (and faults in) the output, as BM_MemoryCopy's buffers are.
    bake_core(result, input, threads, plateau_epsilon, spike);
    for (auto _ : state) bake_core(result, input, threads, plateau_epsilon, spike);
    set_core_counters(state, input, packed_bytes(result.packed));
}

void BM_BakeCore(benchmark::State& state) {
    run_bake_core(state, 0.0f, SpikeFit::Auto);
}
BENCHMARK(BM_BakeCore)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

// The same bake with two-lobe LEAN's plateau layer (docs/math.md §10), as `leanfade bake` writes
// by default: BM_BakeCoreWithPlateau / BM_BakeCore is the time the layer adds to a bake.
void BM_BakeCoreWithPlateau(benchmark::State& state) {
    run_bake_core(state, kDefaultPlateauEpsilon, SpikeFit::Auto);
}
BENCHMARK(BM_BakeCoreWithPlateau)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

// The same with the plateaus alone forming the spike (`--spike plateaus`, leanfade 0.2's layer):
// BM_BakeCoreWithPlateau / this is the time the central window's fit adds (docs/math.md §10).
void BM_BakeCorePlateausOnly(benchmark::State& state) {
    run_bake_core(state, kDefaultPlateauEpsilon, SpikeFit::Plateaus);
}
BENCHMARK(BM_BakeCorePlateausOnly)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

// The plateau layer's reference path (add_plateau_layer: packed_top_slopes, plateau_mips, then
// packed), the float images the fused bake does without.
void BM_PlateauLayer(benchmark::State& state) {
    const Image& input = decoded_input();
    PackedBakeResult result;
    bake_core(result, input, 0, kDefaultPlateauEpsilon);
    for (auto _ : state) {
        add_plateau_layer(result.packed);
        benchmark::DoNotOptimize(result.packed.levels.data());
    }
    state.counters["texels_per_s"] = benchmark::Counter(
        double(input.texel_count()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PlateauLayer)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

// The bake's cost over the memory floor, drift cancelled: each iteration times one copy of 512 MiB (the
// bandwidth, as BM_MemoryCopy) and then one bake (as BM_BakeCore), and the counters give the
// floor of that iteration's bandwidth and the mean of the per-iteration ratios core / floor.
void BM_CoreOverFloor(benchmark::State& state) {
    const Image& input = decoded_input();
    PackedBakeResult result;
    bake_core(result, input, int(state.range(0)));
    const double floor = double(floor_bytes(input, packed_bytes(result.packed)));
    std::vector<char> a(kBandwidthBytes, 1), b(kBandwidthBytes, 0);
    double ratio_sum = 0.0, floor_sum = 0.0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        std::memcpy(b.data(), a.data(), kBandwidthBytes);
        benchmark::ClobberMemory();
        const auto t1 = std::chrono::steady_clock::now();
        bake_core(result, input, int(state.range(0)));
        const auto t2 = std::chrono::steady_clock::now();
        const double copy_s = std::chrono::duration<double>(t1 - t0).count();
        const double core_s = std::chrono::duration<double>(t2 - t1).count();
        const double floor_s = floor / (2.0 * double(kBandwidthBytes) / copy_s);
        state.SetIterationTime(core_s);
        ratio_sum += core_s / floor_s;
        floor_sum += floor_s;
    }
    const double n = double(state.iterations());
    state.counters["floor_ms"] = 1e3 * floor_sum / n;
    state.counters["core_over_floor"] = ratio_sum / n;
}
BENCHMARK(BM_CoreOverFloor)->Arg(2)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(20);

void BM_BakeCoreFresh(benchmark::State& state) {
    const Image& input = decoded_input();
    BakeOptions options;
    options.threads = int(state.range(0));
    options.plateau_epsilon = 0.0f;  // the two layers, as BM_BakeCore
    std::size_t bytes = 0;
    for (auto _ : state) {
        const PackedBakeResult r =
            bake_packed(input, BakeSource::Normal, options, Storage::Unorm16, "bench");
        bytes = packed_bytes(r.packed);
        benchmark::DoNotOptimize(r.packed.levels.data());
    }
    set_core_counters(state, input, bytes);
}
BENCHMARK(BM_BakeCoreFresh)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

// The portable kernels (what a CPU without AVX2 runs); same bytes.
void BM_BakeCoreScalar(benchmark::State& state) {
    const Image& input = decoded_input();
    PackedBakeResult result;
    const bool previous = set_bake_simd(false);
    bake_core(result, input, int(state.range(0)));
    for (auto _ : state) bake_core(result, input, int(state.range(0)));
    set_core_counters(state, input, packed_bytes(result.packed));
    set_bake_simd(previous);
}
BENCHMARK(BM_BakeCoreScalar)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BakeCoreReference(benchmark::State& state) {
    const Image& input = decoded_input();
    BakeOptions options;
    options.threads = int(state.range(0));
    options.plateau_epsilon = 0.0f;  // the two layers, as BM_BakeCore
    std::size_t bytes = 0;
    for (auto _ : state) {
        const BakeResult r = bake_lean_map(input, BakeSource::Normal, options);
        const PackedLeanMap packed = pack_lean_map(r.map, Storage::Unorm16, "bench");
        bytes = packed_bytes(packed);
        benchmark::DoNotOptimize(packed.levels.data());
    }
    set_core_counters(state, input, bytes);
}
BENCHMARK(BM_BakeCoreReference)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

// The parts of the end-to-end time that are not the core.
void BM_DecodePng(benchmark::State& state) {
    input_png();  // written once, outside the timing
    for (auto _ : state) {
        const Image input = io::read_image(input_png());
        benchmark::DoNotOptimize(input.pixels.data());
    }
}
BENCHMARK(BM_DecodePng)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_WriteKtx2(benchmark::State& state) {
    BakeOptions two_layers;
    two_layers.plateau_epsilon = 0.0f;  // as BM_BakeCore
    const PackedBakeResult r =
        bake_packed(decoded_input(), BakeSource::Normal, two_layers, Storage::Unorm16, "bench");
    const std::string out = (work_dir() / "write.ktx2").string();
    for (auto _ : state) io::write_ktx2(out, r.packed);
    state.SetBytesProcessed(std::int64_t(state.iterations()) *
                            std::int64_t(packed_bytes(r.packed)));
}
BENCHMARK(BM_WriteKtx2)->Unit(benchmark::kMillisecond)->UseRealTime();

// What `leanfade bake in.png -o out.ktx2 --threads N --plateau-epsilon 0` does: the PNG's
// 16-bit samples kept as integers, baked straight into the mapped output file (the two layers,
// as BM_BakeCore; BM_BakeCoreWithPlateau has the plateau layer's cost).
void BM_BakeEndToEnd(benchmark::State& state) {
    BakeOptions options;
    options.threads = int(state.range(0));
    options.plateau_epsilon = 0.0f;
    const std::string out = (work_dir() / "out.ktx2").string();
    input_png();
    io::ReadOptions read_options;
    read_options.drop_alpha = true;
    io::WriteOptions write_options;
    write_options.threads = options.threads;
    for (auto _ : state) {
        const std::variant<Image, UnormImage> samples =
            io::read_image_compact(input_png(), read_options);
        io::Ktx2FileSink file(out, write_options);
        bake(BakeInput(samples, BakeSource::Normal, input_png()),
             BakeSettings{.options = options,
                          .storage = StoragePolicy::fixed(Storage::Unorm16),
                          .generator = "bench",
                          .keep_empty_plateau = true},
             file);
    }
    state.counters["texels_per_s"] =
        benchmark::Counter(double(bench_size()) * bench_size() * double(state.iterations()),
                           benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BakeEndToEnd)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same with the reference path (before the fast path), for the before / after table.
void BM_BakeEndToEndReference(benchmark::State& state) {
    BakeOptions options;
    options.threads = int(state.range(0));
    const std::string out = (work_dir() / "out_reference.ktx2").string();
    input_png();
    for (auto _ : state) {
        const Image input = io::read_image(input_png());
        const BakeResult r = bake_lean_map(input, BakeSource::Normal, options);
        io::write_ktx2(out, pack_lean_map(r.map, Storage::Unorm16, "bench"));
    }
}
BENCHMARK(BM_BakeEndToEndReference)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

// nvcompress (NVIDIA Texture Tools 2, Debian libnvtt-bin) on the same 16-bit PNG: decode, MIP
// chain, 8-bit RGBA DDS. Each iteration removes the output first and checks that a DDS of the
// expected size (128-byte header + 4 bytes per texel over the chain) appeared.
void BM_Nvcompress(benchmark::State& state) {
    if (std::system("command -v nvcompress >/dev/null 2>&1") != 0) {
        state.SkipWithError("nvcompress not installed (Debian libnvtt-bin)");
        return;
    }
    const bool mips = state.range(0) != 0;
    const std::string dds = (work_dir() / "out.dds").string();
    input_png();
    const std::string cmd = std::string("nvcompress -normal -rgb ") + (mips ? "" : "-nomips ") +
                            "'" + input_png() + "' '" + dds + "' >/dev/null 2>&1";
    std::uint64_t texels = 0;
    for (int w = bench_size(), h = bench_size();; w = std::max(1, w / 2), h = std::max(1, h / 2)) {
        texels += std::uint64_t(w) * std::uint64_t(h);
        if (!mips || (w == 1 && h == 1)) break;
    }
    const std::uint64_t expected = 128 + 4 * texels;
    for (auto _ : state) {
        fs::remove(dds);
        if (std::system(cmd.c_str()) != 0) {
            state.SkipWithError("nvcompress failed");
            return;
        }
        std::error_code ec;
        const std::uintmax_t size = fs::file_size(dds, ec);
        if (ec || size != expected) {
            state.SkipWithError(("nvcompress wrote " + std::to_string(ec ? 0 : size) +
                                 " bytes, expected " + std::to_string(expected))
                                    .c_str());
            return;
        }
    }
    state.counters["texels_per_s"] =
        benchmark::Counter(double(bench_size()) * bench_size() * double(state.iterations()),
                           benchmark::Counter::kIsRate);
}
// Arg 1: with its MIP chain (like our bake); 0: top level only.
BENCHMARK(BM_Nvcompress)
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

// Two commands as a user runs them, a fresh process each, alternating within each iteration so
// that drift of the machine falls on both; each iteration first removes `outputs` and checks that
// they appear. The benchmark's time is leanfade's; the counters give the mean time of each over
// the iterations (`ours_ms`, `theirs_ms`) and their ratio (leanfade_over_nvcompress).
void run_against(benchmark::State& state, const std::string& ours, const std::string& theirs,
                 const std::vector<std::string>& outputs, const std::string& theirs_ms) {
    if (std::system("command -v nvcompress >/dev/null 2>&1") != 0) {
        state.SkipWithError("nvcompress not installed (Debian libnvtt-bin)");
        return;
    }
    const auto timed = [](const std::string& command) {
        const auto start = std::chrono::steady_clock::now();
        const int status = std::system((command + " >/dev/null 2>&1").c_str());
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return status == 0 ? seconds : -1.0;
    };
    double ours_total = 0.0, theirs_total = 0.0;
    for (auto _ : state) {
        for (const std::string& output : outputs) fs::remove(output);
        const double mine = timed(ours);
        const double other = timed(theirs);
        bool written = true;
        for (const std::string& output : outputs) written = written && fs::exists(output);
        if (mine < 0.0 || other < 0.0 || !written) {
            state.SkipWithError(("failed: " + ours + " / " + theirs).c_str());
            return;
        }
        state.SetIterationTime(mine);
        ours_total += mine;
        theirs_total += other;
    }
    const double n = double(state.iterations());
    state.counters["leanfade_ms"] = 1e3 * ours_total / n;
    state.counters[theirs_ms] = 1e3 * theirs_total / n;
    state.counters["leanfade_over_nvcompress"] = ours_total / theirs_total;
}

// `leanfade bake` (its defaults: Zstandard levels) and `nvcompress -normal -rgb` (with its MIP
// chain) on the same PNG.
void BM_CliAgainstNvcompress(benchmark::State& state) {
    const std::string ktx2 = (work_dir() / "cli.ktx2").string();
    const std::string dds = (work_dir() / "cli.dds").string();
    run_against(state,
                std::string("'") + LEANFADE_TOOL + "' bake '" + input_png() + "' -o '" + ktx2 +
                    "' --threads " + std::to_string(state.range(0)),
                "nvcompress -normal -rgb '" + input_png() + "' '" + dds + "'", {ktx2, dds},
                "nvcompress_ms");
}
BENCHMARK(BM_CliAgainstNvcompress)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);

// Block compression of the engine textures (leanfade/io/detail/block_compression.hpp): the normal
// texture's full chain of a bench_size() map compressed on 2 threads. Arg 0: BC5 (libsquish),
// 1: ASTC 4x4 (libastcenc, medium effort), 2: Basis Universal UASTC (basis_universal.hpp: its
// WebAssembly encoder under Node.js, one process: the chain is one texture; Zstandard included).
// Counter: texels per second (all levels).
void BM_CompressNormalTexture(benchmark::State& state) {
    static const RoughnessTexturesRgba8 textures = [] {
        BakeOptions options;
        const LeanMap map = bake_lean_map(io::read_image(input_png()), BakeSource::Normal, options).map;
        RoughnessOptions roughness;
        roughness.base_roughness = 0.3f;
        return roughness_textures_rgba8(map, roughness, nullptr, {true, false});
    }();
    const io::BlockCompression compression = state.range(0) == 0   ? io::BlockCompression::Bc
                                             : state.range(0) == 1 ? io::BlockCompression::Astc
                                                                   : io::BlockCompression::Basis;
    std::uint64_t texels = 0;
    for (const Rgba8Image& level : textures.normal) texels += std::uint64_t(level.width) * level.height;
    for (auto _ : state) {
        if (compression == io::BlockCompression::Basis) {
            io::write_ktx2_uastc({{(work_dir() / "normal.uastc.ktx2").string(), &textures.normal, false}},
                                 "leanfade bench", LEANFADE_UASTC_ENCODER);
            continue;
        }
        const auto blocks = io::compress_levels(textures.normal, compression, io::EngineTexture::Normal, 2);
        benchmark::DoNotOptimize(blocks.data());
    }
    state.SetLabel(io::to_string(compression));
    state.counters["texels_per_s"] =
        benchmark::Counter(double(texels) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CompressNormalTexture)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_CompressNormalTexture)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// `leanfade bake N.png --roughness-out R.ktx2 --compress bc` (the bake's moments, roughness and
// normal MIPs, BC4 + BC5 of every level) against `nvcompress -normal -bc5` (MIP chain and BC5 of
// the normal map only) on the same PNG, each a fresh process, alternating within each iteration.
void BM_CompressBcAgainstNvcompress(benchmark::State& state) {
    const std::string ktx2 = (work_dir() / "bc.ktx2").string();
    const std::string dds = (work_dir() / "bc5.dds").string();
    run_against(state,
                std::string("'") + LEANFADE_TOOL + "' bake '" + input_png() + "' --roughness-out '" +
                    ktx2 + "' --compress bc --threads 2",
                "nvcompress -normal -bc5 '" + input_png() + "' '" + dds + "'", {ktx2, dds},
                "nvcompress_bc5_ms");
}
BENCHMARK(BM_CompressBcAgainstNvcompress)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(3);

// A command run as a user runs it (/bin/sh -c, no stdin, output discarded): wall seconds and the
// peak resident memory of the process (and of what it waited for), KiB; seconds < 0 on failure.
struct CommandRun {
    double seconds = -1.0;
    long max_rss_kib = 0;
};

CommandRun run_command(const std::string& command) {
    CommandRun run;
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", (command + " >/dev/null 2>&1 </dev/null").c_str(),
              static_cast<char*>(nullptr));
        _exit(127);
    }
    int status = 0;
    struct rusage usage {};
    if (pid < 0 || wait4(pid, &status, 0, &usage) != pid) return run;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return run;
    run.seconds = seconds;
    run.max_rss_kib = usage.ru_maxrss;
    return run;
}

std::string quoted(const std::string& s) {
    return "'" + s + "'";
}

// A glTF scene of one plane (two triangles, positions, normals, texture coordinates) whose one
// material has input_png() as its normal texture and a roughness factor of 0.3, written beside
// the PNG once per run.
const std::string& plane_gltf() {
    static const std::string path = [] {
        const float vertices[] = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1,   // positions
                                  0,  1, 0,  0, 1, 0,  0, 1, 0, 0,  1, 0,   // normals
                                  0,  0, 1,  0, 1, 1,  0, 1};               // uv
        const std::uint16_t indices[] = {0, 2, 1, 0, 3, 2};
        {
            std::FILE* bin = std::fopen((work_dir() / "plane.bin").c_str(), "wb");
            if (bin == nullptr) return std::string();
            std::fwrite(vertices, sizeof vertices, 1, bin);
            std::fwrite(indices, sizeof indices, 1, bin);
            std::fclose(bin);
        }
        const std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
"nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,
"TEXCOORD_0":2},"indices":3,"material":0}]}],"materials":[{"name":"ground","normalTexture":
{"index":0},"pbrMetallicRoughness":{"roughnessFactor":0.3}}],"textures":[{"source":0}],
"images":[{"uri":"normals16.png"}],"buffers":[{"uri":"plane.bin","byteLength":140}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,
"byteLength":48},{"buffer":0,"byteOffset":96,"byteLength":32},{"buffer":0,"byteOffset":128,
"byteLength":12}],"accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3",
"min":[-1,0,-1],"max":[1,0,1]},{"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},
{"bufferView":2,"componentType":5126,"count":4,"type":"VEC2"},{"bufferView":3,
"componentType":5123,"count":6,"type":"SCALAR"}]})";
        const std::string p = (work_dir() / "plane.gltf").string();
        std::FILE* file = std::fopen(p.c_str(), "wb");
        if (file == nullptr) return std::string();
        std::fwrite(json.data(), 1, json.size(), file);
        std::fclose(file);
        return p;
    }();
    return path;
}

// The engine outputs against Filament's `roughness-prefilter` (Debian libfilament-tools) on the
// same PNG, a fresh process each, alternating within each iteration: roughness MIPs alone
// (`bake PNG --roughness-out R.ktx2 --roughness 0.3`: the metallic-roughness and normal KTX2
// files, no LEAN map), `roughness-prefilter -r 0.3 PNG OUT.png` (a PNG per level), the LEAN bake
// alone and the LEAN bake with the export (`-o M.ktx2 --roughness-out R.ktx2`); then a glTF
// round trip of plane_gltf() (`bake plane.gltf --compress none -o out/plane.glb`): with an empty cache folder,
// again (the cached run replacing the first run's outputs) and again into a new folder.
// Counters: mean wall time and peak memory of each, and the ratios of docs/perf.md.
void BM_EngineOutputsAgainstFilament(benchmark::State& state) {
    if (std::system("command -v roughness-prefilter >/dev/null 2>&1") != 0) {
        state.SkipWithError("roughness-prefilter not installed (Debian libfilament-tools)");
        return;
    }
    const std::string png = quoted(input_png());
    const std::string tool = quoted(LEANFADE_TOOL);
    const std::string rough = quoted((work_dir() / "engine.ktx2").string());
    const std::string lean = quoted((work_dir() / "engine_lean.ktx2").string());
    const std::string filament_out = quoted((work_dir() / "filament.png").string());
    const std::string threads = " --threads " + std::to_string(state.range(0));
    const std::vector<std::pair<std::string, std::string>> commands = {
        {"roughness", tool + " bake " + png + " --roughness-out " + rough + " --roughness 0.3" + threads},
        {"filament", "roughness-prefilter -r 0.3 " + png + " " + filament_out},
        {"lean", tool + " bake " + png + " -o " + lean + threads},
        {"lean_export", tool + " bake " + png + " -o " + lean + " --roughness-out " + rough +
                            " --roughness 0.3" + threads},
    };
    input_png();
    if (plane_gltf().empty()) {
        state.SkipWithError("cannot write the glTF scene");
        return;
    }
    const fs::path cache = work_dir() / "gltf-cache";
    const fs::path out = work_dir() / "gltf-out";
    const fs::path out_new = work_dir() / "gltf-out-new";
    // RGBA8 KTX2 (--compress none): the copy and cache costs, not the Basis Universal encoder's
    // (docs/compression.md gives that one).
    const std::string gltf_bake = "env XDG_CACHE_HOME=" + quoted(cache.string()) + " " + tool +
                                  " bake " + quoted(plane_gltf()) + threads +
                                  " --compress none -o ";
    const std::vector<std::pair<std::string, std::string>> gltf_commands = {
        {"gltf_first", gltf_bake + quoted((out / "plane.glb").string())},
        {"gltf_cached", gltf_bake + quoted((out / "plane.glb").string())},
        {"gltf_cached_new_folder", gltf_bake + quoted((out_new / "plane.glb").string())},
    };
    std::map<std::string, double> seconds;
    std::map<std::string, long> memory;
    for (auto _ : state) {
        double ours = 0.0;
        std::error_code ec;
        for (const fs::path& folder : {cache, out, out_new}) fs::remove_all(folder, ec);
        fs::create_directories(out, ec);
        fs::create_directories(out_new, ec);
        std::vector<std::pair<std::string, std::string>> all = commands;
        all.insert(all.end(), gltf_commands.begin(), gltf_commands.end());
        for (const auto& [name, command] : all) {
            const CommandRun run = run_command(command);
            if (run.seconds < 0.0) {
                state.SkipWithError((name + " failed: " + command).c_str());
                return;
            }
            seconds[name] += run.seconds;
            memory[name] = std::max(memory[name], run.max_rss_kib);
            if (name == "roughness") ours = run.seconds;
        }
        state.SetIterationTime(ours);
    }
    const double n = double(state.iterations());
    for (const auto& [name, total] : seconds) {
        state.counters[name + "_ms"] = 1e3 * total / n;
        state.counters[name + "_peak_mib"] = double(memory[name]) / 1024.0;
    }
    state.counters["roughness_over_filament_time"] = seconds["roughness"] / seconds["filament"];
    state.counters["roughness_over_filament_memory"] =
        double(memory["roughness"]) / double(memory["filament"]);
    state.counters["lean_export_over_lean_time"] = seconds["lean_export"] / seconds["lean"];
    state.counters["gltf_cached_over_first_time"] = seconds["gltf_cached"] / seconds["gltf_first"];
    state.counters["gltf_cached_new_folder_over_first_time"] =
        seconds["gltf_cached_new_folder"] / seconds["gltf_first"];
}
BENCHMARK(BM_EngineOutputsAgainstFilament)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(3);

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::AddCustomContext("avx2_kernels", bake_simd_active() ? "yes" : "no");
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    std::error_code ec;
    fs::remove_all(work_dir(), ec);
    return 0;
}
