#pragma once
// Flow maps: a direction field over a surface that weights moving bump layers (LEAN §3.5, Fig.
// 11: ocean waves follow the currents). A flow field is a 2-channel Image of vectors (x along +u,
// y along +v, any length; only the direction matters, and a zero vector is "no flow"); the layer
// weights come from the shared shading header's lf_flow_weights, so the CPU and the shaders weight
// alike. GL-free.
#include <span>
#include <string>

#include <glm/vec2.hpp>

#include "leanfade/core/image.hpp"

namespace leanfade {

// A gyre: a clockwise rotation about the centre of the map (uv (0.5, 0.5)), like the North
// Atlantic's in LEAN Fig. 11. Unit-length vectors tangent to circles about the centre, shrinking
// linearly to 0 within `core_radius` of it (uv units, (0, 0.5]) where the layers then share
// equally. size x size, 2 channels (4 to 16384 texels). Throws leanfade::Error("size" or
// "core-radius", cause).
Image make_gyre_flow(int size, float core_radius = 0.1f);

// The flow field of a flow-map image as flow-map painting tools write it: red = x (+u), green =
// y (+v), 0.5 = zero, so f = 2 rg - 1 (values in [0, 1] as read by io::read_image). `file` names
// the image in errors: Throws leanfade::Error(file, cause) for fewer than 2 channels, an empty
// image or a value that is not finite.
Image flow_from_rg(const Image& rg, const std::string& file);
// The inverse: 2 channels in [0, 1] (a flow vector longer than 1 along an axis is clamped there).
Image flow_to_rg(const Image& flow);

// Per-texel layer weights of a flow field for layers with the given velocities (texture u, v per
// second; 1 to 4 layers): RGBA = t0..t3 from lf_flow_weights (each texel sums to 1; the channels
// of absent layers are 0). Throws leanfade::Error("flow" or "layer-velocities", cause) for a flow
// field without 2 channels, or for 0 or more than 4 velocities or a non-finite one.
Image flow_weights(const Image& flow, std::span<const glm::vec2> velocities);

}  // namespace leanfade
