#version 450 core
// Vertex stage of every technique (bump, lean, fade, reference). Builds the tangent frame per
// vertex (docs/math.md §1: T along +u, Bt = w cross(N, T) along +v, N), and passes to the fragment
// stage the tangent-space light direction, the unnormalised tangent-space view vector Vt (its
// length is the distance to the eye in world units) and the eye depth used by fog.
//
// World units: the renderer's model matrix scales the object to a bounding radius of 1.

#include "bindings.glsl"

layout(location = 0) in vec3 a_position;  // object space
layout(location = 1) in vec3 a_normal;    // object space, unit
layout(location = 2) in vec2 a_uv;        // mesh texture coordinates, set 0
layout(location = 3) in vec4 a_tangent;   // object space xyz (unit, along +u of the normal
                                          // texture's set), w = handedness
layout(location = 4) in vec2 a_uv1;       // mesh texture coordinates, set 1 (glTF TEXCOORD_1)
// How far the normal field is linear around the vertex (scene::Vertex::linear_normal_change; 0:
// as far as measured), read by geometric antialiasing (docs/math.md §11).
layout(location = 5) in float a_linear_normal_change;

// Everything the vertex stage reads per draw, as one std140 block (mirrored in C++ by
// LfObjectUniforms, libs/gl/include/leanfade/gl/detail/shading_block.hpp).
layout(std140, binding = LF_BINDING_OBJECT_BLOCK) uniform LfObjectBlock {
    mat4 u_model;          // object -> world
    mat4 u_view;           // world -> eye (no scale: eye depths are in world units)
    mat4 u_clip;           // world -> clip (projection * view, reference tiles included)
    mat3 u_normal_matrix;  // transpose(inverse(mat3(u_model)))
    vec3 u_eye_world;      // eye position, world space
    float u_tiling;        // texture repeats per unit of uv
    vec3 u_light_world;    // unit direction toward the light, world space
};

#if defined(LF_SEPARATE_VARYINGS)
struct VertexData { LF_VERTEX_DATA(LF_VERTEX_MEMBER) };
VertexData v_out;
LF_VERTEX_DATA(LF_VERTEX_OUTPUT)
#else
out VertexData { LF_VERTEX_DATA(LF_VERTEX_MEMBER) } v_out;  // bindings.glsl
#endif

void main() {
    vec4 world = u_model * vec4(a_position, 1.0);
    vec3 n = normalize(u_normal_matrix * a_normal);
    vec3 t = mat3(u_model) * a_tangent.xyz;
    t = normalize(t - n * dot(n, t));  // Gram-Schmidt (docs/math.md §1)
    vec3 b = a_tangent.w * cross(n, t);
    vec3 to_eye = u_eye_world - world.xyz;
    v_out.uv = a_uv * u_tiling;
    v_out.uv1 = a_uv1 * u_tiling;
    v_out.light_t = vec3(dot(t, u_light_world), dot(b, u_light_world), dot(n, u_light_world));
    v_out.view_t = vec3(dot(t, to_eye), dot(b, to_eye), dot(n, to_eye));
    v_out.eye_depth = -(u_view * world).z;
    v_out.linear_normal_change = a_linear_normal_change;
    gl_Position = u_clip * world;
#if defined(LF_SEPARATE_VARYINGS)
    LF_VERTEX_DATA(LF_VERTEX_STORE)
    // The WGSL export (`leanfade shaders --lang wgsl`) takes the same u_clip as OpenGL: WebGPU's
    // clip space has z in [0, w], not [-w, w]; naga's SPIR-V reader negates y (Vulkan's clip
    // space is y-down, WebGPU's y-up, as OpenGL's), which is undone here.
    gl_Position.z = 0.5 * (gl_Position.z + gl_Position.w);
    gl_Position.y = -gl_Position.y;
#endif
}
