// std140 block members from a field list (leanfade/gl/detail/std140.hpp).
#include "leanfade/gl/detail/std140.hpp"

#include <cstdint>
#include <cstring>

namespace leanfade::gl {
namespace {

void append_members(std::span<const Std140Field> fields, const std::string& prefix,
                    std::size_t base, std::vector<BlockMember>& out) {
    for (std::size_t i = 0; i < fields.size(); ++i) {
        const Std140Field& f = fields[i];
        const std::size_t offset = base + std140_offset_of(fields, i);
        if (f.kind == Std140Kind::Struct) {
            append_members(f.members, prefix + f.name + ".", offset, out);
            continue;
        }
        out.push_back({prefix + f.name + (f.array_size > 0 ? "[0]" : ""), offset});
    }
}

const char* glsl_type(Std140Kind kind) {
    switch (kind) {
        case Std140Kind::Float: return "float";
        case Std140Kind::Int: return "int";
        case Std140Kind::Vec2: return "vec2";
        case Std140Kind::Vec3: return "vec3";
        case Std140Kind::Vec4: return "vec4";
        case Std140Kind::Mat3: return "mat3";
        case Std140Kind::Mat4: return "mat4";
        case Std140Kind::Struct: return "struct";
    }
    return "";
}

// Numbers of a member (one array element) and where each sits relative to the member (std140:
// a mat3's columns 16 bytes apart).
int component_count(Std140Kind kind) {
    switch (kind) {
        case Std140Kind::Float:
        case Std140Kind::Int: return 1;
        case Std140Kind::Vec2: return 2;
        case Std140Kind::Vec3: return 3;
        case Std140Kind::Vec4: return 4;
        case Std140Kind::Mat3: return 9;
        case Std140Kind::Mat4: return 16;
        case Std140Kind::Struct: return 0;
    }
    return 0;
}

std::size_t component_offset(Std140Kind kind, int component) {
    return kind == Std140Kind::Mat3 ? std::size_t(component / 3) * 16 + std::size_t(component % 3) * 4
                                    : std::size_t(component) * 4;
}

void append_values(std::span<const Std140Field> fields, const std::string& prefix,
                   const std::uint8_t* base, std::vector<BlockValue>& out) {
    for (std::size_t i = 0; i < fields.size(); ++i) {
        const Std140Field& f = fields[i];
        const std::uint8_t* at = base + std140_offset_of(fields, i);
        if (f.kind == Std140Kind::Struct) {
            append_values(f.members, prefix + f.name + ".", at, out);
            continue;
        }
        BlockValue value{prefix + f.name, glsl_type(f.kind), {}};
        const int elements = f.array_size > 0 ? f.array_size : 1;
        const std::size_t stride = std140_round_up(std140_member_size({f.name, f.kind, 0}), 16);
        for (int e = 0; e < elements; ++e)
            for (int c = 0; c < component_count(f.kind); ++c) {
                const std::uint8_t* p = at + std::size_t(e) * stride + component_offset(f.kind, c);
                if (f.kind == Std140Kind::Int) {
                    std::int32_t v = 0;
                    std::memcpy(&v, p, 4);
                    value.values.push_back(double(v));
                } else {
                    float v = 0.0f;
                    std::memcpy(&v, p, 4);
                    value.values.push_back(double(v));
                }
            }
        out.push_back(std::move(value));
    }
}

}  // namespace

std::vector<BlockValue> std140_block_values(std::span<const Std140Field> fields,
                                            const void* block, const std::string& prefix) {
    std::vector<BlockValue> values;
    append_values(fields, prefix, static_cast<const std::uint8_t*>(block), values);
    return values;
}

std::vector<BlockMember> std140_block_members(std::span<const Std140Field> fields,
                                              const std::string& prefix) {
    std::vector<BlockMember> members;
    append_members(fields, prefix, 0, members);
    return members;
}

}  // namespace leanfade::gl
