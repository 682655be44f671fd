#include "leanfade/core/image.hpp"

#include <stdexcept>

#include "leanfade/core/memory.hpp"

namespace leanfade {

Image::Image(int w, int h, int c, float fill) : width(w), height(h), channels(c) {
    if (w < 0 || h < 0 || c < 0 || c > 4) throw std::invalid_argument("Image: bad dimensions");
    assign_large(pixels, std::size_t(w) * std::size_t(h) * std::size_t(c), fill);
}

}  // namespace leanfade
