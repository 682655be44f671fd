// SPIR-V -> WGSL by naga (npm package naga-wasm) under Node.js: the translator script
// (tools/wgsl/spirv_to_wgsl.mjs, installed as share/leanfade/wgsl/) run once over a private
// temporary folder, without a shell: its arguments are the script and two folders this function
// made.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/gl/shader_export.hpp"

extern char** environ;

namespace leanfade::gl {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTranslatorFile = "spirv_to_wgsl.mjs";

// A folder of its own under the system's temporary folder, removed with everything in it.
class TemporaryFolder {
  public:
    TemporaryFolder() {
        std::string pattern = (fs::temp_directory_path() / "leanfade-wgsl-XXXXXX").string();
        if (::mkdtemp(pattern.data()) == nullptr)
            throw Error(fs::temp_directory_path().string(),
                        "cannot make a temporary folder for the WGSL translation");
        path_ = pattern;
    }
    ~TemporaryFolder() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    const fs::path& path() const { return path_; }

  private:
    fs::path path_;
};

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

std::string find_wgsl_translator() {
    std::error_code error;
    const fs::path program = fs::read_symlink("/proc/self/exe", error);
    if (error) return {};
    const fs::path folder = program.parent_path();
    for (const fs::path& candidate :
         {folder / "wgsl" / kTranslatorFile,
          folder / ".." / "share" / "leanfade" / "wgsl" / kTranslatorFile}) {
        if (fs::is_regular_file(candidate, error)) return fs::weakly_canonical(candidate).string();
    }
    return {};
}

std::vector<WgslTranslation> translate_spirv_to_wgsl(
    const std::vector<std::vector<std::uint32_t>>& modules, const std::vector<std::string>& names,
    const std::string& translator) {
    const TemporaryFolder scratch;
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
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    const std::string in_text = in.string(), out_text = out.string();
    std::vector<char*> argv{const_cast<char*>("node"), const_cast<char*>(translator.c_str()),
                            const_cast<char*>(in_text.c_str()), const_cast<char*>(out_text.c_str()),
                            nullptr};
    pid_t child = 0;
    const int spawned = ::posix_spawnp(&child, "node", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0)
        throw Error("lang", spawned == ENOENT
                                ? "WGSL is translated under Node.js, and `node` is not on the PATH "
                                  "(Debian package nodejs)"
                                : "cannot start Node.js for the WGSL translation");
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::string message = read_all(log);
        message = message.substr(0, message.find('\n'));
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
