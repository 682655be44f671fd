#pragma once
// The one error type of leanfade: every recoverable failure carries the file it concerns (or a
// short subject such as the name of a setting ("shininess") or "GL") and the cause. Libraries throw it and never exit; each
// subcommand prints what() as one line and returns a non-zero exit code.
#include <stdexcept>
#include <string>

namespace leanfade {

class Error : public std::runtime_error {
public:
    Error(std::string file, std::string cause)
        : std::runtime_error(file.empty() ? cause : file + ": " + cause),
          file_(std::move(file)),
          cause_(std::move(cause)) {}

    const std::string& file() const noexcept { return file_; }
    const std::string& cause() const noexcept { return cause_; }

private:
    std::string file_;
    std::string cause_;
};

}  // namespace leanfade
