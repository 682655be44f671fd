#pragma once
// The bake's entry points below bake(input, settings, sink) (leanfade/core/lean_map.hpp): the
// same fused bake with its arguments spelled out, for the tests, benchmarks and fuzzers that
// compare its paths with each other and with the float reference (bake_lean_map). Not a promise:
// engines call bake().
#include <string>
#include <variant>
#include <vector>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade {

PackedBakeResult bake_packed(const Image& input, BakeSource source, const BakeOptions& options,
                             Storage storage, const std::string& generator,
                             const std::string& source_name = "",
                             const MomentRunSink& moments = {});
// `--bits auto` around any bake of a width x height map: `bake(storage, probe)` first (storage:
// Unorm16 for auto), its float moments given to `probe` (a MomentRunSink the bake must call,
// with its own, if any: both_sinks); with `automatic`, a second `bake(chosen, {})` when the
// StorageProbe's choice is another storage, and the probe's scores in the result.
template <typename Bake>
PackedBakeResult bake_with_auto_storage(Storage storage, bool automatic, int width, int height,
                                        Bake&& bake) {
    if (!automatic) return bake(storage, MomentRunSink{});
    StorageProbe probe(width, height);
    PackedBakeResult result = bake(storage, probe.sink());
    const StorageProbe::Scores scores = probe.scores(result.packed.scale);
    const Storage chosen =
        scores.unorm16 >= scores.float16 ? Storage::Unorm16 : Storage::Float16;
    if (chosen != storage) result = bake(chosen, MomentRunSink{});
    result.probe_unorm16_psnr = scores.unorm16;
    result.probe_float16_psnr = scores.float16;
    return result;
}
// A sink that gives each run to `first` and to `second` (either may be empty).
MomentRunSink both_sinks(const MomentRunSink& first, const MomentRunSink& second);


// One image baked as `leanfade bake` bakes it into a KTX2 file, in memory: the policy's bake
// (bake_with_auto_storage), then, when the plateau rule found nothing flat, the empty plateau
// layer removed (two-lobe LEAN shades a map without it as LEAN, as it would this one).
// Integer samples (an 8- or 16-bit file's) bake as bake_packed_to's UnormImage overload does.
// write_ktx2 of the result writes the bytes `leanfade bake` writes for the same input and
// settings; io::bake_image_to_ktx2 writes them without the copy in memory.
PackedBakeResult bake_packed_image(const std::variant<Image, UnormImage>& input, BakeSource source,
                                   const BakeOptions& options, StoragePolicy storage,
                                   const std::string& generator,
                                   const std::string& source_name = "",
                                   const MomentRunSink& moments = {});
// The same into `result`, reusing its buffers: baking another map of the same size and storage
// allocates no output memory.
void bake_packed_into(PackedBakeResult& result, const Image& input, BakeSource source,
                      const BakeOptions& options, Storage storage, const std::string& generator,
                      const std::string& source_name = "", const MomentRunSink& moments = {});

// The bake written straight into memory the caller provides (e.g. a mapped output file:
// `leanfade bake` writes the KTX2 file this way, with no copy of the map in between). The
// returned result's packed map holds the metadata and the level sizes; its slices are empty.
// `moments`, when set, sees the float moments of every level as they are made. Targets with a
// null lean1 at every level pack nothing: the bake then only feeds `moments` (and needs
// plateau_epsilon = 0).
PackedBakeResult bake_packed_to(const PackedOutputOpener& open_output, const Image& input,
                                BakeSource source, const BakeOptions& options, Storage storage,
                                const std::string& generator, const std::string& source_name = "",
                                const MomentRunSink& moments = {});
// The same from integer samples (an 8- or 16-bit file's, half the memory of the float image):
// exactly the bytes and summary of bake_packed_to(open_output, input.to_float(), ...) with
// options.source_max_code = input.effective_max_code(...) (the plateau layer depends on it).
PackedBakeResult bake_packed_to(const PackedOutputOpener& open_output, const UnormImage& input,
                                BakeSource source, const BakeOptions& options, Storage storage,
                                const std::string& generator, const std::string& source_name = "",
                                const MomentRunSink& moments = {});
// Only the float moments: the fused bake of `input` (Image or UnormImage) with nothing packed,
// every run given to `moments` (plateau_epsilon is ignored). Validates and throws as
// bake_lean_map; returns the summary and the source as bake_packed_to does.
template <typename Input>
PackedBakeResult bake_moments(const Input& input, BakeSource source, BakeOptions options,
                              const std::string& source_name, const MomentRunSink& moments) {
    options.plateau_epsilon = 0.0f;
    return bake_packed_to(
        [](const PackedLeanMap& layout) {
            return std::vector<PackedLevelTarget>(layout.levels.size());
        },
        input, source, options, Storage::Float32, "", source_name, moments);
}


}  // namespace leanfade
