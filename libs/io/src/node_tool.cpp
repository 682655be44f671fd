// Scripts under Node.js (node_tool.hpp): found relative to the running program, never by a path
// of the build, and started by posix_spawnp with an argument list.
#include "leanfade/io/detail/node_tool.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "leanfade/core/error.hpp"

extern char** environ;

namespace leanfade::io {

namespace fs = std::filesystem;

ScratchFolder::ScratchFolder(const std::string& prefix) {
    std::string pattern = (fs::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr)
        throw Error(fs::temp_directory_path().string(), "cannot make a temporary folder");
    path_ = pattern;
}

ScratchFolder::~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
}

std::string find_node_script(const std::string& file_name) {
    std::error_code error;
    const fs::path program = fs::read_symlink("/proc/self/exe", error);
    if (error) return {};
    const fs::path folder = program.parent_path();
    for (const fs::path& candidate :
         {folder / "node" / file_name, folder / ".." / "share" / "leanfade" / "node" / file_name})
        if (fs::is_regular_file(candidate, error)) return fs::weakly_canonical(candidate).string();
    return {};
}

namespace {

// Starts `node <script> <arguments...>` without a shell, its output into `log_file`.
pid_t spawn_node(const std::string& script, const std::vector<std::string>& arguments,
                 const std::string& log_file, const std::string& setting) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_file.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    std::vector<char*> argv{const_cast<char*>("node"), const_cast<char*>(script.c_str())};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t child = 0;
    const int spawned = ::posix_spawnp(&child, "node", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0)
        throw Error::setting(setting,
                             spawned == ENOENT
                                 ? "needs Node.js, and `node` is not on the PATH (Debian package "
                                   "nodejs)"
                                 : "cannot start Node.js");
    return child;
}

int wait_for(pid_t child) {
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

int run_node_script(const std::string& script, const std::vector<std::string>& arguments,
                    const std::string& log_file, const std::string& setting) {
    return wait_for(spawn_node(script, arguments, log_file, setting));
}

std::vector<int> run_node_scripts(const std::string& script,
                                  const std::vector<std::vector<std::string>>& arguments,
                                  const std::vector<std::string>& log_files,
                                  const std::string& setting) {
    std::vector<pid_t> children;
    std::vector<int> statuses;
    try {
        for (std::size_t i = 0; i < arguments.size(); ++i)
            children.push_back(spawn_node(script, arguments[i], log_files.at(i), setting));
    } catch (...) {
        for (const pid_t child : children) wait_for(child);  // none left behind
        throw;
    }
    for (const pid_t child : children) statuses.push_back(wait_for(child));
    return statuses;
}

std::string first_line_of(const std::string& file) {
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);
    return line;
}

}  // namespace leanfade::io
