#pragma once
// Pieces shared by the reference bake (lean_map.cpp, slopes.cpp) and the fused fast path
// (bake_packed.cpp), so that both follow one definition of the filter taps, of sc and of the
// input checks (SPEC §2-3).
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "leanfade/core/image.hpp"
#include "leanfade/core/lean_map.hpp"

namespace leanfade::detail {

// Area-weighted reduction from `src` to `dst` samples: destination i covers the source interval
// [i r, (i + 1) r), r = src / dst, each source texel weighted by its overlap / r. For even sizes
// this is the 2-tap box (weights exactly 0.5); for odd sizes 3 taps. The weights of every source
// texel sum to 1/r, so the mean is preserved exactly and, the filter being linear, moments stay
// linear (LEAN §3).
struct Tap {
    int index;
    double weight;
};
std::vector<std::vector<Tap>> reduction_taps(int src, int dst);

// sc (SPEC §3, LEAN §5) from the top level's max |Bx|, |By| and max Mxx, Myy: the smallest float
// with |B| <= sc and M.xx, M.yy <= sc^2, with a floor that avoids a zero scale for a flat map.
float lean_scale(double max_b, double max_m);

// The summary fields taken from the 1x1 level: covariance M - B B^T and its anisotropy.
void summarize_coarsest(LeanMapSummary& summary, glm::vec2 mean, glm::vec3 second);

// Input checks and messages of slopes_from_normals (slopes.cpp), shared so that the fast path
// refuses the same inputs with the same words, naming the same (first, row-major) texel.
void check_normal_map_shape(const Image& normals, const std::string& source_name);
void check_normal_map_shape(int width, int height, int channels, const std::string& source_name);
[[noreturn]] void throw_non_finite_normal(const std::string& source_name, int x, int y);
[[noreturn]] void throw_negative_normal_z(const std::string& source_name, int x, int y, float z);
// A slope component steeper than kMaxSlope (or NaN) at texel (x, y); `cause` names the input.
[[noreturn]] void throw_steep_slope(const std::string& source_name, int x, int y, float slope,
                                    const char* cause);
inline constexpr const char* kSteepNormalCause = "normal components far outside [0, 1]";

}  // namespace leanfade::detail
