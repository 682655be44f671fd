#version 450 core
// Per-frame LEAN map generation (LEAN paper §5, "per-frame generation"; docs/math.md §2-3): one
// invocation per texel of the top level reads a height map (Sobel / 8, docs/math.md §2) or a normal
// map (B = n.xy / n.z), and writes both packed slices of the LEAN texture with a given sc:
//   slice 0, lean1 = (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5),  n = normalize(B, 1)
//   slice 1, lean2 = (0.5 B / sc + 0.5, Mxx / sc^2, Myy / sc^2),  M = (Bx^2, By^2, Bx By) + 1/s
// exactly as the CPU baker does for its top level (libs/core lean_map.cpp). The other MIP levels
// come from glGenerateMipmap, which averages the packed values: correct, because the packing is
// affine per channel (docs/math.md §3).
//
// Defines (exactly one of each pair, set by leanfade::gl::LeanGenerator):
//   SOURCE_HEIGHT | SOURCE_NORMAL     what u_source holds (height in .r; normal as 0.5 n + 0.5)
//   SLICE_FORMAT <qualifier>          rgba8 | rgba16 | rgba16f | rgba32f, the texture's storage
//
// Texel coordinates are GL's: row 0 is v = 0 (the bottom row of the image file), so +v is +y here.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D u_source;  // same size as the top level; texelFetch only
layout(binding = 0, SLICE_FORMAT) uniform writeonly image2DArray u_lean;

uniform float u_strength;     // height per texel spacing (docs/math.md §2)
uniform float u_scale;        // sc
uniform float u_inv_s;        // 1/s baked into Mxx, Myy (LEAN eq. 6), or 0
uniform float u_green_sign;   // -1 for DirectX-convention normal maps, else 1
uniform bool u_wrap_repeat;   // Sobel taps past the edge: repeat, or clamp to the edge
uniform float u_min_normal_z; // normal maps: z raised to this (kMinNormalZ)

int wrap(int i, int n) {
    if (u_wrap_repeat) return (i + n) % n;  // i is in [-1, n]
    return clamp(i, 0, n - 1);
}

#if defined(SOURCE_HEIGHT)
float height_at(ivec2 p, ivec2 size) {
    return texelFetch(u_source, ivec2(wrap(p.x, size.x), wrap(p.y, size.y)), 0).r;
}
#endif

// Projected slope B of texel p (docs/math.md §2).
vec2 slope(ivec2 p, ivec2 size) {
#if defined(SOURCE_HEIGHT)
    float l_down = height_at(p + ivec2(-1, -1), size);
    float l_mid = height_at(p + ivec2(-1, 0), size);
    float l_up = height_at(p + ivec2(-1, 1), size);
    float c_down = height_at(p + ivec2(0, -1), size);
    float c_up = height_at(p + ivec2(0, 1), size);
    float r_down = height_at(p + ivec2(1, -1), size);
    float r_mid = height_at(p + ivec2(1, 0), size);
    float r_up = height_at(p + ivec2(1, 1), size);
    float dfdu = ((r_up + 2.0 * r_mid + r_down) - (l_up + 2.0 * l_mid + l_down)) / 8.0;
    float dfdv = ((l_up + 2.0 * c_up + r_up) - (l_down + 2.0 * c_down + r_down)) / 8.0;
    return vec2(-u_strength * dfdu, -u_strength * dfdv);
#elif defined(SOURCE_NORMAL)
    vec3 encoded = texelFetch(u_source, p, 0).rgb;
    vec3 n = 2.0 * encoded - vec3(1.0);
    n.y *= u_green_sign;
    n.z = max(n.z, u_min_normal_z);
    return n.xy / n.z;
#else
#error "define SOURCE_HEIGHT or SOURCE_NORMAL"
#endif
}

void main() {
    ivec2 size = imageSize(u_lean).xy;
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y) return;
    vec2 b = slope(p, size);
    float inv_len = 1.0 / sqrt(b.x * b.x + b.y * b.y + 1.0);
    vec3 n = vec3(b * inv_len, inv_len);
    vec3 m = vec3(b.x * b.x + u_inv_s, b.y * b.y + u_inv_s, b.x * b.y);
    float sc2 = u_scale * u_scale;
    imageStore(u_lean, ivec3(p, 0), vec4(0.5 * n + vec3(0.5), 0.5 * m.z / sc2 + 0.5));
    imageStore(u_lean, ivec3(p, 1), vec4(0.5 * b / u_scale + vec2(0.5), m.x / sc2, m.y / sc2));
}
