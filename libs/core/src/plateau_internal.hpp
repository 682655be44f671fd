#pragma once
// The plateau layer written by the packed bakes (bake_packed.cpp) straight into their output, the
// bytes of add_plateau_layer (leanfade/core/detail/plateau.hpp) without its float images of the finest
// level.
#include <cstdint>
#include <vector>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"

namespace leanfade::detail {

// Fills targets[l].plateau of every level of `layout` (its storage, sc and level sizes) from the
// finest level's packed lean2 texels at `lean2_top`. epsilon: slope units, finite and > 0;
// source_step: the source's quantisation step (source_slope_step), the rule also takes the
// storage's (storage_slope_step).
// With SpikeFit::Auto the rule's central window is fitted first (fit_spike_window).
// Returns the rule it applied, the spike's share of the map (the coarsest f) and the fit.
struct PlateauOutcome {
    PlateauRule rule;
    float fraction = 0.0f;
    SpikeWindowFit fit;
};
PlateauOutcome pack_plateau_layer_to(const PackedLeanMap& layout, const std::uint8_t* lean2_top,
                           const std::vector<PackedLevelTarget>& targets, float epsilon,
                           float source_step, SpikeFit fit, int threads);

}  // namespace leanfade::detail
