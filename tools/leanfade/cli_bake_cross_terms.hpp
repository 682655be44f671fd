#pragma once
// `leanfade bake --cross-terms A,B -o PAIR.ktx2`: the cross-term texture of two aligned bump
// layers ("mixing textures", docs/math.md §6), every MIP level, as a KTX2 file (layout in
// docs/ktx2.md, "Cross-term textures").
#include <string>

#include "leanfade/core/lean_map.hpp"

namespace leanfade::cli {

struct CrossTermBakeArgs {
    std::string sources;  // "A,B": built-in sets, height/normal images or .ktx2 LEAN maps
    std::string output;   // .ktx2
    BakeSource from = BakeSource::Auto;
    bool directx = false;
    float strength = 1.0f;  // height per texel spacing of height maps
    int size = 256;         // built-in sets
    unsigned seed = 1;
    int max_size = 16384;
};

// Returns the exit code; throws leanfade::Error naming the file or flag.
int run_bake_cross_terms(const CrossTermBakeArgs& args);

}  // namespace leanfade::cli
