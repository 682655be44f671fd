#pragma once
// The one error type of leanfade. Every recoverable failure carries what it concerns, as a kind
// to switch on and a subject, and the cause in words:
// - ErrorKind::File: a file read or written (missing, unreadable, malformed, refused, not
//   writable), or a subject that is neither a file nor a setting ("GL", "EGL", "scene");
//   file() is its path or that subject.
// - ErrorKind::Setting: a setting's value, or settings that do not go together; setting() is its
//   id, as the libraries name settings ("shininess", "roughness-map", "layer-weights"), never a
//   flag.
// A cause that names other settings quotes each id ('strict_normals') and lists it in
// mentioned_settings(), so that a caller can word them its own way (the command line maps ids to
// flags, cli::with_flag_name) without reading the sentence. Libraries throw it and never exit;
// each subcommand prints what() as one line and returns a non-zero exit code.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace leanfade {

enum class ErrorKind {
    File,     // a file, or a subject that is no setting: file()
    Setting,  // a setting: setting()
};

class Error : public std::runtime_error {
public:
    // An error about `file` (its path, or a subject such as "GL"), of kind File.
    Error(std::string file, std::string cause)
        : Error(ErrorKind::File, std::move(file), std::move(cause), {}) {}

    // An error about the setting `id` (kind Setting); `mentioned` lists the other settings the
    // cause quotes ('id').
    static Error setting(std::string id, std::string cause,
                         std::vector<std::string> mentioned = {}) {
        return Error(ErrorKind::Setting, std::move(id), std::move(cause), std::move(mentioned));
    }

    // An error about `file` whose cause quotes the settings `mentioned` (kind File).
    static Error file_mentioning(std::string file, std::string cause,
                                 std::vector<std::string> mentioned) {
        return Error(ErrorKind::File, std::move(file), std::move(cause), std::move(mentioned));
    }

    // Of any kind: `subject` is the file or the setting id.
    Error(ErrorKind kind, std::string subject, std::string cause,
          std::vector<std::string> mentioned)
        : std::runtime_error(subject.empty() ? cause : subject + ": " + cause),
          kind_(kind),
          subject_(std::move(subject)),
          cause_(std::move(cause)),
          mentioned_(std::move(mentioned)) {}

    ErrorKind kind() const noexcept { return kind_; }
    // What what() names first: the file (kind File) or the setting's id (kind Setting).
    const std::string& file() const noexcept { return subject_; }
    // The setting's id for kind Setting, "" otherwise.
    const std::string& setting() const noexcept {
        static const std::string none;
        return kind_ == ErrorKind::Setting ? subject_ : none;
    }
    const std::string& cause() const noexcept { return cause_; }
    // The settings the cause quotes by id ('strict_normals'), in the order written.
    const std::vector<std::string>& mentioned_settings() const noexcept { return mentioned_; }

private:
    ErrorKind kind_;
    std::string subject_;
    std::string cause_;
    std::vector<std::string> mentioned_;
};

}  // namespace leanfade
