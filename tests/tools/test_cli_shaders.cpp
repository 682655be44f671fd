// leanfade shaders: every stage and variant in GLSL, SPIR-V, HLSL, MSL, GLSL ES and WGSL, checked
// with the tools Debian has: glslangValidator compiles the GLSL (OpenGL) and the HLSL back (its
// HLSL front end), spirv-val validates every SPIR-V module (the exported ones, optimised, and the
// HLSL compiled back), spirv-dis shows the bindings and names they keep, and the index's reflection
// of each module agrees with the disassembly and the C++ mirrors of the blocks. Debian 12 has no
// Metal compiler: the MSL files get a structural check (entry point, block, sampler and struct
// names, resource indices), which is not a compile. Errors: a bad --lang, an output that cannot be
// written, a shader that does not compile: one line, exit 1, nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "leanfade/core/technique.hpp"
#include "leanfade/gl/detail/shader_export.hpp"
#include "leanfade/gl/detail/shading_block.hpp"
#include "leanfade/gl/shader_library.hpp"
#include "leanfade/scene/detail/map_kinds.hpp"
#include "tools_test_helpers.hpp"

namespace leanfade::test {
namespace {

namespace fs = std::filesystem;

// Runs a command line through the shell, its output into `log` (returned with the exit code).
int run_tool(const std::string& command, const fs::path& log, std::string* output) {
    const int status =
        std::system((command + " >" + shell_quote(log.string()) + " 2>&1 </dev/null").c_str());
    *output = read_text(log);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The scene variants the renderer builds: the fragment stages `leanfade shaders` exports.
std::vector<const gl::ShaderVariant*> scene_variants() {
    std::vector<const gl::ShaderVariant*> variants;
    for (const gl::ShaderVariant& v : gl::shader_variants())
        if (v.vertex == "scene.vert" && v.fragment == "scene.frag") variants.push_back(&v);
    return variants;
}

struct Export {
    fs::path folder;
    nlohmann::json index;
};

// `leanfade shaders --lang LANG -o <scratch>/out`, which must succeed; `name` is the scratch
// folder's (one per test: ctest runs them in parallel).
Export export_shaders(const std::string& lang, const std::string& name = "") {
    const fs::path scratch = scratch_dir("shaders_" + (name.empty() ? lang : name));
    const fs::path out = scratch / "out";
    const RunResult r = run_leanfade("shaders --lang " + lang + " -o " + shell_quote(out), scratch);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(std::to_string(1 + scene_variants().size()) + " " + lang + " shaders"),
              std::string::npos)
        << r.out;
    Export e{out, nlohmann::json::parse(read_text(out / "shaders.json"))};
    return e;
}

// The index lists the vertex stage and one fragment stage per scene variant, with its defines,
// and every file it names exists and is not empty.
void expect_complete_index(const Export& e, const std::string& lang, const std::string& ext) {
    ASSERT_EQ(e.index["language"], lang);
    const auto& shaders = e.index["shaders"];
    const std::vector<const gl::ShaderVariant*> variants = scene_variants();
    ASSERT_EQ(shaders.size(), 1 + variants.size());
    EXPECT_EQ(shaders[0]["stage"], "vert");
    EXPECT_EQ(shaders[0]["file"], "scene.vert" + ext);
    for (std::size_t i = 0; i < variants.size(); ++i) {
        const auto& s = shaders[i + 1];
        EXPECT_EQ(s["variant"], variants[i]->name);
        EXPECT_EQ(s["stage"], "frag");
        EXPECT_EQ(s["file"], variants[i]->name + ".frag" + ext);
        EXPECT_EQ(s["defines"].get<std::vector<std::string>>(), variants[i]->defines);
    }
    for (const auto& s : shaders) {
        const fs::path file = e.folder / s["file"].get<std::string>();
        ASSERT_TRUE(fs::is_regular_file(file)) << file;
        EXPECT_GT(fs::file_size(file), 500u) << file;
    }
    // Every technique of the table has its ordinary fragment stage.
    for (const TechniqueInfo& row : kTechniques)
        EXPECT_TRUE(fs::is_regular_file(
            e.folder / (gl::variant_name(gl::VariantKey::scene(row.id)) + ".frag" + ext)))
            << row.name;
}

std::string stage_of(const nlohmann::json& s) {
    return s["stage"].get<std::string>();
}

TEST(ShadersCli, GlslIsSelfContainedAndCompilesForOpenGl) {
    const Export e = export_shaders("glsl");
    expect_complete_index(e, "glsl", ".glsl");
    std::map<std::string, std::string> files_of_stage;  // "vert" -> "'a.glsl' 'b.glsl' ..."
    for (const auto& s : e.index["shaders"]) {
        const fs::path file = e.folder / s["file"].get<std::string>();
        const std::string text = read_text(file);
        EXPECT_EQ(text.rfind("#version 450 core\n", 0), 0u) << file;
        EXPECT_EQ(text.find("#include"), std::string::npos) << file;
        EXPECT_EQ(text.find("#line"), std::string::npos) << file;
        for (const std::string& define : s["defines"].get<std::vector<std::string>>())
            EXPECT_NE(text.find("#define " + define + "\n"), std::string::npos) << define;
        if (stage_of(s) == "frag") {
            EXPECT_NE(text.find("LfShade lf_shade("), std::string::npos) << file;
            EXPECT_NE(text.find("uniform LfShadingBlock"), std::string::npos) << file;
        }
        std::string& files = files_of_stage[stage_of(s)];
        files += ' ';
        files += shell_quote(file.string());
    }
    // glslangValidator compiles each file on its own (OpenGL rules, no SPIR-V) and fails when
    // any does not compile, naming it.
    const fs::path log = e.folder.parent_path() / "tool.txt";
    ASSERT_EQ(files_of_stage.size(), 2u);
    for (const auto& [stage, files] : files_of_stage) {
        std::string output;
        EXPECT_EQ(run_tool("glslangValidator -S " + stage + files, log, &output), 0) << output;
    }
}

// The numbers of the "OpDecorate %x Binding N" lines of a disassembly, one per resource.
std::vector<int> bindings_of(const std::string& disassembly) {
    std::vector<int> bindings;
    std::istringstream in(disassembly);
    std::string line;
    while (std::getline(in, line)) {
        const std::size_t at = line.find(" Binding ");
        if (line.find("OpDecorate") != std::string::npos && at != std::string::npos)
            bindings.push_back(std::stoi(line.substr(at + 9)));
    }
    return bindings;
}

TEST(ShadersCli, SpirvModulesValidateAndKeepNamesAndBindings) {
    const Export e = export_shaders("spirv");
    expect_complete_index(e, "spirv", ".spv");
    EXPECT_EQ(e.index["uniform_block_binding_offset"], gl::kSpirvUniformBlockBase);
    const fs::path log = e.folder.parent_path() / "tool.txt";
    std::vector<int> vertex_bindings;
    for (const auto& s : e.index["shaders"]) {
        const fs::path file = e.folder / s["file"].get<std::string>();
        const std::string bytes = read_text(file);
        ASSERT_EQ(bytes.size() % 4, 0u) << file;
        EXPECT_EQ(bytes.substr(0, 4), std::string("\x03\x02\x23\x07", 4)) << file;  // magic
        std::string output;
        EXPECT_EQ(run_tool("spirv-val --target-env vulkan1.0 " + shell_quote(file), log, &output),
                  0)
            << file << ": " << output;
        ASSERT_EQ(run_tool("spirv-dis " + shell_quote(file), log, &output), 0) << output;
        if (stage_of(s) == "frag") {
            // The fragment block at its binding + the shift.
            EXPECT_NE(output.find("OpName %LfShadingBlock \"LfShadingBlock\""), std::string::npos);
            EXPECT_NE(output.find("OpMemberName %LfShadingBlock 0 \"u_shading\""),
                      std::string::npos);
            EXPECT_NE(
                output.find("Binding " + std::to_string(gl::bindings::LF_BINDING_SHADING_BLOCK +
                                                        gl::kSpirvUniformBlockBase)),
                std::string::npos)
                << file;
            // The LEAN map (read by every variant but the layered ones) at its texture unit.
            if (s["variant"].get<std::string>().find("_layered") == std::string::npos) {
                EXPECT_NE(output.find("OpName %u_lean \"u_lean\""), std::string::npos);
                EXPECT_NE(output.find("OpDecorate %u_lean Binding " +
                                      std::to_string(gl::bindings::LF_BINDING_LEAN_MAP)),
                          std::string::npos)
                    << file;
            }
            EXPECT_NE(output.find("OpEntryPoint Fragment %main \"main\""), std::string::npos);
            // One descriptor set for the pipeline: no two resources of the vertex and the
            // fragment stage share a binding.
            std::vector<int> all = bindings_of(output);
            all.insert(all.end(), vertex_bindings.begin(), vertex_bindings.end());
            EXPECT_EQ(std::set<int>(all.begin(), all.end()).size(), all.size()) << file;
        } else {
            vertex_bindings = bindings_of(output);  // the vertex stage comes first
            EXPECT_EQ(vertex_bindings.size(), 1u) << output;
            EXPECT_NE(output.find("OpName %LfObjectBlock \"LfObjectBlock\""), std::string::npos);
            EXPECT_NE(
                output.find("Binding " + std::to_string(gl::bindings::LF_BINDING_OBJECT_BLOCK +
                                                        gl::kSpirvUniformBlockBase)),
                std::string::npos);
            EXPECT_NE(output.find("OpEntryPoint Vertex %main \"main\""), std::string::npos);
        }
    }
}

// A block's reflected members (arrays by their first element, as the C++ mirrors list them) by
// name, with their offsets.
std::map<std::string, std::size_t> reflected_members(const nlohmann::json& resource) {
    std::map<std::string, std::size_t> out;
    for (const auto& m : resource["members"])
        out[m["name"].get<std::string>() + (m.contains("array_size") ? "[0]" : "")] =
            m["offset"].get<std::size_t>();
    return out;
}

std::map<std::string, std::size_t> mirror_members(const std::vector<gl::BlockMember>& members) {
    std::map<std::string, std::size_t> out;
    for (const gl::BlockMember& m : members) out[m.name] = m.offset;
    return out;
}

// The SPIR-V index reflects each module: exactly the bindings the module declares (after
// optimisation, those it reads), each block's members at the offsets of its C++ mirror, the
// vertex attributes with their formats, and the fragment stage's inputs as the vertex stage's
// outputs. Optimisation shrinks every module and removes the base roughness from the variants
// that do not read it.
TEST(ShadersCli, SpirvIsOptimisedAndReflectedInTheIndex) {
    const Export e = export_shaders("spirv", "spirv_reflection");
    const fs::path log = e.folder.parent_path() / "tool.txt";
    namespace b = gl::bindings;
    const std::map<std::string, std::map<std::string, std::size_t>> mirrors{
        {"LfShadingBlock", mirror_members(gl::shading_block_members())},
        {"LfObjectBlock", mirror_members(gl::object_block_members())},
        {"LfLayerBlock", mirror_members(gl::layer_block_members())}};
    nlohmann::json vertex_outputs, vertex_inputs;
    std::set<int> sampled;  // every sampler binding some variant reads
    std::size_t before = 0, after = 0;
    for (const auto& s : e.index["shaders"]) {
        const fs::path file = e.folder / s["file"].get<std::string>();
        const std::string variant = s["variant"];
        EXPECT_EQ(s["size"].get<std::size_t>(), fs::file_size(file)) << file;
        EXPECT_LT(s["size"].get<std::size_t>(), s["unoptimised_size"].get<std::size_t>()) << file;
        before += s["unoptimised_size"].get<std::size_t>();
        after += s["size"].get<std::size_t>();
        const auto& r = s["reflection"];
        EXPECT_EQ(r["entry_point"], "main");
        EXPECT_EQ(r["stage"], stage_of(s) == "vert" ? "vertex" : "fragment");

        std::string output;
        ASSERT_EQ(run_tool("spirv-dis " + shell_quote(file), log, &output), 0) << output;
        const std::vector<int> declared = bindings_of(output);
        std::multiset<int> reflected;
        for (const auto& res : r["resources"]) {
            reflected.insert(res["binding"].get<int>());
            EXPECT_EQ(res["set"], 0);
            EXPECT_EQ(res["stage"], r["stage"]);
            const std::string name = res["name"];
            if (res["descriptor_type"] == "uniform_buffer") {
                ASSERT_EQ(mirrors.count(name), 1u) << name;
                EXPECT_EQ(reflected_members(res), mirrors.at(name)) << file << ": " << name;
                EXPECT_GT(res["block_size"].get<std::size_t>(), 0u);
                EXPECT_EQ(res["array_size"], 1);
            } else {
                EXPECT_EQ(res["descriptor_type"], "combined_image_sampler") << name;
                sampled.insert(res["binding"].get<int>());
                EXPECT_EQ(res["array_size"], name == "u_layer_maps" ? 4 : 1) << name;
                // The surface maps' samplers (u_ + their table's GLSL name) are 2D, as are the
                // layer weights; the LEAN maps are arrays of slices.
                bool two_d = name == "u_layer_weights";
                for (const scene::MapKindInfo& row : scene::kMapKinds) {
                    std::string sampler = "u_" + std::string(row.glsl_name);
                    std::transform(sampler.begin(), sampler.end(), sampler.begin(),
                                   [](unsigned char c) { return char(std::tolower(c)); });
                    two_d = two_d || name == sampler;
                }
                EXPECT_EQ(res["type"], two_d ? "sampler2D" : "sampler2DArray") << name;
            }
        }
        EXPECT_EQ(reflected, std::multiset<int>(declared.begin(), declared.end())) << file;
        const std::set<int> numbers(declared.begin(), declared.end());
        if (stage_of(s) == "vert") {
            const auto& inputs = r["inputs"];
            ASSERT_EQ(inputs.size(), 6u);
            const char* names[] = {"a_position", "a_normal", "a_uv",
                                   "a_tangent",  "a_uv1",    "a_linear_normal_change"};
            const char* formats[] = {"R32G32B32_SFLOAT",    "R32G32B32_SFLOAT", "R32G32_SFLOAT",
                                     "R32G32B32A32_SFLOAT", "R32G32_SFLOAT",    "R32_SFLOAT"};
            for (int i = 0; i < 6; ++i) {
                EXPECT_EQ(inputs[i]["name"], names[i]);
                EXPECT_EQ(inputs[i]["location"], i);
                EXPECT_EQ(inputs[i]["format"], formats[i]);
            }
            vertex_outputs = r["outputs"];
            vertex_inputs = inputs;
            EXPECT_EQ(vertex_outputs.size(), 6u);  // VertexData; gl_Position is a built-in
            continue;
        }
        EXPECT_EQ(r["inputs"], vertex_outputs) << file;
        ASSERT_EQ(r["outputs"].size(), 1u);
        EXPECT_EQ(r["outputs"][0]["name"], "o_color");
        // Blinn-Phong reads no base roughness: its binding is gone.
        if (variant.find("_ct") == std::string::npos) {
            EXPECT_EQ(numbers.count(b::LF_BINDING_BASE_ROUGHNESS), 0u) << file;
        } else if (variant.find("_layered") == std::string::npos) {
            EXPECT_EQ(numbers.count(b::LF_BINDING_BASE_ROUGHNESS), 1u) << file;
        }
        EXPECT_EQ(numbers.count(b::LF_BINDING_LEAN_MAP),
                  variant.find("_layered") == std::string::npos ? 1u : 0u)
            << file;
    }
    // The index's vertex layout is the vertex stage's interface: each attribute at its location
    // with the reflected format's component count, interleaved in one binding of 60 bytes.
    const auto& layout = e.index["vertex_layout"];
    EXPECT_EQ(layout["stride"], 60);
    ASSERT_EQ(layout["attributes"].size(), vertex_inputs.size());
    std::size_t offset = 0;
    for (std::size_t i = 0; i < vertex_inputs.size(); ++i) {
        const auto& a = layout["attributes"][i];
        EXPECT_EQ(a["location"], vertex_inputs[i]["location"]);
        EXPECT_EQ("a_" + a["name"].get<std::string>(), vertex_inputs[i]["name"]);
        const std::string format = vertex_inputs[i]["format"];
        const int components = int(std::count(format.begin(), format.end(), '3'));  // R32G32..
        EXPECT_EQ(a["components"], components) << format;
        EXPECT_EQ(a["offset"], offset);
        offset += 4 * a["components"].get<std::size_t>();
    }
    EXPECT_EQ(offset, 60u);
    // The index's surface maps: distinct bits of u_shading.maps, each bound where some variant
    // samples it, with a uv transform slot and what to bind in its absence.
    int bits = 0;
    for (const auto& m : e.index["maps"]) {
        const int bit = m["maps_bit"];
        EXPECT_EQ(bit & (bit - 1), 0) << m.dump();
        EXPECT_EQ(bits & bit, 0) << m.dump();
        bits |= bit;
        EXPECT_EQ(sampled.count(m["binding"].get<int>()), 1u) << m.dump();
        EXPECT_GE(m["uv_transform"].get<int>(), 0);
        EXPECT_LT(m["uv_transform"].get<int>(), 7);
        EXPECT_FALSE(m["when_absent"].get<std::string>().empty());
    }
    EXPECT_EQ(e.index["maps"].size(), scene::kMapKindCount);

    // The whole set: optimisation takes out most of what glslang writes.
    EXPECT_LT(after * 3, before) << after << " of " << before << " bytes";
    EXPECT_NE(e.index["optimizer"].get<std::string>().find("spirv-opt -O"), std::string::npos);
}

TEST(ShadersCli, HlslCompilesBackWithGlslangAndKeepsNames) {
    const Export e = export_shaders("hlsl");
    expect_complete_index(e, "hlsl", ".hlsl");
    const fs::path log = e.folder.parent_path() / "tool.txt";
    const fs::path back = e.folder.parent_path() / "back.spv";
    for (const auto& s : e.index["shaders"]) {
        const fs::path file = e.folder / s["file"].get<std::string>();
        const std::string text = read_text(file);
        if (stage_of(s) == "frag") {
            // Registers are the OpenGL numbers.
            EXPECT_NE(text.find("cbuffer LfShadingBlock : register(b" +
                                std::to_string(gl::bindings::LF_BINDING_SHADING_BLOCK) + ")"),
                      std::string::npos)
                << file;
            if (s["variant"].get<std::string>().find("_layered") == std::string::npos) {
                EXPECT_NE(text.find("Texture2DArray<float4> u_lean : register(t" +
                                    std::to_string(gl::bindings::LF_BINDING_LEAN_MAP) + ")"),
                          std::string::npos)
                    << file;
            }
        } else {
            EXPECT_NE(text.find("cbuffer LfObjectBlock : register(b" +
                                std::to_string(gl::bindings::LF_BINDING_OBJECT_BLOCK) + ")"),
                      std::string::npos)
                << file;
        }
        // glslang's HLSL front end: compiled to SPIR-V, which must validate (--spirv-val) and
        // be there.
        std::string output;
        fs::remove(back);
        EXPECT_EQ(run_tool("glslangValidator -D -V --spirv-val -e main -S " + stage_of(s) + " " +
                               shell_quote(file) + " -o " + shell_quote(back),
                           log, &output),
                  0)
            << file << ": " << output;
        EXPECT_TRUE(fs::is_regular_file(back)) << file << ": " << output;
    }
}

// Structural only: no Metal compiler exists in Debian 12 (docs/integration.md).
TEST(ShadersCli, MslHasEntryPointsBlocksAndResourceIndicesStructuralCheckNotACompile) {
    const Export e = export_shaders("msl");
    expect_complete_index(e, "msl", ".metal");
    for (const auto& s : e.index["shaders"]) {
        const fs::path file = e.folder / s["file"].get<std::string>();
        const std::string text = read_text(file);
        EXPECT_NE(text.find("#include <metal_stdlib>"), std::string::npos) << file;
        // Argument indices are the OpenGL numbers (shaders/bindings.glsl): [[texture(unit)]],
        // [[sampler(unit)]], [[buffer(block binding)]].
        namespace b = gl::bindings;
        auto has = [&](const std::string& pattern) {
            return std::regex_search(text, std::regex(pattern));
        };
        const std::string variant = s["variant"].get<std::string>();
        if (stage_of(s) == "frag") {
            EXPECT_NE(text.find("fragment main0_out main0("), std::string::npos) << file;
            EXPECT_NE(text.find("struct LfShadingBlock"), std::string::npos) << file;
            EXPECT_NE(text.find("LfShadingUniforms u_shading;"), std::string::npos) << file;
            EXPECT_NE(text.find("struct LfParams"), std::string::npos) << file;
            EXPECT_TRUE(has(R"(constant LfShadingBlock& \w+ \[\[buffer\()" +
                            std::to_string(b::LF_BINDING_SHADING_BLOCK) + R"(\)\]\])"))
                << file;
            if (variant.find("_layered") == std::string::npos) {
                const std::string unit = std::to_string(b::LF_BINDING_LEAN_MAP);
                EXPECT_TRUE(
                    has(R"(texture2d_array<float> u_lean \[\[texture\()" + unit + R"(\)\]\])"))
                    << file;
                EXPECT_TRUE(has(R"(sampler u_leanSmplr \[\[sampler\()" + unit + R"(\)\]\])"))
                    << file;
            } else {
                EXPECT_TRUE(has(R"(array<texture2d_array<float>, 4> u_layer_maps \[\[texture\()" +
                                std::to_string(b::LF_BINDING_LAYER_MAPS) + R"(\)\]\])"))
                    << file;
                EXPECT_TRUE(has(R"(constant LfLayerBlock& \w+ \[\[buffer\()" +
                                std::to_string(b::LF_BINDING_LAYER_BLOCK) + R"(\)\]\])"))
                    << file;
            }
        } else {
            EXPECT_NE(text.find("vertex main0_out main0("), std::string::npos) << file;
            EXPECT_NE(text.find("struct LfObjectBlock"), std::string::npos) << file;
            EXPECT_TRUE(has(R"(constant LfObjectBlock& \w+ \[\[buffer\()" +
                            std::to_string(b::LF_BINDING_OBJECT_BLOCK) + R"(\)\]\])"))
                << file;
        }
        // Every brace closed: a truncated or garbled translation would not balance.
        long depth = 0;
        for (const char c : text) depth += c == '{' ? 1 : c == '}' ? -1 : 0;
        EXPECT_EQ(depth, 0) << file;
    }
}

// GLSL ES 3.00 for WebGL2: every variant but those ES cannot express (the roughness MIPs' LOD
// queries) has a file that glslangValidator compiles under OpenGL ES rules; the vertex outputs
// and fragment inputs, matched by name in ES, carry one name; no layout bindings (ES 3.00 has
// none), the reflection gives the OpenGL units and block bindings instead.
TEST(ShadersCli, GlslEsCompilesAsEs300ForWebGl2WithMatchingInterfaceAndReflection) {
    const fs::path scratch = scratch_dir("shaders_glsl_es");
    const fs::path out = scratch / "out";
    const RunResult r = run_leanfade("shaders --lang glsl-es -o " + shell_quote(out), scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json index = nlohmann::json::parse(read_text(out / "shaders.json"));
    EXPECT_EQ(index["language"], "glsl-es");
    const std::vector<const gl::ShaderVariant*> variants = scene_variants();
    const auto& shaders = index["shaders"];
    ASSERT_EQ(shaders.size(), 1 + variants.size());
    std::set<std::string> vertex_outputs;
    std::set<std::string> fragment_inputs;
    std::size_t omitted = 0;
    const std::regex interface_variable(R"((in|out) (highp |mediump )?\w+ (lf_vertex_\w+);)");
    const fs::path log = scratch / "tool.txt";
    for (std::size_t i = 0; i < shaders.size(); ++i) {
        const auto& s = shaders[i];
        const std::string variant = s["variant"];
        // The roughness MIPs of one LEAN map (bump layers mix moments instead).
        const bool roughness = i > 0 && variants[i - 1]->key.technique == Technique::Roughness &&
                               variant.find("_layered") == std::string::npos;
        if (roughness) {
            // The one construct ES 3.00 lacks, named.
            EXPECT_NE(s.value("omitted", "").find("textureQueryLevels"), std::string::npos)
                << variant;
            EXPECT_FALSE(s.contains("file")) << variant;
            ++omitted;
            continue;
        }
        ASSERT_FALSE(s.contains("omitted")) << variant << ": " << s["omitted"];
        const fs::path file = out / s["file"].get<std::string>();
        EXPECT_EQ(s["file"], variant + "." + stage_of(s) + ".essl");
        const std::string text = read_text(file);
        EXPECT_EQ(text.rfind("#version 300 es\n", 0), 0u) << file;
        EXPECT_EQ(text.find("binding"), std::string::npos) << file;
        std::set<std::string>& names = stage_of(s) == "vert" ? vertex_outputs : fragment_inputs;
        const std::string direction = stage_of(s) == "vert" ? "out" : "in";
        std::set<std::string> mine;
        for (std::sregex_iterator it(text.begin(), text.end(), interface_variable), end; it != end;
             ++it)
            if ((*it)[1] == direction) mine.insert((*it)[3]);
        // uv, light_t, view_t, eye_depth, uv1, linear_normal_change
        EXPECT_EQ(mine.size(), 6u) << file;
        if (names.empty()) names = mine;
        EXPECT_EQ(mine, names) << file;
        // The reflection: OpenGL numbers (blocks below the SPIR-V offset), the blocks' layout.
        bool shading_block = false;
        for (const auto& res : s["reflection"]["resources"]) {
            EXPECT_LT(res["binding"].get<int>(), 16) << file;
            if (res["name"] == "LfShadingBlock") {
                shading_block = true;
                EXPECT_EQ(res["binding"], gl::bindings::LF_BINDING_SHADING_BLOCK);
                EXPECT_EQ(res["block_size"], sizeof(gl::LfShadingUniforms));
            }
        }
        EXPECT_EQ(shading_block, stage_of(s) == "frag") << file;
        std::string output;
        EXPECT_EQ(
            run_tool("glslangValidator -S " + stage_of(s) + " " + shell_quote(file), log, &output),
            0)
            << file << ": " << output;
    }
    EXPECT_EQ(vertex_outputs, fragment_inputs);
    EXPECT_GT(omitted, 0u);
    EXPECT_NE(r.out.find(std::to_string(omitted) + " variants have no glsl-es form"),
              std::string::npos)
        << r.out;
}

// WGSL (naga from the SPIR-V with split samplers): every variant has a file or says why not
// (arrays of textures for bump layers, the LOD query of the roughness MIPs); each file turns off
// the derivative-uniformity diagnostic and binds in group 0; the reflection pairs every texture
// with its sampler at kWgslSamplerBindingOffset + its unit, and the shading block keeps its C++
// mirror's size. (The files are parsed by an independent WGSL parser and drawn by WebGPU in
// tests/web.)
TEST(ShadersCli, WgslSplitsSamplersAndSaysWhyAVariantHasNoForm) {
    const fs::path scratch = scratch_dir("shaders_wgsl");
    const fs::path out = scratch / "out";
    const RunResult r = run_leanfade("shaders --lang wgsl -o " + shell_quote(out), scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json index = nlohmann::json::parse(read_text(out / "shaders.json"));
    EXPECT_EQ(index["language"], "wgsl");
    EXPECT_EQ(index["sampler_binding_offset"], gl::kWgslSamplerBindingOffset);
    EXPECT_EQ(index["uniform_block_binding_offset"], gl::kSpirvUniformBlockBase);
    const std::vector<const gl::ShaderVariant*> variants = scene_variants();
    const auto& shaders = index["shaders"];
    ASSERT_EQ(shaders.size(), 1 + variants.size());
    std::size_t files = 0;
    for (std::size_t i = 0; i < shaders.size(); ++i) {
        const auto& s = shaders[i];
        const std::string variant = s["variant"];
        const bool layered = variant.find("_layered") != std::string::npos;
        const bool roughness =
            i > 0 && variants[i - 1]->key.technique == Technique::Roughness && !layered;
        if (layered || roughness) {
            EXPECT_NE(s.value("omitted", "")
                          .find(layered ? "array of combined image samplers" : "ImageQueryLod"),
                      std::string::npos)
                << variant << ": " << s.value("omitted", "");
            EXPECT_FALSE(s.contains("file")) << variant;
            continue;
        }
        ASSERT_FALSE(s.contains("omitted")) << variant << ": " << s["omitted"];
        ++files;
        const std::string text = read_text(out / s["file"].get<std::string>());
        EXPECT_EQ(text.rfind("diagnostic(off, derivative_uniformity);\n", 0), 0u) << variant;
        EXPECT_NE(text.find(stage_of(s) == "vert" ? "@vertex" : "@fragment"), std::string::npos);
        EXPECT_EQ(text.find("binding_array"), std::string::npos) << variant;
        EXPECT_EQ(text.find("@group(1)"), std::string::npos) << variant;
        std::map<std::string, int> textures, samplers;
        for (const auto& res : s["reflection"]["resources"]) {
            const std::string kind = res["descriptor_type"];
            EXPECT_NE(kind, "combined_image_sampler") << variant;
            if (kind == "sampled_texture") textures[res["name"]] = res["binding"];
            if (kind == "sampler") samplers[res["name"]] = res["binding"];
            if (res["name"] == "LfShadingBlock") {
                EXPECT_EQ(res["block_size"], sizeof(gl::LfShadingUniforms));
            }
        }
        EXPECT_EQ(textures.size(), samplers.size()) << variant;
        for (const auto& [name, binding] : textures)
            EXPECT_EQ(samplers[name + "_sampler"], binding + int(gl::kWgslSamplerBindingOffset))
                << variant << " " << name;
        if (stage_of(s) == "frag") {
            EXPECT_EQ(textures.count("u_lean"), 1u) << variant;
        }
    }
    EXPECT_GE(files, 1u + kTechniques.size() - 1);  // every technique but the roughness MIPs
    EXPECT_NE(r.out.find(std::to_string(shaders.size() - files) + " variants have no wgsl form"),
              std::string::npos)
        << r.out;
}

// Without the translator beside the program (a copy of leanfade in another folder), WGSL is a
// one-line error that says what is missing, and nothing is written.
TEST(ShadersCli, WgslWithoutTheTranslatorIsOneLineAndWritesNothing) {
    const fs::path scratch = scratch_dir("shaders_wgsl_alone");
    const fs::path program = scratch / "bin" / "leanfade";
    fs::create_directories(program.parent_path());
    fs::copy_file(LEANFADE_EXE, program);
    const fs::path out = scratch / "out";
    const fs::path log = scratch / "log.txt";
    std::string output;
    EXPECT_EQ(run_tool(shell_quote(program.string()) + " shaders --lang wgsl -o " +
                           shell_quote(out.string()),
                       log, &output),
              1);
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
    EXPECT_NE(output.find("naga-wasm"), std::string::npos) << output;
    EXPECT_FALSE(fs::exists(out));
}

TEST(ShadersCli, UnknownLanguageIsOneLineAndWritesNothing) {
    const fs::path scratch = scratch_dir("shaders_bad_lang");
    const RunResult r =
        run_leanfade("shaders --lang cuda -o " + shell_quote(scratch / "out"), scratch);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.err,
              "leanfade shaders: --lang: unknown shader language 'cuda' (expected glsl, spirv, "
              "hlsl, msl, glsl-es or wgsl)\n");
    EXPECT_FALSE(fs::exists(scratch / "out"));
}

TEST(ShadersCli, OutputFolderThatIsAFileIsRefused) {
    const fs::path scratch = scratch_dir("shaders_out_is_file");
    const fs::path out = scratch / "out";
    std::ofstream(out) << "not a folder";
    const RunResult r = run_leanfade("shaders --lang glsl -o " + shell_quote(out), scratch);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(out.string()), std::string::npos) << r.err;
    EXPECT_EQ(read_text(out), "not a folder");
}

// A shader that does not compile (a syntax error in the shared header of a --shaders folder):
// the error names the file and line, and no output is written, for a language compiled by
// glslang and for plain GLSL alike (its exported text would not compile either: the same check
// is glslang's).
TEST(ShadersCli, ShaderThatDoesNotCompileNamesFileAndLineAndWritesNothing) {
    const fs::path scratch = scratch_dir("shaders_broken");
    const fs::path sources = scratch / "src";
    fs::copy(fs::path(LEANFADE_SOURCE_DIR) / "shaders", sources);
    {
        std::ofstream header(sources / "lean_shading.glsl", std::ios::app);
        header << "this is not GLSL;\n";
    }
    const RunResult r = run_leanfade("shaders --lang spirv --shaders " + shell_quote(sources) +
                                         " -o " + shell_quote(scratch / "out"),
                                     scratch);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find((sources / "lean_shading.glsl").string() + ": line "), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(scratch / "out"));
}

// A second export into the same folder replaces every file with the same bytes (the output is
// a function of the sources only) and leaves no temporary behind.
// (SPIR-V too: the optimiser's output is a function of its input.)
TEST(ShadersCli, ExportIsDeterministicAndReplacesFiles) {
    for (const std::string lang : {"hlsl", "spirv"}) {
        const fs::path scratch = scratch_dir("shaders_twice_" + lang);
        const fs::path out = scratch / "out";
        ASSERT_EQ(
            run_leanfade("shaders --lang " + lang + " -o " + shell_quote(out), scratch).exit_code,
            0);
        std::map<std::string, std::string> first;
        for (const auto& entry : fs::directory_iterator(out))
            first[entry.path().filename().string()] = read_text(entry.path());
        ASSERT_EQ(
            run_leanfade("shaders --lang " + lang + " -o " + shell_quote(out), scratch).exit_code,
            0);
        std::map<std::string, std::string> second;
        for (const auto& entry : fs::directory_iterator(out))
            second[entry.path().filename().string()] = read_text(entry.path());
        EXPECT_EQ(first, second) << lang;
        EXPECT_EQ(second.size(), 2 + scene_variants().size());  // the stages and shaders.json
    }
}

}  // namespace
}  // namespace leanfade::test
