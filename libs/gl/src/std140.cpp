// std140 block members from a field list (leanfade/gl/std140.hpp).
#include "leanfade/gl/std140.hpp"

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

}  // namespace

std::vector<BlockMember> std140_block_members(std::span<const Std140Field> fields,
                                              const std::string& prefix) {
    std::vector<BlockMember> members;
    append_members(fields, prefix, 0, members);
    return members;
}

}  // namespace leanfade::gl
