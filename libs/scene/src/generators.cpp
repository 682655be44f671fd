// Sphere, torus, plane and terrain (the teapot lives in teapot.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/random.hpp"
#include "leanfade/scene/detail/generators.hpp"
#include "mesh_internal.hpp"

namespace leanfade::scene {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxSegments = 4096;  // keeps vertex counts far below 2^32

// cos and sin of 2 pi * f with f = 0 and f = 1 giving bit-identical results, so that duplicated
// seam vertices land exactly on the originals.
glm::dvec2 unit_circle(double f) {
    if (f <= 0.0 || f >= 1.0) {
        return {1.0, 0.0};
    }
    return {std::cos(kTwoPi * f), std::sin(kTwoPi * f)};
}

void require(bool ok, const char* object, const std::string& cause) {
    if (!ok) {
        throw Error(object, cause);
    }
}

// 2D gradient (Perlin) noise on a 256-periodic lattice, roughly in [-1, 1], zero at lattice points.
class GradientNoise {
public:
    explicit GradientNoise(SplitMix64& rng) {
        for (int k = 0; k < 256; ++k) {
            perm_[std::size_t(k)] = std::uint8_t(k);
        }
        for (int k = 255; k > 0; --k) {  // Fisher-Yates
            const auto r = std::size_t(rng.next() % std::uint64_t(k + 1));
            std::swap(perm_[std::size_t(k)], perm_[r]);
        }
    }

    double operator()(double x, double y) const {
        const double fx = std::floor(x);
        const double fy = std::floor(y);
        const int ix = int(fx) & 255;
        const int iy = int(fy) & 255;
        const double dx = x - fx;
        const double dy = y - fy;
        const double n00 = corner(ix, iy, dx, dy);
        const double n10 = corner(ix + 1, iy, dx - 1.0, dy);
        const double n01 = corner(ix, iy + 1, dx, dy - 1.0);
        const double n11 = corner(ix + 1, iy + 1, dx - 1.0, dy - 1.0);
        const double wx = fade(dx);
        const double wy = fade(dy);
        const double bottom = n00 + wx * (n10 - n00);
        const double top = n01 + wx * (n11 - n01);
        return 1.4 * (bottom + wy * (top - bottom));
    }

private:
    static double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

    double corner(int ix, int iy, double dx, double dy) const {
        // Eight gradient directions: the axes and the diagonals, all unit length.
        static constexpr double kD = 0.70710678118654752440;
        static constexpr std::array<std::array<double, 2>, 8> kGrad = {{{1.0, 0.0},
                                                                        {-1.0, 0.0},
                                                                        {0.0, 1.0},
                                                                        {0.0, -1.0},
                                                                        {kD, kD},
                                                                        {-kD, kD},
                                                                        {kD, -kD},
                                                                        {-kD, -kD}}};
        const std::uint8_t h = perm_[std::size_t((perm_[std::size_t(ix & 255)] + iy) & 255)];
        const auto& g = kGrad[h & 7u];
        return g[0] * dx + g[1] * dy;
    }

    std::array<std::uint8_t, 256> perm_{};
};

// A cells x cells grid over x, z in [-size / 2, size / 2] with y = heights[j * (cells + 1) + i]
// at x = -size / 2 + i * step, z = size / 2 - j * step; u along +x, v along -z.
Mesh height_grid(const char* name, int cells, double size, const std::vector<double>& heights) {
    const int row = cells + 1;
    const double step = size / cells;
    auto h = [&](int i, int j) {
        return heights[std::size_t(std::clamp(j, 0, cells)) * std::size_t(row) +
                       std::size_t(std::clamp(i, 0, cells))];
    };
    Mesh mesh;
    mesh.name = name;
    mesh.vertices.reserve(std::size_t(row) * std::size_t(row));
    mesh.indices.reserve(std::size_t(cells) * std::size_t(cells) * 6);
    detail::append_grid(mesh, cells, cells, {}, [&](double s, double t) {
        const int i = int(std::lround(s * cells));
        const int j = int(std::lround(t * cells));
        // Central differences inside, one-sided on the border. z = size / 2 - j * step.
        const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, cells);
        const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, cells);
        const double dhdx = (h(i1, j) - h(i0, j)) / (double(i1 - i0) * step);
        const double dhdz = -(h(i, j1) - h(i, j0)) / (double(j1 - j0) * step);
        Vertex v{};
        v.position = glm::vec3(-0.5 * size + i * step, h(i, j), 0.5 * size - j * step);
        v.normal = glm::vec3(glm::normalize(glm::dvec3(-dhdx, 1.0, -dhdz)));
        v.uv = glm::vec2(float(i * step / kTileLength), float(j * step / kTileLength));
        return v;
    });
    return mesh;
}

}  // namespace

Mesh make_sphere(int segments, int stacks) {
    require(segments >= 3 && segments <= kMaxSegments, "sphere",
            "segments must be in [3, 4096], got " + std::to_string(segments));
    require(stacks >= 2 && stacks <= kMaxSegments, "sphere",
            "stacks must be in [2, 4096], got " + std::to_string(stacks));
    Mesh mesh;
    mesh.name = "sphere";
    detail::CollapsedEdges poles;
    poles.v0 = true;
    poles.v1 = true;
    detail::append_grid(mesh, segments, stacks, poles, [](double s, double t) {
        // t: 0 at the south pole (y = -1), 1 at the north pole; s: longitude / 2 pi, 0 at +z.
        const glm::dvec2 lon = unit_circle(s);
        const double polar = std::numbers::pi * (1.0 - t);  // angle from +y
        double y = std::cos(polar);
        double ring = std::sin(polar);
        if (t <= 0.0 || t >= 1.0) {
            y = t <= 0.0 ? -1.0 : 1.0;
            ring = 0.0;
        }
        const glm::dvec3 p(ring * lon.y, y, ring * lon.x);
        Vertex v{};
        v.position = glm::vec3(p);
        v.normal = glm::vec3(glm::normalize(p));
        v.uv = glm::vec2(float(16.0 * s), float(8.0 * t));
        return v;
    });
    detail::remove_unused_vertices(mesh);
    detail::finish(mesh);
    return mesh;
}

Mesh make_torus(int major_segments, int minor_segments) {
    require(major_segments >= 3 && major_segments <= kMaxSegments, "torus",
            "major segments must be in [3, 4096], got " + std::to_string(major_segments));
    require(minor_segments >= 3 && minor_segments <= kMaxSegments, "torus",
            "minor segments must be in [3, 4096], got " + std::to_string(minor_segments));
    constexpr double kMajor = 0.75;
    constexpr double kMinor = 0.25;
    Mesh mesh;
    mesh.name = "torus";
    detail::append_grid(mesh, major_segments, minor_segments, {}, [&](double s, double t) {
        const glm::dvec2 a = unit_circle(s);  // around y, 0 at +z, toward +x
        const glm::dvec2 b = unit_circle(t);  // around the tube, 0 outside, then up
        const glm::dvec3 n(b.x * a.y, b.y, b.x * a.x);
        const glm::dvec3 centre(kMajor * a.y, 0.0, kMajor * a.x);
        Vertex v{};
        v.position = glm::vec3(centre + kMinor * n);
        v.normal = glm::vec3(n);
        v.uv = glm::vec2(float(12.0 * s), float(4.0 * t));
        return v;
    });
    detail::finish(mesh);
    return mesh;
}

Mesh make_plane(float size, int segments) {
    require(std::isfinite(size) && size > 0.0f, "plane",
            "size must be a positive number, got " + std::to_string(size));
    require(segments >= 1 && segments <= kMaxSegments, "plane",
            "segments must be in [1, 4096], got " + std::to_string(segments));
    const std::vector<double> flat(std::size_t(segments + 1) * std::size_t(segments + 1), 0.0);
    Mesh mesh = height_grid("plane", segments, double(size), flat);
    detail::finish(mesh);
    return mesh;
}

Mesh make_terrain(std::uint32_t seed) {
    constexpr int kCells = 247;
    constexpr double kSize = 20.0;
    constexpr int kOctaves = 5;
    constexpr double kBaseFrequency = 3.0 / kSize;  // 3 lattice cells across at octave 0
    constexpr double kAmplitude = 2.0;              // world units at octave 0
    SplitMix64 rng(0x5EED7E22A1ull ^ (std::uint64_t(seed) << 17) ^ std::uint64_t(seed));
    const GradientNoise noise(rng);
    std::array<glm::dvec2, kOctaves> offsets{};
    for (auto& o : offsets) {
        o = glm::dvec2(rng.uniform() * 256.0, rng.uniform() * 256.0);
    }
    const int row = kCells + 1;
    const double step = kSize / kCells;
    std::vector<double> heights(std::size_t(row) * std::size_t(row));
    double lo = 1e300;
    double hi = -1e300;
    for (int j = 0; j < row; ++j) {
        for (int i = 0; i < row; ++i) {
            const double x = -0.5 * kSize + i * step;
            const double z = 0.5 * kSize - j * step;
            double h = 0.0;
            double frequency = kBaseFrequency;
            double amplitude = kAmplitude;
            for (int o = 0; o < kOctaves; ++o) {
                h += amplitude * noise(x * frequency + offsets[std::size_t(o)].x,
                                       z * frequency + offsets[std::size_t(o)].y);
                frequency *= 2.0;
                amplitude *= 0.5;
            }
            heights[std::size_t(j) * std::size_t(row) + std::size_t(i)] = h;
            lo = std::min(lo, h);
            hi = std::max(hi, h);
        }
    }
    const double mid = 0.5 * (lo + hi);
    for (double& h : heights) {
        h -= mid;
    }
    Mesh mesh = height_grid("terrain", kCells, kSize, heights);
    detail::finish(mesh);
    return mesh;
}

}  // namespace leanfade::scene
