#version 450 core
// The fill-rate floor of `leanfade bench`: the scene's geometry and vertex stage (scene.vert)
// with a constant colour, so a frame costs only the vertex work, rasterisation, the depth test
// and the colour write. Every technique's frame time is reported against it.
layout(location = 0) out vec4 o_color;

void main() {
    o_color = vec4(0.5, 0.5, 0.5, 1.0);
}
