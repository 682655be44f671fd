// Combined image samplers split into a texture and a sampler (spirv_samplers.hpp), on the
// module's instruction stream: SPIR-V 1.0 specification §2.3 (physical layout), §2.4 (logical
// layout: debug names, then decorations, then types and global variables, then functions).
#include "spirv_samplers.hpp"

#include <cstddef>
#include <map>
#include <optional>
#include <set>

#include <spirv_cross/spirv.hpp>

namespace leanfade::gl {
namespace {

using Instruction = std::vector<std::uint32_t>;

std::uint32_t opcode(const Instruction& i) { return i[0] & 0xffffu; }

Instruction make(spv::Op op, std::initializer_list<std::uint32_t> operands) {
    Instruction i{0};
    i.insert(i.end(), operands.begin(), operands.end());
    i[0] = (std::uint32_t(i.size()) << 16) | std::uint32_t(op);
    return i;
}

// A literal string: UTF-8, NUL-terminated, padded to whole words, first byte lowest (§2.2.1).
std::vector<std::uint32_t> literal_string(const std::string& text) {
    std::vector<std::uint32_t> out(text.size() / 4 + 1, 0u);
    for (std::size_t i = 0; i < text.size(); ++i)
        out[i / 4] |= std::uint32_t(static_cast<unsigned char>(text[i])) << (8 * (i % 4));
    return out;
}

std::string read_string(const Instruction& i, std::size_t first_word) {
    std::string out;
    for (std::size_t w = first_word; w < i.size(); ++w)
        for (int b = 0; b < 4; ++b) {
            const char c = char((i[w] >> (8 * b)) & 0xffu);
            if (c == '\0') return out;
            out += c;
        }
    return out;
}

// Instructions whose operand 3 (after result type and result) is a sampled image.
bool takes_sampled_image(spv::Op op) {
    return (op >= spv::OpImageSampleImplicitLod && op <= spv::OpImageSampleProjDrefExplicitLod) ||
           op == spv::OpImageGather || op == spv::OpImageDrefGather || op == spv::OpImage ||
           op == spv::OpImageQueryLod ||
           (op >= spv::OpImageSparseSampleImplicitLod &&
            op <= spv::OpImageSparseSampleProjDrefExplicitLod) ||
           op == spv::OpImageSparseGather || op == spv::OpImageSparseDrefGather;
}

}  // namespace

SplitSamplers split_combined_image_samplers(const std::vector<std::uint32_t>& words,
                                            std::uint32_t sampler_binding_offset) {
    SplitSamplers result;
    constexpr std::size_t kHeader = 5;
    if (words.size() < kHeader || words[0] != spv::MagicNumber) {
        result.refused = "not a SPIR-V module";
        return result;
    }
    std::vector<Instruction> code;
    for (std::size_t at = kHeader; at < words.size();) {
        const std::uint32_t count = words[at] >> 16;
        if (count == 0 || at + count > words.size()) {
            result.refused = "a truncated instruction";
            return result;
        }
        code.emplace_back(words.begin() + std::ptrdiff_t(at),
                          words.begin() + std::ptrdiff_t(at + count));
        at += count;
    }
    std::uint32_t bound = words[3];
    auto fresh = [&bound] { return bound++; };

    // Types: sampled image -> its image; pointers (UniformConstant) by pointee.
    std::map<std::uint32_t, std::uint32_t> image_of_sampled;
    std::set<std::uint32_t> arrays_of_sampled;
    std::map<std::uint32_t, std::uint32_t> uniform_pointer_to;  // pointer type -> pointee
    std::optional<std::uint32_t> sampler_type;
    for (const Instruction& i : code) {
        switch (spv::Op(opcode(i))) {
            case spv::OpTypeSampledImage:
                image_of_sampled[i[1]] = i[2];
                break;
            case spv::OpTypeArray:
            case spv::OpTypeRuntimeArray:
                if (image_of_sampled.count(i[2])) arrays_of_sampled.insert(i[1]);
                break;
            case spv::OpTypeSampler:
                sampler_type = i[1];
                break;
            case spv::OpTypePointer:
                if (i[2] == spv::StorageClassUniformConstant) uniform_pointer_to[i[1]] = i[3];
                break;
            default:
                break;
        }
    }
    // The combined samplers: variables whose pointee is a sampled image.
    struct Combined {
        std::uint32_t image_type = 0;
        std::uint32_t sampler_variable = 0;
    };
    std::map<std::uint32_t, Combined> combined;  // by variable
    for (const Instruction& i : code) {
        if (opcode(i) != spv::OpVariable) continue;
        const auto pointee = uniform_pointer_to.find(i[1]);
        if (pointee == uniform_pointer_to.end()) continue;
        if (arrays_of_sampled.count(pointee->second)) {
            result.refused = "an array of combined image samplers (WebGPU has no texture arrays)";
            return result;
        }
        const auto image = image_of_sampled.find(pointee->second);
        if (image != image_of_sampled.end()) combined[i[2]] = {image->second, 0};
    }
    if (combined.empty()) {
        result.words = words;
        return result;
    }
    // Every use of a combined sampler must be a load (or its name, decorations, interface).
    for (const Instruction& i : code) {
        const spv::Op op = spv::Op(opcode(i));
        if (op == spv::OpName || op == spv::OpDecorate || op == spv::OpEntryPoint ||
            op == spv::OpVariable)
            continue;
        for (std::size_t w = 1; w < i.size(); ++w)
            if (combined.count(i[w]) && !(op == spv::OpLoad && w == 3)) {
                result.refused = "a combined image sampler used by an instruction other than a load";
                return result;
            }
    }

    // New types, each declared where what it names already is: the sampler type (when the
    // module has none) and its pointer before the first image type, a pointer to an image type
    // right after that type.
    std::vector<Instruction> sampler_types;
    const bool had_sampler_type = sampler_type.has_value();
    if (!sampler_type) {
        sampler_type = fresh();
        sampler_types.push_back(make(spv::OpTypeSampler, {*sampler_type}));
    }
    std::map<std::uint32_t, std::uint32_t> pointer_of;  // pointee -> UniformConstant pointer
    for (const auto& [pointer, target] : uniform_pointer_to) pointer_of.emplace(target, pointer);
    std::map<std::uint32_t, Instruction> declared_after;  // type -> a new pointer to it
    auto pointer_to = [&](std::uint32_t pointee) {
        const auto known = pointer_of.find(pointee);
        if (known != pointer_of.end()) return known->second;
        const std::uint32_t pointer = fresh();
        pointer_of[pointee] = pointer;
        declared_after[pointee] =
            make(spv::OpTypePointer, {pointer, spv::StorageClassUniformConstant, pointee});
        return pointer;
    };
    const std::uint32_t sampler_pointer = pointer_to(*sampler_type);
    if (!had_sampler_type) {
        sampler_types.push_back(declared_after.at(*sampler_type));
        declared_after.erase(*sampler_type);
    }
    std::map<std::uint32_t, std::uint32_t> image_pointer;  // image type -> pointer
    for (auto& [variable, c] : combined) {
        image_pointer[c.image_type] = pointer_to(c.image_type);
        c.sampler_variable = fresh();
    }

    struct Loaded {
        std::uint32_t type = 0;     // the sampled image's
        std::uint32_t image = 0;    // the loaded texture
        std::uint32_t sampler = 0;  // the loaded sampler
    };
    std::map<std::uint32_t, Loaded> loads;  // by the former load's result
    std::vector<Instruction> out;
    out.reserve(code.size() + 4 * combined.size() + declared_after.size() + 2);
    bool sampler_types_written = sampler_types.empty();
    for (const Instruction& i : code) {
        const spv::Op op = spv::Op(opcode(i));
        if (!sampler_types_written && op == spv::OpTypeImage) {
            out.insert(out.end(), sampler_types.begin(), sampler_types.end());
            sampler_types_written = true;
        }
        const auto c = i.size() > 2 ? combined.find(op == spv::OpVariable ? i[2] : i[1])
                                    : combined.end();
        if (op == spv::OpName && c != combined.end()) {
            out.push_back(i);
            Instruction name{0, c->second.sampler_variable};
            for (const std::uint32_t w : literal_string(read_string(i, 2) + "_sampler"))
                name.push_back(w);
            name[0] = (std::uint32_t(name.size()) << 16) | spv::OpName;
            out.push_back(name);
        } else if (op == spv::OpDecorate && c != combined.end() &&
                   (i[2] == spv::DecorationBinding || i[2] == spv::DecorationDescriptorSet)) {
            out.push_back(i);
            const std::uint32_t value =
                i[2] == spv::DecorationBinding ? i[3] + sampler_binding_offset : i[3];
            out.push_back(make(spv::OpDecorate, {c->second.sampler_variable, i[2], value}));
        } else if (op == spv::OpVariable && c != combined.end()) {
            out.push_back(make(spv::OpVariable, {image_pointer.at(c->second.image_type), i[2],
                                                 spv::StorageClassUniformConstant}));
            out.push_back(make(spv::OpVariable, {sampler_pointer, c->second.sampler_variable,
                                                 spv::StorageClassUniformConstant}));
        } else if (op == spv::OpLoad && combined.count(i[3])) {
            // The texture and the sampler are loaded here; the sampled image is made again
            // before each instruction that takes it (it must be made in that one's block).
            const Combined& from = combined.at(i[3]);
            const Loaded loaded{i[1], fresh(), fresh()};
            out.push_back(make(spv::OpLoad, {from.image_type, loaded.image, i[3]}));
            out.push_back(
                make(spv::OpLoad, {*sampler_type, loaded.sampler, from.sampler_variable}));
            loads[i[2]] = loaded;
        } else if (takes_sampled_image(op) && loads.count(i[3])) {
            const Loaded& loaded = loads.at(i[3]);
            const std::uint32_t sampled = fresh();
            out.push_back(
                make(spv::OpSampledImage, {loaded.type, sampled, loaded.image, loaded.sampler}));
            Instruction use = i;
            use[3] = sampled;
            out.push_back(use);
        } else {
            out.push_back(i);
        }
        const bool declares_type = op >= spv::OpTypeVoid && op <= spv::OpTypeForwardPointer;
        if (declares_type) {
            const auto pointer = declared_after.find(i[1]);
            if (pointer != declared_after.end()) out.push_back(pointer->second);
        }
    }

    // A former load's result used by anything else (copied, selected, passed) has no value now.
    for (const Instruction& i : out) {
        if (takes_sampled_image(spv::Op(opcode(i))) && i.size() > 3 && loads.count(i[3])) continue;
        for (std::size_t w = 1; w < i.size(); ++w)
            if (loads.count(i[w]) && opcode(i) != spv::OpName && opcode(i) != spv::OpDecorate) {
                result.refused = "a combined image sampler's value used by an instruction that "
                                 "does not sample";
                return result;
            }
    }
    result.words.assign(words.begin(), words.begin() + kHeader);
    result.words[3] = bound;
    for (const Instruction& i : out) result.words.insert(result.words.end(), i.begin(), i.end());
    return result;
}

}  // namespace leanfade::gl
