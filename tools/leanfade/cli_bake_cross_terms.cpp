// The cross-term texture of two bump layers (cli_bake_cross_terms.hpp).
#include "cli_bake_cross_terms.hpp"

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "cli_flags.hpp"
#include "leanfade/scene/scene_source.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/layers.hpp"
#include "leanfade/core/detail/text.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/output_plan.hpp"
#include "leanfade/version.hpp"

namespace leanfade::cli {
namespace {

std::vector<std::uint8_t> float_bytes(const Image& image) {
    std::vector<std::uint8_t> bytes(image.pixels.size() * sizeof(float));
    std::memcpy(bytes.data(), image.pixels.data(), bytes.size());
    return bytes;
}

}  // namespace

int run_bake_cross_terms(const CrossTermBakeArgs& args) {
    const std::vector<std::string> sources = split(args.sources, ',');
    if (sources.size() != 2)
        throw Error("--cross-terms", "give the two layers of one pair: A,B");
    if (args.output.size() < 5 || args.output.substr(args.output.size() - 5) != ".ktx2")
        throw Error("-o", "the cross-term texture is written as .ktx2");
    io::OutputPlan plan;
    for (const std::string& s : sources)
        if (std::filesystem::exists(s)) plan.add_input(s);
    plan.add_output(args.output, "-o");
    plan.check();

    scene::BumpMapSource flags;
    flags.from = args.from;
    flags.directx = args.directx;
    flags.texture_size = args.size;
    flags.seed = args.seed;
    flags.max_size = args.max_size;
    ShadingSettings settings;
    settings.bump_strength = args.strength;
    scene::SceneSourceReport report;
    const Image bi = scene::top_slopes(scene::load_layer_map(sources[0], flags, settings, &report));
    const Image bj = scene::top_slopes(scene::load_layer_map(sources[1], flags, settings, &report));
    print_scene_report({}, report);
    if (bi.width != bj.width || bi.height != bj.height)
        throw Error("--cross-terms", "the two layers must be aligned: '" + sources[0] + "' is " +
                                         std::to_string(bi.width) + "x" +
                                         std::to_string(bi.height) + ", '" + sources[1] +
                                         "' is " + std::to_string(bj.width) + "x" +
                                         std::to_string(bj.height));
    const std::vector<Image> products = build_cross_terms(bi, bj);
    // Slice 1: the pair's mean slopes (Bi.x, Bi.y, Bj.x, Bj.y), MIP-mapped alike.
    Image means(bi.width, bi.height, 4);
    for (std::size_t t = 0; t < bi.texel_count(); ++t) {
        means.pixels[4 * t] = bi.pixels[2 * t];
        means.pixels[4 * t + 1] = bi.pixels[2 * t + 1];
        means.pixels[4 * t + 2] = bj.pixels[2 * t];
        means.pixels[4 * t + 3] = bj.pixels[2 * t + 1];
    }
    const std::vector<Image> mean_chain = build_mip_chain(means);
    PackedLeanMap packed;
    packed.storage = Storage::Float32;
    packed.scale = 1.0f;
    packed.generator = std::string(LEANFADE_GENERATOR) + " cross terms";
    for (std::size_t level = 0; level < products.size(); ++level) {
        PackedLevel l;
        l.width = products[level].width;
        l.height = products[level].height;
        l.lean1 = float_bytes(products[level]);
        l.lean2 = float_bytes(mean_chain[level]);
        packed.levels.push_back(std::move(l));
    }
    io::write_cross_term_ktx2(args.output, packed);
    std::printf("%s: cross terms of %s and %s, %dx%d, %zu levels\n", args.output.c_str(),
                sources[0].c_str(), sources[1].c_str(), bi.width, bi.height,
                packed.levels.size());
    return 0;
}

}  // namespace leanfade::cli
