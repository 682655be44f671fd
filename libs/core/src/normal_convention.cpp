// Does a normal map look like the other convention? (lean_map.hpp, NormalConventionCheck)
#include <algorithm>
#include <cmath>
#include <vector>

#include "leanfade/core/lean_map.hpp"

namespace leanfade {

namespace {

// Slopes of one decoded texel as read in `convention` (z raised to kMinNormalZ, as the bake).
glm::vec2 texel_slope(float r, float g, float b, float green_sign) {
    const float nx = 2.0f * r - 1.0f, ny = green_sign * (2.0f * g - 1.0f);
    const float nz = std::max(2.0f * b - 1.0f, kMinNormalZ);
    return {nx / nz, ny / nz};
}

}  // namespace

NormalConventionCheck check_normal_convention(const Image& normals, NormalConvention convention,
                                              int max_samples_per_side) {
    NormalConventionCheck check;
    if (normals.channels < 3 || normals.width < 3 || normals.height < 3) return check;
    const int w = normals.width, h = normals.height;
    // Every `step`-th row and column: a bounded cost for large maps.
    const int step = std::max(1, std::max(w, h) / std::max(1, max_samples_per_side));
    const float green_sign = convention == NormalConvention::DirectX ? -1.0f : 1.0f;
    auto slope = [&](int x, int y) {
        x = (x + w) % w;
        y = (y + h) % h;
        const float r = normals.at(x, y, 0), g = normals.at(x, y, 1), b = normals.at(x, y, 2);
        return texel_slope(r, g, b, green_sign);
    };
    double as_read = 0.0, flipped = 0.0;
    for (int y = 0; y < h; y += step) {
        for (int x = 0; x < w; x += step) {
            // Central differences; +v is toward row y - 1 (docs/math.md §2).
            const double dbx_dv = 0.5 * double(slope(x, y - 1).x - slope(x, y + 1).x);
            const double dby_du = 0.5 * double(slope(x + 1, y).y - slope(x - 1, y).y);
            // B = -grad(height) has no curl: dBx/dv = dBy/du. Read with green flipped, By
            // changes sign and the curl becomes dBx/dv + dBy/du.
            as_read += (dbx_dv - dby_du) * (dbx_dv - dby_du);
            flipped += (dbx_dv + dby_du) * (dbx_dv + dby_du);
            ++check.samples;
        }
    }
    check.curl_as_read = check.samples > 0 ? as_read / double(check.samples) : 0.0;
    check.curl_flipped = check.samples > 0 ? flipped / double(check.samples) : 0.0;
    return check;
}

bool NormalConventionCheck::looks_flipped() const {
    // Only where the flipped reading is clearly closer to a height field (4 times less curl) and
    // the map varies along both axes enough to tell (a map of ridges along one axis does not).
    return samples >= 64 && curl_flipped < 0.25 * curl_as_read && curl_as_read > 1e-6;
}

}  // namespace leanfade
