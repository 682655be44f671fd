#version 450 core
// Box pixel filter of the reference (docs/math.md §7, LEAN Fig. 14): each output pixel is the mean
// of the k x k samples of the supersampled tile that cover it. Linear radiance in, linear radiance
// out.
layout(binding = 0) uniform sampler2D u_samples;  // the supersampled tile, k times the size
uniform int u_factor;                             // k
uniform ivec2 u_tile_origin;                      // the tile's first output pixel (window coords)

layout(location = 0) out vec4 o_color;

void main() {
    ivec2 base = (ivec2(gl_FragCoord.xy) - u_tile_origin) * u_factor;
    vec4 sum = vec4(0.0);
    for (int y = 0; y < u_factor; ++y)
        for (int x = 0; x < u_factor; ++x) sum += texelFetch(u_samples, base + ivec2(x, y), 0);
    o_color = sum / float(u_factor * u_factor);
}
