#pragma once
// Runs the leanfade executable as a user would and captures its exit code and output.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace leanfade::test {

// The resident-memory bound of a run of leanfade, KiB: `kib` for an ordinary build, twice that
// when the suite runs under `make sanitize` (AddressSanitizer's shadow memory and quarantine grow
// every process; LEANFADE_TEST_SANITIZED, set by tests/CMakeLists.txt).
inline long memory_bound_kib(long kib) {
#if defined(LEANFADE_TEST_SANITIZED)
    return 2 * kib;
#else
    return kib;
#endif
}

struct RunResult {
    int exit_code = -1;
    std::string out;        // stdout
    std::string err;        // stderr
    long max_rss_kib = -1;  // run_leanfade_bounded: peak resident memory of the process tree
};

inline std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// The `env` prefix of a command whose LEAN-map cache is the folder `dir`/cache.
inline std::string cache_env(const std::filesystem::path& dir) {
    return "env XDG_CACHE_HOME=" + shell_quote((dir / "cache").string());
}

inline std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Runs `leanfade ARGS` from the shell, stdout and stderr into `scratch`, no stdin. `prefix` comes
// before the executable (e.g. "env NAME=value", "env -u DISPLAY" or an xvfb-run command line) and
// `working_dir`, when given, is the folder it runs in. args are passed verbatim after the
// executable (already quoted where needed).
inline RunResult run_leanfade_in(const std::string& args, const std::filesystem::path& scratch,
                                 const std::filesystem::path& working_dir = {},
                                 const std::string& prefix = "") {
    const auto out = scratch / "stdout.txt", err = scratch / "stderr.txt";
    std::string cmd;
    if (!working_dir.empty()) cmd = "cd " + shell_quote(working_dir.string()) + " && ";
    if (!prefix.empty()) cmd += prefix + " ";
    cmd += shell_quote(LEANFADE_EXE) + " " + args + " >" + shell_quote(out.string()) + " 2>" +
           shell_quote(err.string()) + " </dev/null";
    const int status = std::system(cmd.c_str());
    RunResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = read_text(out);
    r.err = read_text(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
}

inline RunResult run_leanfade(const std::string& args, const std::filesystem::path& scratch) {
    return run_leanfade_in(args, scratch);
}

// run_leanfade with bounds, for hostile inputs: the run is killed after `seconds` (exit code 124,
// or 137 when it ignores SIGTERM for 5 more seconds), so a hang fails the test instead of
// blocking it, and max_rss_kib reports the largest resident set of the run (wait4), so that a
// test can check that a small hostile file did not make leanfade allocate without bound.
inline RunResult run_leanfade_bounded(const std::string& args, const std::filesystem::path& scratch,
                                      int seconds = 20) {
    const auto out = scratch / "stdout.txt", err = scratch / "stderr.txt";
    const std::string cmd = "timeout -k 5 " + std::to_string(seconds) + " " +
                            shell_quote(LEANFADE_EXE) + " " + args + " >" +
                            shell_quote(out.string()) + " 2>" + shell_quote(err.string()) +
                            " </dev/null";
    RunResult r;
    const pid_t child = ::fork();
    if (child == 0) {
        ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    if (child < 0) return r;
    int status = 0;
    struct rusage usage {};
    while (::wait4(child, &status, 0, &usage) < 0) {
        if (errno != EINTR) return r;
    }
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.max_rss_kib = usage.ru_maxrss;
    r.out = read_text(out);
    r.err = read_text(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
}

}  // namespace leanfade::test
