// SPIR-V -> WGSL by naga (npm package naga-wasm) under Node.js: the translator script
// (tools/node/spirv_to_wgsl.mjs, installed in share/leanfade/node/) run once over a private
// temporary folder, without a shell: its arguments are two folders this function made.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/gl/detail/shader_export.hpp"
#include "leanfade/io/detail/node_tool.hpp"

namespace leanfade::gl {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTranslatorFile = "spirv_to_wgsl.mjs";

std::string read_all(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string module_file(std::size_t index) {
    char name[32];
    std::snprintf(name, sizeof name, "%05zu", index);
    return name;
}

}  // namespace

std::string find_wgsl_translator() { return io::find_node_script(kTranslatorFile); }

std::vector<WgslTranslation> translate_spirv_to_wgsl(
    const std::vector<std::vector<std::uint32_t>>& modules, const std::vector<std::string>& names,
    const std::string& translator) {
    const io::ScratchFolder scratch("leanfade-wgsl");
    const fs::path in = scratch.path() / "spirv", out = scratch.path() / "wgsl";
    fs::create_directories(in);
    fs::create_directories(out);
    for (std::size_t i = 0; i < modules.size(); ++i) {
        std::ofstream file(in / (module_file(i) + ".spv"), std::ios::binary);
        file.write(reinterpret_cast<const char*>(modules[i].data()),
                   std::streamsize(modules[i].size() * sizeof(std::uint32_t)));
        if (!file) throw Error(in.string(), "cannot write a SPIR-V module for the translation");
    }
    const std::string log = (scratch.path() / "node.log").string();
    const int status =
        io::run_node_script(translator, {in.string(), out.string()}, log, "lang");
    if (status != 0) {
        const std::string message = io::first_line_of(log);
        throw Error(translator, "the WGSL translator failed: " +
                                    (message.empty() ? std::string("no message") : message));
    }
    std::vector<WgslTranslation> texts(modules.size());
    for (std::size_t i = 0; i < modules.size(); ++i) {
        const fs::path file = out / (module_file(i) + ".wgsl");
        const fs::path refused = out / (module_file(i) + ".refused");
        std::error_code error;
        if (fs::is_regular_file(file, error)) {
            texts[i].text = read_all(file);
        } else if (fs::is_regular_file(refused, error)) {
            std::string reason = read_all(refused);
            texts[i].refused = reason.substr(0, reason.find('\n'));
        } else {
            throw Error(translator, "the translator wrote no WGSL for " + names[i]);
        }
    }
    return texts;
}

}  // namespace leanfade::gl
