#version 450 core
// Two-lobe LEAN's plateau layer of a LEAN map generated on the GPU (docs/math.md §10; the CPU's
// plateau_texels of libs/core plateau.cpp): one invocation per texel of the top level reads the
// slopes B = (2 lean2.xy - 1) sc of the texel, of its four neighbours and of the four texels
// u_radius away along both axes (the map repeats; plateau.hpp's PlateauRule) from the generated
// LEAN texture, and writes
//   (1, B.x, B.y, |B|^2)  where every component differs from each of those by less than epsilon,
//   0                     elsewhere,
// to the plateau texture's level 0 (RGBA16F, decoded values as MapKind::Plateau holds them). Its
// other levels come from glGenerateMipmap: the values are linear in the texels, like the moments.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2DArray u_lean;  // the generated LEAN map; texelFetch, level 0
layout(binding = 0, rgba16f) uniform writeonly image2D u_plateau;

uniform float u_scale;    // sc of the LEAN map
uniform float u_epsilon;  // the plateau rule's epsilon, slope units
uniform ivec2 u_radius;   // the plateau rule's radius, texels (>= 1 per axis)

vec2 slope_at(ivec2 p, ivec2 size) {
    ivec2 q = (p + size) % size;  // p is in [-radius, size - 1 + radius], radius < size
    return (2.0 * texelFetch(u_lean, ivec3(q, 1), 0).xy - vec2(1.0)) * u_scale;
}

bool near(vec2 a, vec2 b) {
    return abs(a.x - b.x) < u_epsilon && abs(a.y - b.y) < u_epsilon;
}

void main() {
    ivec2 size = imageSize(u_plateau);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y) return;
    vec2 b = slope_at(p, size);
    bool plateau = near(slope_at(p + ivec2(-1, 0), size), b) &&
                   near(slope_at(p + ivec2(1, 0), size), b) &&
                   near(slope_at(p + ivec2(0, -1), size), b) &&
                   near(slope_at(p + ivec2(0, 1), size), b) &&
                   near(slope_at(p + ivec2(-u_radius.x, 0), size), b) &&
                   near(slope_at(p + ivec2(u_radius.x, 0), size), b) &&
                   near(slope_at(p + ivec2(0, -u_radius.y), size), b) &&
                   near(slope_at(p + ivec2(0, u_radius.y), size), b);
    imageStore(u_plateau, p, plateau ? vec4(1.0, b, dot(b, b)) : vec4(0.0));
}
