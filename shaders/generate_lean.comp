#version 450 core
// Per-frame LEAN map generation (LEAN paper §5, "per-frame generation"; docs/math.md §2-3): one
// invocation per texel of the top level reads a height map (Sobel / 8, docs/math.md §2) or a normal
// map (B = n.xy / n.z), and writes both packed slices of the LEAN texture with a given sc:
//   slice 0, lean1 = (0.5 n + 0.5, 0.5 Mxy / sc^2 + 0.5),  n = normalize(B, 1)
//   slice 1, lean2 = (0.5 B / sc + 0.5, Mxx / sc^2, Myy / sc^2),  M = (Bx^2, By^2, Bx By) + 1/s
// in the offset encoding of UNORM storages, or (n, Mxy / sc^2), (B / sc, Mxx / sc^2, Myy / sc^2)
// in the signed encoding of float storages (leanfade::LeanEncoding),
// exactly as the CPU baker does for its top level (libs/core lean_map.cpp). The other MIP levels
// come from glGenerateMipmap, which averages the packed values: correct, because the packing is
// affine per channel (docs/math.md §3).
//
// Defines (exactly one of each, set by leanfade::gl::LeanGenerator):
//   SOURCE_HEIGHT | SOURCE_NORMAL | SOURCE_LAYERS
//       what the slopes come from: u_source's height in .r, or its normal as 0.5 n + 0.5; or the
//       bump layers of a material mixed by the "height" method at one instant (docs/math.md §6,
//       moving layers): sum t_i k_i B_i(uv tiling_i + offset_i) from the layers' LEAN maps at
//       level 0, read bilinearly as texel values at texel centres, weights constant or from the
//       weight map; the same as mix_slopes_at of libs/core layers.hpp
//   SLICE_FORMAT <qualifier>          rgba8 | rgba16 | rgba16f | rgba32f, the texture's storage
//
// Texel coordinates are GL's: row 0 is v = 0 (the bottom row of the image file), so +v is +y here.
layout(local_size_x = 8, local_size_y = 8) in;

#if defined(SOURCE_LAYERS)
#include "lean_shading.glsl"
#include "bindings.glsl"
// The material's layers as the renderer binds them for drawing (renderer.cpp, bind_layers).
layout(binding = LF_BINDING_LAYER_MAPS) uniform sampler2DArray u_layer_maps[4];
layout(binding = LF_BINDING_LAYER_WEIGHTS) uniform sampler2D u_layer_weights;
layout(std140, binding = LF_BINDING_LAYER_BLOCK) uniform LfLayerBlock {
    LfLayerUniforms u_layers;
};
#else
layout(binding = 0) uniform sampler2D u_source;  // same size as the top level; texelFetch only
#endif
layout(binding = 0, SLICE_FORMAT) uniform writeonly image2DArray u_lean;

uniform float u_strength;     // height per texel spacing (docs/math.md §2)
uniform float u_scale;        // sc
uniform float u_inv_s;        // 1/s baked into Mxx, Myy (LEAN eq. 6), or 0
uniform float u_green_sign;   // -1 for DirectX-convention normal maps, else 1
uniform bool u_wrap_repeat;   // Sobel taps past the edge: repeat, or clamp to the edge
uniform float u_min_normal_z; // normal maps: z raised to this (kMinNormalZ)
uniform float u_lean_offset;  // 1: the offset encoding (UNORM storages); 0: signed (float ones)

int wrap(int i, int n) {
    if (u_wrap_repeat) return (i + n) % n;  // i is in [-1, n]
    return clamp(i, 0, n - 1);
}

#if defined(SOURCE_HEIGHT)
float height_at(ivec2 p, ivec2 size) {
    return texelFetch(u_source, ivec2(wrap(p.x, size.x), wrap(p.y, size.y)), 0).r;
}
#endif

#if defined(SOURCE_LAYERS)
int wrap_index(int i, int n) {
    int r = i % n;
    return r < 0 ? r + n : r;
}

// Bilinear weights and the four texels around uv of a repeating texture of `size` texels (texel
// values at texel centres): corners (x0, y0), (x1, y0), (x0, y1), (x1, y1).
void bilinear_taps(vec2 uv, ivec2 size, out ivec2 taps[4], out vec4 weights) {
    vec2 x = uv * vec2(size) - vec2(0.5);
    vec2 x0 = floor(x);
    vec2 f = x - x0;
    ivec2 i0 = ivec2(x0);
    for (int corner = 0; corner < 4; ++corner) {
        ivec2 d = ivec2(corner & 1, corner >> 1);
        taps[corner] = ivec2(wrap_index(i0.x + d.x, size.x), wrap_index(i0.y + d.y, size.y));
    }
    weights = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
}

// Layer i's mean slope B (strength 1) at its texture coordinates `uv`, from level 0.
vec2 layer_slope(int i, vec2 uv) {
    ivec2 taps[4];
    vec4 w;
    bilinear_taps(uv, textureSize(u_layer_maps[i], 0).xy, taps, w);
    vec2 lean2_xy = vec2(0.0);
    for (int c = 0; c < 4; ++c)
        lean2_xy += w[c] * texelFetch(u_layer_maps[i], ivec3(taps[c], 1), 0).xy;
    // docs/math.md §3-4: B = ((1 + o) s - o) sc with the layer's encoding offset o.
    float o = u_layers.lean_offsets[i];
    return ((1.0 + o) * lean2_xy - vec2(o)) * u_layers.scales[i];
}

vec4 layer_weights(vec2 uv) {
    if (u_layers.weight_map == 0) return u_layers.weights;
    ivec2 taps[4];
    vec4 w;
    bilinear_taps(uv, textureSize(u_layer_weights, 0), taps, w);
    vec4 t = vec4(0.0);
    for (int c = 0; c < 4; ++c) t += w[c] * texelFetch(u_layer_weights, taps[c], 0);
    return t;
}
#endif

// Projected slope B of texel p (docs/math.md §2).
vec2 slope(ivec2 p, ivec2 size) {
#if defined(SOURCE_LAYERS)
    vec2 uv = (vec2(p) + vec2(0.5)) / vec2(size);
    vec4 t = layer_weights(uv);
    vec2 b = vec2(0.0);
    for (int i = 0; i < 4; ++i) {
        if (i >= u_layers.count) break;
        vec4 offsets = u_layers.offsets[i / 2];
        vec2 offset = (i % 2 == 0) ? offsets.xy : offsets.zw;
        b += t[i] * u_layers.strengths[i] * layer_slope(i, uv * u_layers.tilings[i] + offset);
    }
    return b;
#elif defined(SOURCE_HEIGHT)
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
#error "define SOURCE_HEIGHT, SOURCE_NORMAL or SOURCE_LAYERS"
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
    // s = g v + o for n, B, Mxy: (0.5, 0.5) in the offset encoding, (1, 0) in the signed one.
    float g = u_lean_offset > 0.0 ? 0.5 : 1.0;
    float o = u_lean_offset > 0.0 ? 0.5 : 0.0;
    imageStore(u_lean, ivec3(p, 0), vec4(g * n + vec3(o), g * m.z / sc2 + o));
    imageStore(u_lean, ivec3(p, 1), vec4(g * b / u_scale + vec2(o), m.x / sc2, m.y / sc2));
}
