#pragma once
// leanfade's scripts that run under Node.js with npm packages pinned by a lockfile (tools/node:
// the WGSL translator, naga; the Basis Universal encoder), found beside the running program:
// <its folder>/node/ in a build tree, <its folder>/../share/leanfade/node/ when installed.
#include <filesystem>
#include <string>
#include <vector>

namespace leanfade::io {

// A private folder under the system's temporary folder (mkdtemp), removed with its contents:
// where a script's inputs and outputs are exchanged. Throws leanfade::Error when it cannot be
// made.
class ScratchFolder {
  public:
    explicit ScratchFolder(const std::string& prefix = "leanfade");
    ~ScratchFolder();
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    const std::filesystem::path& path() const { return path_; }

  private:
    std::filesystem::path path_;
};

// The script `file_name` ("spirv_to_wgsl.mjs") beside the running program, or "" when neither
// place has it.
std::string find_node_script(const std::string& file_name);

// Runs `node <script> <arguments...>` without a shell (the arguments are passed as they are),
// its standard output and error into `log_file`, and waits. Returns the exit status (0 on
// success). Throws leanfade::Error(setting, cause) when Node.js is not on the PATH or cannot be
// started.
int run_node_script(const std::string& script, const std::vector<std::string>& arguments,
                    const std::string& log_file, const std::string& setting);

// Runs `node <script> <arguments[i]...>` for every i at once (one process each, as
// run_node_script), each with its own log file, and waits for all. Returns their exit statuses.
std::vector<int> run_node_scripts(const std::string& script,
                                  const std::vector<std::vector<std::string>>& arguments,
                                  const std::vector<std::string>& log_files,
                                  const std::string& setting);

// The first line of a file (a script's message), "" when it cannot be read.
std::string first_line_of(const std::string& file);

}  // namespace leanfade::io
