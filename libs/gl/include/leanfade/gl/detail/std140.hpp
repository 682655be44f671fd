#pragma once
// std140 layout (OpenGL 4.5 core, §7.6.2.2) computed from a field list, so that a uniform block's
// C++ mirror states each member once: its name, its GLSL type and its C++ offset. The offsets
// std140 gives are computed here and compared with the C++ ones at compile time, and the names
// and offsets the driver must report come from the same list (tests/gl/test_shaders.cpp).
//
// Supported member types: float, int, vec2, vec3, vec4, mat3, mat4, arrays of vec4, and nested
// structs (their own field list).
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace leanfade::gl {

struct Std140Field;

enum class Std140Kind { Float, Int, Vec2, Vec3, Vec4, Mat3, Mat4, Struct };

struct Std140Field {
    const char* name;         // as GLSL declares it
    Std140Kind kind;
    std::size_t cpp_offset;   // offsetof in the C++ mirror
    int array_size = 0;       // 0: not an array
    std::span<const Std140Field> members = {};  // kind Struct: its fields
};

constexpr std::size_t std140_round_up(std::size_t value, std::size_t alignment) {
    return (value + alignment - 1) / alignment * alignment;
}

constexpr std::size_t std140_struct_size(std::span<const Std140Field> fields);

// Base alignment of a member (rules 1-9: scalars 4, vec2 8, vec3 and vec4 16, matrices and
// structs and every array element rounded up to 16).
constexpr std::size_t std140_alignment(const Std140Field& f) {
    std::size_t alignment = 16;
    switch (f.kind) {
        case Std140Kind::Float:
        case Std140Kind::Int: alignment = 4; break;
        case Std140Kind::Vec2: alignment = 8; break;
        default: alignment = 16; break;
    }
    return f.array_size > 0 ? std140_round_up(alignment, 16) : alignment;
}

// Bytes a member occupies (an array: its count times the element stride; a vec3 12, so that a
// scalar after it fills the fourth component).
constexpr std::size_t std140_member_size(const Std140Field& f) {
    std::size_t size = 0;
    switch (f.kind) {
        case Std140Kind::Float:
        case Std140Kind::Int: size = 4; break;
        case Std140Kind::Vec2: size = 8; break;
        case Std140Kind::Vec3: size = 12; break;
        case Std140Kind::Vec4: size = 16; break;
        case Std140Kind::Mat3: size = 48; break;  // three columns, each padded to a vec4
        case Std140Kind::Mat4: size = 64; break;
        case Std140Kind::Struct: size = std140_struct_size(f.members); break;
    }
    return f.array_size > 0 ? std::size_t(f.array_size) * std140_round_up(size, 16) : size;
}

// The std140 offset of each field, in order.
constexpr std::size_t std140_offset_of(std::span<const Std140Field> fields, std::size_t index) {
    std::size_t offset = 0;
    for (std::size_t i = 0; i <= index; ++i) {
        offset = std140_round_up(offset, std140_alignment(fields[i]));
        if (i < index) offset += std140_member_size(fields[i]);
    }
    return offset;
}

// Where the last field ends (a block's data size before the struct rounding).
constexpr std::size_t std140_end(std::span<const Std140Field> fields) {
    if (fields.empty()) return 0;
    const std::size_t last = fields.size() - 1;
    return std140_offset_of(fields, last) + std140_member_size(fields[last]);
}

// A struct's size: its end rounded up to 16 (rule 9).
constexpr std::size_t std140_struct_size(std::span<const Std140Field> fields) {
    return std140_round_up(std140_end(fields), 16);
}

// True when every field (and every nested struct's field) sits at its std140 offset in the C++
// mirror.
constexpr bool std140_matches_cpp(std::span<const Std140Field> fields) {
    for (std::size_t i = 0; i < fields.size(); ++i) {
        if (std140_offset_of(fields, i) != fields[i].cpp_offset) return false;
        if (fields[i].kind == Std140Kind::Struct && !std140_matches_cpp(fields[i].members))
            return false;
    }
    return true;
}

// One member as the driver names it (glGetProgramResourceIndex) and its offset in the block.
struct BlockMember {
    std::string name;
    std::size_t offset;
};

// The members the driver lists for a block whose fields are `fields`, names prefixed with
// `prefix` ("u_shading." for an instance name, "" for none): nested structs flattened
// ("u_shading.params.shininess"), arrays as their first element ("u_layers.offsets[0]").
std::vector<BlockMember> std140_block_members(std::span<const Std140Field> fields,
                                              const std::string& prefix);

// One member's value in a block's bytes: its name as std140_block_members gives it (an array's
// without "[0]"), its GLSL type ("float", "int", "vec3", "mat4", ...) and its numbers (a matrix
// column by column, an array element by element).
struct BlockValue {
    std::string name;
    std::string type;
    std::vector<double> values;
};

// The value of every member of the block `block` points at (a C++ mirror whose layout is
// `fields`, std140_matches_cpp), for tools that hand a block's contents to another program
// (`leanfade shaders` writes the defaults into shaders.json).
std::vector<BlockValue> std140_block_values(std::span<const Std140Field> fields,
                                            const void* block, const std::string& prefix);

}  // namespace leanfade::gl
