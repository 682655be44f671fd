#pragma once
// Combined image samplers split into a texture and a sampler, in a SPIR-V module's words: what
// WebGPU (WGSL has no combined samplers) and a translator to WGSL need. GLSL's
// `uniform sampler2D u_map` (binding b) becomes a texture `u_map` at binding b and a sampler
// `u_map_sampler` at binding b + sampler_binding_offset, same descriptor set; each load of the
// combined sampler becomes a load of both and OpSampledImage, so the code that samples is
// unchanged.
//
// Written here because no library of Debian 12 does it: SPIRV-Tools gained the pass
// (--split-combined-image-sampler) in 2025, after Debian 12's 2023.1.
#include <cstdint>
#include <string>
#include <vector>

namespace leanfade::gl {

struct SplitSamplers {
    std::vector<std::uint32_t> words;  // the module, split (empty when `refused` is set)
    std::string refused;  // why the module cannot be split ("" when it was): an array of combined
                          // samplers (WebGPU has no arrays of textures), or a combined sampler
                          // used by anything but a load
};

// `words`: a SPIR-V module in host order, as SPIRV-Tools' optimiser leaves it (functions inlined:
// combined samplers are loaded from their variables, never passed). The result is not validated
// here: the caller runs the validator.
SplitSamplers split_combined_image_samplers(const std::vector<std::uint32_t>& words,
                                            std::uint32_t sampler_binding_offset);

}  // namespace leanfade::gl
