// Fuzz target: image decoding (io::read_image_from_memory: PNG, OpenEXR, PFM, and JPEG, TGA, DDS,
// TIFF, PSD, BMP, HDR, WebP through OpenImageIO, each with its header checks) and the whole bake
// of what decodes, differentially: the reference path (bake_lean_map, pack_lean_map) and the fast
// path `leanfade bake` runs (bake_packed, AVX2 or portable) must throw the same message or give
// the same bytes (lean_map.hpp promises both); then unpack and summarize. A PNG also goes the
// way `leanfade bake` reads and bakes it: kept as integer samples (read_image_compact, equal to
// the floats) and baked into caller memory (bake_packed_to), which must give the same bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "fuzz_common.hpp"
#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/image_io.hpp"

using namespace leanfade;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    io::ReadOptions read_options;
    read_options.max_dimension = fuzz::kMaxDimension;
    Image image;
    try {
        image = io::read_image_from_memory(fuzz::to_bytes(data, size), "fuzz-input", read_options);
    } catch (const Error&) {
        return 0;
    }

    // The bake settings vary with the input (deterministically), so every path is reached.
    const std::uint8_t selector = data[size - 1];
    BakeOptions options;
    options.threads = 1;
    options.wrap = (selector & 1) != 0 ? Wrap::Clamp : Wrap::Repeat;
    options.convention = (selector & 2) != 0 ? NormalConvention::DirectX : NormalConvention::OpenGL;
    options.bake_roughness_shininess = (selector & 4) != 0 ? 64.0f : 0.0f;
    options.strength = (selector & 8) != 0 ? 40.0f : 1.0f;
    const BakeSource source = (selector & 0x30) == 0x10   ? BakeSource::Height
                              : (selector & 0x30) == 0x20 ? BakeSource::Normal
                                                          : BakeSource::Auto;
    static constexpr Storage kStorages[4] = {Storage::Unorm8, Storage::Unorm16, Storage::Float16,
                                             Storage::Float32};
    const Storage storage = kStorages[(selector >> 6) & 3];
    PackedLeanMap reference;
    std::string reference_error;
    try {
        const BakeResult result = bake_lean_map(image, source, options, "fuzz-input");
        reference = pack_lean_map(result.map, storage, "fuzz");
    } catch (const Error& e) {
        reference_error = e.what();
    }
    set_bake_simd(size % 2 == 0);
    PackedBakeResult fast;
    std::string fast_error;
    try {
        fast = bake_packed(image, source, options, storage, "fuzz", "fuzz-input");
    } catch (const Error& e) {
        fast_error = e.what();
    }
    if (fast_error != reference_error) __builtin_trap();
    if (!reference_error.empty()) return 0;

    if (fast.packed.scale != reference.scale ||
        fast.packed.levels.size() != reference.levels.size()) {
        __builtin_trap();
    }
    for (std::size_t i = 0; i < reference.levels.size(); ++i) {
        if (fast.packed.levels[i].lean1 != reference.levels[i].lean1 ||
            fast.packed.levels[i].lean2 != reference.levels[i].lean2) {
            __builtin_trap();
        }
    }
    const auto compact =
        io::read_image_compact_from_memory(fuzz::to_bytes(data, size), "fuzz-input", read_options);
    if (const UnormImage* samples = std::get_if<UnormImage>(&compact)) {
        if (samples->to_float().pixels != image.pixels) __builtin_trap();
        // lean1, lean2 and the plateau layer of each level (the packed bakes add that layer by
        // default: bake_packed_to wants a target for it, or it throws std::invalid_argument).
        std::vector<std::vector<std::uint8_t>> layers;
        bool plateau = false;
        const PackedBakeResult to = bake_packed_to(
            [&](const PackedLeanMap& layout) {
                std::vector<PackedLevelTarget> targets;
                plateau = layout.has_plateau();
                layers.resize(3 * layout.levels.size());
                for (std::size_t l = 0; l < layout.levels.size(); ++l) {
                    const std::size_t bytes = std::size_t(layout.levels[l].width) *
                                              std::size_t(layout.levels[l].height) *
                                              std::size_t(bytes_per_texel(storage));
                    layers[3 * l].assign(bytes, 0xAB);
                    layers[3 * l + 1].assign(bytes, 0xCD);
                    if (plateau) layers[3 * l + 2].assign(bytes, 0xEF);
                    targets.push_back({layers[3 * l].data(), layers[3 * l + 1].data(),
                                       plateau ? layers[3 * l + 2].data() : nullptr});
                }
                return targets;
            },
            *samples, source, options, storage, "fuzz", "fuzz-input");
        if (to.packed.scale != reference.scale || layers.size() != 3 * reference.levels.size() ||
            plateau != fast.packed.has_plateau())
            __builtin_trap();
        // The plateau rule takes the samples' own precision as the quantisation step: the float
        // bake of the same values gives the same layer when told it (BakeOptions::
        // source_max_code, as `leanfade bake` does), not without.
        PackedBakeResult coded;
        if (plateau) {
            BakeOptions with_code = options;
            with_code.source_max_code = samples->effective_max_code(
                resolve_bake_source(source, *samples) == BakeSource::Normal ? 3 : 1);
            coded = bake_packed(image, source, with_code, storage, "fuzz", "fuzz-input");
        }
        for (std::size_t i = 0; i < reference.levels.size(); ++i) {
            if (layers[3 * i] != reference.levels[i].lean1 ||
                layers[3 * i + 1] != reference.levels[i].lean2 ||
                (plateau && layers[3 * i + 2] != coded.packed.levels[i].plateau)) {
                __builtin_trap();
            }
        }
    }
    const LeanMapSummary summary = summarize(unpack_lean_map(reference));
    if (summary.levels != mip_level_count(image.width, image.height)) __builtin_trap();
    return 0;
}
