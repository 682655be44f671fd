// Two-lobe LEAN's central window (leanfade/core/detail/plateau.hpp, docs/math.md §10): on a map whose
// slopes are peakier than a Gaussian and have nothing flat, the fitted window puts the peak in
// the spike and the far highlight comes back; the window's layer filters linearly; the plateaus
// alone are the layer of earlier versions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/shading.hpp"
#include "test_helpers.hpp"

namespace leanfade {
namespace {

// Slopes of a rough surface made of patches of two roughnesses (8 x 8 texels each, a
// checkerboard of sd 0.05 and 0.3 per axis): a Gaussian scale mixture, whose centre is about
// 1.6 times as dense as the Gaussian of its covariance and of which no texel is on a plateau
// (neighbours differ by far more than epsilon).
Image patchy_slopes(int size) {
    std::mt19937 rng(7);
    std::normal_distribution<float> unit(0.0f, 1.0f);
    Image slopes(size, size, 2);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float sd = ((x / 8 + y / 8) % 2 == 0) ? 0.05f : 0.3f;
            slopes.at(x, y, 0) = sd * unit(rng);
            slopes.at(x, y, 1) = sd * unit(rng);
        }
    return slopes;
}

struct FarHighlight {
    double truth = 0, lean = 0, two_lobe = 0;
};

// The density of the whole map's slopes at its mean slope, at Blinn-Phong's 1/s per axis: the
// truth (every texel's own lobe, averaged), LEAN (one Gaussian of the map's moments) and
// two-lobe LEAN with the layer's coarsest texel `plateau` (f, f Bs, f |Bs|^2).
FarHighlight far_highlight(const Image& slopes, glm::vec4 plateau, float s) {
    using namespace shading;
    const float inv_s = 1.0f / s;
    const test::SlopeMoments moments = test::slope_moments(slopes);
    const double n = double(slopes.texel_count());
    const vec3 h(float(moments.mean.x), float(moments.mean.y), 1.0f);
    FarHighlight out;
    for (std::size_t i = 0; i < slopes.texel_count(); ++i)
        out.truth += lf_lean_lobe(h, vec2(slopes.pixels[2 * i], slopes.pixels[2 * i + 1]),
                                  vec3(inv_s, inv_s, 0.0f)) / n;
    LfMoments m;
    m.normal = vec3(0.0f, 0.0f, 1.0f);
    m.mean = vec2(moments.mean);
    m.second = vec3(moments.second);
    m.plateau = plateau;
    LfParams p = lf_default_params();
    p.inv_s_shading = inv_s;
    p.shininess = s;
    const LfLobe lean = lf_lobe_setup(LF_TECHNIQUE_LEAN, m, p);
    out.lean = lf_lean_lobe(h, lean.mean, lean.sigma);
    const LfLobe two = lf_lobe_setup(LF_TECHNIQUE_TWO_LOBE, m, p);
    out.two_lobe = lf_two_lobe_density(two, h);
    return out;
}

TEST(SpikeWindow, FitPutsThePeakOfAMapWithoutFlatGroundInTheSpike) {
    const Image slopes = patchy_slopes(256);
    const PlateauRule plateaus = plateau_rule_for(slopes);
    // Nothing is flat: the plateaus alone are LEAN.
    const std::vector<Image> none = plateau_mips(slopes, plateaus);
    ASSERT_EQ(none.back().pixels[0], 0.0f);

    const SpikeWindowFit fit = fit_spike_window(slopes, plateaus);
    ASSERT_NE(fit.window.shape, SpikeWindowShape::None);
    EXPECT_EQ(fit.plateau_fraction, 0.0f);
    EXPECT_LT(fit.error, fit.plateaus_error);
    PlateauRule rule = plateaus;
    rule.window = fit.window;
    const std::vector<Image> chain = plateau_mips(slopes, rule);
    const Image& coarsest = chain.back();
    ASSERT_EQ(coarsest.texel_count(), 1u);
    const glm::vec4 layer(coarsest.pixels[0], coarsest.pixels[1], coarsest.pixels[2],
                          coarsest.pixels[3]);
    EXPECT_GT(layer.x, 0.05f);
    EXPECT_LT(layer.x, 0.95f);
    for (float s : {128.0f, 1024.0f, 13777.0f}) {
        const FarHighlight far = far_highlight(slopes, layer, s);
        // A Gaussian scale mixture of sd 0.05 and 0.3: LEAN's one Gaussian of the mixture's
        // covariance keeps about 0.6 of the centre; the spike brings it within 15 %.
        EXPECT_LT(far.lean / far.truth, 0.8) << "s " << s;
        EXPECT_NEAR(far.two_lobe / far.truth, 1.0, 0.15) << "s " << s;
    }
}

TEST(SpikeWindow, WindowLayerIsTheMeanOfItsTexelsAtEveryLevel) {
    // The layer holds w (1, B, |B|^2) per texel; a MIP level is the mean of its footprint's
    // texels exactly (the moments' filter), whichever window.
    const Image slopes = patchy_slopes(64);
    PlateauRule rule = plateau_rule_for(slopes);
    for (SpikeWindowShape shape : {SpikeWindowShape::Disc, SpikeWindowShape::Biweight}) {
        rule.window = SpikeWindow{shape, glm::vec2(0.01f, -0.02f), 0.2f, true};
        const std::vector<Image> chain = plateau_mips(slopes, rule);
        const Image& top = chain.front();
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                const float bx = slopes.at(x, y, 0), by = slopes.at(x, y, 1);
                const float w = top.at(x, y, 0);
                ASSERT_EQ(w, spike_window_weight(rule.window, bx, by));
                ASSERT_FLOAT_EQ(top.at(x, y, 1), w * bx);
                ASSERT_FLOAT_EQ(top.at(x, y, 3), w * (bx * bx + by * by));
            }
        for (std::size_t l = 1; l < chain.size(); ++l) {
            const int step = 1 << l;
            for (int y = 0; y < chain[l].height; ++y)
                for (int x = 0; x < chain[l].width; ++x)
                    for (int c = 0; c < 4; ++c) {
                        double sum = 0.0;
                        for (int j = 0; j < step; ++j)
                            for (int i = 0; i < step; ++i)
                                sum += top.at(x * step + i, y * step + j, c);
                        const double mean = sum / double(step * step);
                        ASSERT_NEAR(chain[l].at(x, y, c), mean, 1e-5 * (1.0 + std::abs(mean)))
                            << to_string(shape) << " level " << l;
                    }
        }
    }
}

TEST(SpikeWindow, PlateausFitBakesTheLayerOfThePlateausAlone) {
    Image height(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            height.at(x, y, 0) = (x / 16 + y / 16) % 2 == 0
                                     ? 0.0f
                                     : 0.5f * std::sin(0.7f * float(x)) * std::cos(0.3f * float(y));
    BakeOptions options;
    options.spike_fit = SpikeFit::Plateaus;
    const PackedBakeResult baked = bake_packed(height, BakeSource::Height, options, Storage::Float32, "t");
    EXPECT_EQ(baked.summary.spike_window.shape, SpikeWindowShape::None);
    const Image slopes = packed_top_slopes(baked.packed);
    const std::vector<Image> want = plateau_mips(slopes, plateau_rule_for(slopes));
    const std::vector<Image> got = unpack_plateau_layer(baked.packed);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t l = 0; l < got.size(); ++l)
        for (std::size_t i = 0; i < got[l].pixels.size(); ++i)
            ASSERT_NEAR(got[l].pixels[i], want[l].pixels[i], 1e-6f) << "level " << l;
}

TEST(SpikeWindow, NamesAndBadNames) {
    EXPECT_EQ(parse_spike_fit("auto"), SpikeFit::Auto);
    EXPECT_EQ(parse_spike_fit("plateaus"), SpikeFit::Plateaus);
    EXPECT_STREQ(to_string(SpikeFit::Auto), "auto");
    EXPECT_THROW(parse_spike_fit("window"), Error);
    EXPECT_EQ(spike_window_weight(SpikeWindow{}, 0.0f, 0.0f), 0.0f);
}

}  // namespace
}  // namespace leanfade
