#include "leanfade/core/detail/flow_map.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "leanfade/core/error.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade {

Image make_gyre_flow(int size, float core_radius) {
    if (size < 4 || size > 16384)
        throw Error::setting("size", "must be in [4, 16384] texels, got " + std::to_string(size));
    if (!(core_radius > 0.0f && core_radius <= 0.5f))
        throw Error::setting("core-radius", "must be in (0, 0.5] (uv units)");
    Image flow(size, size, 2);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            // Texel centre relative to the map's centre, uv units (v up, row 0 at the top).
            const float du = (float(x) + 0.5f) / float(size) - 0.5f;
            const float dv = 0.5f - (float(y) + 0.5f) / float(size);
            const float r = std::sqrt(du * du + dv * dv);
            if (r <= 0.0f) continue;
            // Clockwise seen with u right and v up: the tangent (dv, -du) / r.
            const float speed = std::min(1.0f, r / core_radius);
            flow.at(x, y, 0) = speed * dv / r;
            flow.at(x, y, 1) = -speed * du / r;
        }
    return flow;
}

Image flow_from_rg(const Image& rg, const std::string& file) {
    if (rg.empty()) throw Error(file, "the flow map is empty");
    if (rg.channels < 2)
        throw Error(file, "a flow map needs red and green channels (x and y), the image has " +
                              std::to_string(rg.channels));
    Image flow(rg.width, rg.height, 2);
    for (int y = 0; y < rg.height; ++y)
        for (int x = 0; x < rg.width; ++x)
            for (int c = 0; c < 2; ++c) {
                const float value = rg.at(x, y, c);
                if (!std::isfinite(value))
                    throw Error(file, "texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                          ") is not finite");
                flow.at(x, y, c) = 2.0f * value - 1.0f;
            }
    return flow;
}

Image flow_to_rg(const Image& flow) {
    if (flow.channels != 2) throw Error::setting("flow", "a flow field has 2 channels");
    Image rg(flow.width, flow.height, 2);
    for (std::size_t i = 0; i < flow.pixels.size(); ++i)
        rg.pixels[i] = std::clamp(0.5f * flow.pixels[i] + 0.5f, 0.0f, 1.0f);
    return rg;
}

Image flow_weights(const Image& flow, std::span<const glm::vec2> velocities) {
    if (flow.channels != 2 || flow.empty())
        throw Error::setting("flow", "a flow field has 2 channels and at least one texel");
    if (velocities.empty() || velocities.size() > 4)
        throw Error::setting("layer-velocities",
                             "1 to 4 layers, got " + std::to_string(velocities.size()));
    glm::vec2 v[4] = {glm::vec2(0.0f), glm::vec2(0.0f), glm::vec2(0.0f), glm::vec2(0.0f)};
    for (std::size_t i = 0; i < velocities.size(); ++i) {
        if (!std::isfinite(velocities[i].x) || !std::isfinite(velocities[i].y))
            throw Error::setting("layer-velocities",
                                 "layer " + std::to_string(i) + "'s is not finite");
        v[i] = velocities[i];
    }
    const int count = int(velocities.size());
    Image weights(flow.width, flow.height, 4);
    for (int y = 0; y < flow.height; ++y)
        for (int x = 0; x < flow.width; ++x) {
            const glm::vec2 f(flow.at(x, y, 0), flow.at(x, y, 1));
            if (!std::isfinite(f.x) || !std::isfinite(f.y))
                throw Error::setting("flow", "texel (" + std::to_string(x) + ", " +
                                                 std::to_string(y) + ") is not finite");
            const glm::vec4 t = shading::lf_flow_weights(f, v[0], v[1], v[2], v[3], count);
            for (int c = 0; c < 4; ++c) weights.at(x, y, c) = t[c];
        }
    return weights;
}

}  // namespace leanfade
