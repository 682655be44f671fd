// --bits auto by measurement (StorageProbe, leanfade/core/lean_map.hpp; docs/ktx2.md,
// "Choosing storage and sc").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <vector>

#include <glm/gtc/packing.hpp>

#include "lean_map_internal.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/core/shading.hpp"

namespace leanfade {
namespace {

// Half float rounding of one value, as the bake stores it (store_float_channel).
float as_half(float value) { return glm::unpackHalf1x16(glm::packHalf1x16(value)); }

// The LEAN lobe at slope h (tangent space) of the moments (B, M), with 1/s added at shading.
float lobe_at(glm::vec2 h, glm::vec2 mean, glm::vec3 second, float inv_s) {
    const glm::vec3 sigma = shading::lf_covariance(mean, second, inv_s);
    return shading::lf_lean_lobe(glm::normalize(glm::vec3(h, 1.0f)), mean, sigma);
}

}  // namespace

StorageProbe::StorageProbe(int width, int height, int threads) : threads_(threads) {
    int w = std::max(width, 1), h = std::max(height, 1);
    const int levels = mip_level_count(w, h);
    levels_.resize(std::size_t(levels));
    for (Level& level : levels_) {
        level.width = w;
        level.height = h;
        level.step_x = (w + kStorageProbeSide - 1) / kStorageProbeSide;
        level.step_y = (h + kStorageProbeSide - 1) / kStorageProbeSide;
        level.columns = (w + level.step_x - 1) / level.step_x;
        const int rows = (h + level.step_y - 1) / level.step_y;
        level.texels.assign(std::size_t(level.columns) * std::size_t(rows), Texel{});
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
}

void StorageProbe::add(const MomentRun& run) {
    if (run.level < 0 || std::size_t(run.level) >= levels_.size()) return;
    Level& level = levels_[std::size_t(run.level)];
    if (run.level == 0) {
        double max_b = 0.0, max_m = 0.0;
        for (int i = 0; i < run.count; ++i) {
            max_b = std::max({max_b, double(std::abs(run.bx[i])), double(std::abs(run.by[i]))});
            max_m = std::max({max_m, double(run.mxx[i]), double(run.myy[i])});
        }
        const std::lock_guard<std::mutex> lock(maxima_mutex_);
        max_b_ = std::max(max_b_, max_b);
        max_m_ = std::max(max_m_, max_m);
    }
    if (run.y % level.step_y != 0) return;
    const std::size_t row = std::size_t(run.y / level.step_y) * std::size_t(level.columns);
    // The first sampled x at or after run.x.
    int x = ((run.x + level.step_x - 1) / level.step_x) * level.step_x;
    for (; x < run.x + run.count; x += level.step_x) {
        const int i = x - run.x;
        level.texels[row + std::size_t(x / level.step_x)] = {
            glm::vec2(run.bx[i], run.by[i]), glm::vec3(run.mxx[i], run.myy[i], run.mxy[i]), true};
    }
}

MomentRunSink StorageProbe::sink() {
    return [this](const MomentRun& run) { add(run); };
}

void StorageProbe::add(const LeanMap& map) {
    for (std::size_t l = 0; l < map.levels.size() && l < levels_.size(); ++l) {
        const MomentLevel& level = map.levels[l];
        std::vector<float> bx(std::size_t(level.width)), by(bx.size()), mxx(bx.size()),
            myy(bx.size()), mxy(bx.size());
        for (int y = 0; y < level.height; ++y) {
            for (int x = 0; x < level.width; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(level.width) + std::size_t(x);
                bx[std::size_t(x)] = level.mean[i].x;
                by[std::size_t(x)] = level.mean[i].y;
                mxx[std::size_t(x)] = level.second[i].x;
                myy[std::size_t(x)] = level.second[i].y;
                mxy[std::size_t(x)] = level.second[i].z;
            }
            add(MomentRun{int(l), y, 0, level.width, bx.data(), by.data(), mxx.data(), myy.data(),
                          mxy.data()});
        }
    }
}

double StorageProbe::psnr(Storage storage, float unorm_scale) const {
    return psnr(std::vector<Storage>{storage}, unorm_scale).front();
}

std::vector<double> StorageProbe::psnr(const std::vector<Storage>& storages,
                                       float unorm_scale) const {
    // The moments as `storage` stores and decodes them.
    const float signed_scale = signed_encoding_scale(Storage::Float16, max_b_, max_m_);
    const auto stored = [&](Storage storage, const Texel& t, glm::vec2& mean, glm::vec3& second) {
        if (storage == Storage::Unorm16 || storage == Storage::Unorm8) {
            const detail::UnormPacking k =
                detail::unorm_packing(storage, unorm_scale, unorm_scale * unorm_scale);
            std::uint16_t q1[4], q2[4];
            detail::unorm_texel(k, glm::vec3(0.0f, 0.0f, 1.0f), t.mean, t.second, q1, q2);
            const glm::vec4 lean1{0.5f, 0.5f, 1.0f, float(q1[3]) / k.max};
            const glm::vec4 lean2{float(q2[0]) / k.max, float(q2[1]) / k.max,
                                  float(q2[2]) / k.max, float(q2[3]) / k.max};
            const shading::LfMoments m = shading::lf_unpack(lean1, lean2, unorm_scale, 1.0f);
            mean = m.mean;
            second = m.second;
        } else if (storage == Storage::Float16) {
            const float sc = signed_scale, sc2 = signed_scale * signed_scale;
            mean = glm::vec2(as_half(t.mean.x / sc), as_half(t.mean.y / sc)) * sc;
            second = glm::vec3(as_half(t.second.x / sc2), as_half(t.second.y / sc2),
                               as_half(t.second.z / sc2)) *
                     sc2;
        } else {
            mean = t.mean;
            second = t.second;
        }
    };
    // The half vectors' slopes around a texel's mean: a disc of radius kStorageProbeRadius, on a
    // grid of 41 x 41 points.
    std::vector<glm::vec2> offsets;
    const float step = kStorageProbeRadius / 20.0f;
    for (int i = -20; i <= 20; ++i)
        for (int j = -20; j <= 20; ++j)
            if (i * i + j * j <= 400) offsets.emplace_back(float(i) * step, float(j) * step);
    const float inv_s = 1.0f / kStorageProbeShininess;
    std::vector<const Texel*> texels;
    for (const Level& level : levels_)
        for (const Texel& t : level.texels)
            if (t.sampled) texels.push_back(&t);
    // Each texel's squared errors on their own, summed in order afterwards: the same result for
    // any thread count.
    const std::size_t n = storages.size();
    std::vector<double> per_texel(texels.size() * n, 0.0);
    parallel_for_rows(int(texels.size()), threads_, [&](int first, int end) {
        std::vector<glm::vec2> means(n);
        std::vector<glm::vec3> seconds(n);
        for (int i = first; i < end; ++i) {
            const Texel& t = *texels[std::size_t(i)];
            for (std::size_t c = 0; c < n; ++c) stored(storages[c], t, means[c], seconds[c]);
            for (const glm::vec2 offset : offsets) {
                const glm::vec2 h = t.mean + offset;
                // Ks = 1 and a white light of radiance 1: the specular radiance (before n.l and
                // Fresnel), clamped as a displayed render is.
                const double want =
                    std::clamp(double(lobe_at(h, t.mean, t.second, inv_s)), 0.0, 1.0);
                for (std::size_t c = 0; c < n; ++c) {
                    double got = double(lobe_at(h, means[c], seconds[c], inv_s));
                    got = std::isnan(got) ? 1.0 : std::clamp(got, 0.0, 1.0);
                    per_texel[std::size_t(i) * n + c] += (got - want) * (got - want);
                }
            }
        }
    });
    std::vector<double> squared(n, 0.0);
    for (std::size_t i = 0; i < texels.size(); ++i)
        for (std::size_t c = 0; c < n; ++c) squared[c] += per_texel[i * n + c];
    const std::uint64_t values = std::uint64_t(texels.size()) * offsets.size();
    std::vector<double> result;
    for (const double sum : squared)
        result.push_back(values == 0 || sum == 0.0 ? std::numeric_limits<double>::infinity()
                                                   : 10.0 * std::log10(double(values) / sum));
    return result;
}

StorageProbe::Scores StorageProbe::scores(float unorm_scale) const {
    const std::vector<double> both = psnr({Storage::Unorm16, Storage::Float16}, unorm_scale);
    return {both[0], both[1]};
}

Storage StorageProbe::choose(float unorm_scale) const {
    const Scores s = scores(unorm_scale);
    return s.unorm16 >= s.float16 ? Storage::Unorm16 : Storage::Float16;
}

}  // namespace leanfade
