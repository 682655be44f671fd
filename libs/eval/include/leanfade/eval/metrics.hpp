#pragma once
// Image metrics of `leanfade eval`: object masks, specular energy, relative RMSE, SSIM and
// frame-to-frame change. GL-free; images are leanfade::Image (row 0 at the top), RGB or RGBA
// (only the first three channels are measured).
//
// Every metric is taken over the object's pixels only (a Mask), so that the background, the
// framing and the image size do not dilute it.
#include <cstdint>
#include <vector>

#include "leanfade/core/image.hpp"

namespace leanfade::eval {

// Which pixels of an image belong to the object: inside[y * width + x] != 0.
struct Mask {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> inside;

    Mask() = default;
    Mask(int w, int h, bool value = false);
    bool at(int x, int y) const { return inside[std::size_t(y) * std::size_t(width) + x] != 0; }
    int count() const;  // number of object pixels
};

// Pixels of `marked` whose first three channels are all >= 0: the renderer's output where the
// background was cleared to a negative marker (shading values are never negative).
Mask covered_pixels(const Image& marked);
// The interior of a mask: pixels whose 3 x 3 neighbourhood lies inside it (image borders count
// as outside). A pixel of a single-sample render whose neighbours' centres are covered is fully
// covered up to sub-pixel features, so the silhouette's partly covered pixels are left out.
Mask erode(const Mask& mask);
// Pixels inside both. Throws leanfade::Error("mask", ...) when the sizes differ.
Mask intersect(const Mask& a, const Mask& b);

// Replaces every pixel outside `mask` with `color` (e.g. the marker background with the display
// background). Throws leanfade::Error("mask", ...) when the sizes differ.
Image fill_outside(const Image& image, const Mask& mask, float r, float g, float b);

// Mean over the mask's pixels and the three colour channels. 0 for an empty mask.
double masked_mean(const Image& image, const Mask& mask);

// Root mean square difference over the mask's pixels and channels, divided by the reference's
// masked_mean (the relative RMSE; 0 for identical images). Returns 0 for an empty mask and
// +infinity when the reference's mean is 0 but the images differ. Throws leanfade::Error("image",
// ...) when the sizes differ.
double relative_rmse(const Image& image, const Image& reference, const Mask& mask);

// Mean absolute difference over the mask's pixels and channels: the change of one pixel from one
// frame to the next when a and b are consecutive frames. Throws when the sizes differ.
double mean_absolute_difference(const Image& a, const Image& b, const Mask& mask);

// Structural similarity (Wang, Bovik, Sheikh & Simoncelli 2004, eq. 13): the mean SSIM index of
// the mask's pixels and the three channels, with their 11 x 11 Gaussian window (sigma 1.5),
// K1 = 0.01, K2 = 0.03 and the dynamic range L = 1 (pass display values in [0, 1], e.g.
// encode_srgb). The window is restricted to the mask (its weights renormalised over the object's
// pixels), so the background and the silhouette do not enter. Identical images give exactly 1.
// Returns 1 for an empty mask. Throws when the sizes differ.
double ssim(const Image& a, const Image& b, const Mask& mask);

// Linear RGB(A) -> display values: clamped to [0, 1] and encoded with the sRGB transfer function
// (IEC 61966-2-1); alpha is copied.
Image encode_srgb(const Image& linear);
float encode_srgb(float linear);

}  // namespace leanfade::eval
