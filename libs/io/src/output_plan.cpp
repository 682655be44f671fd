#include "leanfade/io/detail/output_plan.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <system_error>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"

namespace leanfade::io {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int error_number) {
    return std::strerror(error_number);
}

// What stands at a path, for the messages.
std::string kind_of(mode_t mode) {
    if (S_ISREG(mode)) return "a regular file";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISLNK(mode)) return "a symbolic link";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "of an unknown type";
}

std::string not_regular_cause(mode_t mode) {
    if (S_ISDIR(mode)) return "is a directory; an output must be a file name";
    return "is " + kind_of(mode) + "; an output may only create or replace a regular file";
}

fs::path folder_of(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? fs::path(".") : parent;
}

// The path with its folder resolved (symbolic links, "..", "."), for comparisons.
std::string resolved(const std::string& path) {
    std::error_code error;
    const fs::path p(path);
    fs::path folder = fs::weakly_canonical(fs::absolute(folder_of(path), error), error);
    if (error) folder = fs::absolute(folder_of(path)).lexically_normal();
    return (folder / p.filename()).lexically_normal().string();
}

struct FileId {
    dev_t device = 0;
    ino_t inode = 0;
    bool operator==(const FileId&) const = default;
};

std::optional<FileId> file_id(const std::string& path, bool follow) {
    struct stat info {};
    const int result = follow ? ::stat(path.c_str(), &info) : ::lstat(path.c_str(), &info);
    if (result != 0) return std::nullopt;
    return FileId{info.st_dev, info.st_ino};
}

// The nearest folder of `path` (itself or a parent) that exists: it must be a writable folder.
void check_writable_folder(const std::string& output, const fs::path& folder, bool created) {
    struct stat info {};
    if (::stat(folder.c_str(), &info) != 0) {
        if ((errno == ENOENT) && created) {
            const fs::path parent = folder.has_parent_path() && folder.parent_path() != folder
                                        ? folder.parent_path()
                                        : fs::path(".");
            check_writable_folder(output, parent, true);
            return;
        }
        throw Error(output, "its folder " + folder.string() +
                                (errno == ENOENT ? " does not exist"
                                                 : " cannot be used (" + errno_text(errno) + ")"));
    }
    if (!S_ISDIR(info.st_mode)) throw Error(output, folder.string() + " is not a folder");
    if (::access(folder.c_str(), W_OK | X_OK) != 0) {
        throw Error(output, "its folder " + folder.string() + " is not writable (" +
                                errno_text(errno) + ")");
    }
}

bool inside(const std::string& path, const std::string& folder) {
    if (path.size() <= folder.size() || path.compare(0, folder.size(), folder) != 0) return false;
    return path[folder.size()] == '/' || folder.back() == '/';
}

void fsync_folder(const fs::path& folder) {
    const int descriptor = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (descriptor < 0) return;
    ::fsync(descriptor);
    ::close(descriptor);
}

// ".png" -> "PNG".
std::string format_of(const std::string& extension) {
    std::string format;
    for (char c : extension)
        if (c != '.') format += char(std::toupper(static_cast<unsigned char>(c)));
    return format;
}

}  // namespace

void OutputPlan::add_input(const std::string& path) {
    if (!path.empty()) inputs_.push_back(path);
}

void OutputPlan::add_output(const std::string& path, const std::string& origin,
                            const std::string& extension) {
    outputs_.push_back({path, origin, extension, false});
}

void OutputPlan::add_output_folder(const std::string& path, bool every_file_listed,
                                   const std::string& origin) {
    outputs_.push_back({path, origin, {}, true, every_file_listed});
}

void OutputPlan::check() const {
    struct Input {
        std::string path;
        std::string key;
        std::optional<FileId> id;
    };
    std::vector<Input> inputs;
    for (const std::string& path : inputs_)
        inputs.push_back({path, resolved(path), file_id(path, true)});

    struct Folder {
        std::string key;
        const Output* output;
    };
    std::vector<Folder> folders;
    for (const Output& output : outputs_) {
        if (!output.folder) continue;
        if (output.path.empty()) throw Error("", "an output folder name is empty");
        struct stat info {};
        if (::stat(output.path.c_str(), &info) == 0) {
            if (!S_ISDIR(info.st_mode))
                throw Error(output.path, "is " + kind_of(info.st_mode) + ", not a folder");
            check_writable_folder(output.path, output.path, false);
        } else if (errno == ENOENT) {
            check_writable_folder(output.path, folder_of(output.path), true);
        } else {
            throw Error(output.path, "cannot be used as a folder (" + errno_text(errno) + ")");
        }
        std::error_code error;
        std::string key = fs::weakly_canonical(fs::absolute(output.path), error).string();
        if (error) key = fs::absolute(output.path).lexically_normal().string();
        while (key.size() > 1 && key.back() == '/') key.pop_back();
        for (const Input& input : inputs) {
            if (input.key == key)
                throw Error(output.path, "is the same file as the input " + input.path +
                                             " of this run; an output may not replace an input");
            if (!output.every_file_listed && inside(input.key, key))
                throw Error(output.path, "holds the input " + input.path +
                                             " of this run; the run writes files into this "
                                             "folder, which may not hold its inputs");
        }
        folders.push_back({key, &output});
    }

    std::vector<std::pair<std::string, const Output*>> keys;
    for (const Output& output : outputs_) {
        if (output.folder) continue;
        const std::string& path = output.path;
        if (path.empty()) throw Error("", "an output file name is empty");
        struct stat info {};
        std::optional<FileId> id;
        if (::lstat(path.c_str(), &info) == 0) {
            if (!S_ISREG(info.st_mode)) throw Error(path, not_regular_cause(info.st_mode));
            id = FileId{info.st_dev, info.st_ino};
        } else if (errno == ENOTDIR) {
            throw Error(path, "its folder " + folder_of(path).string() + " is not a folder");
        } else if (errno != ENOENT) {
            throw Error(path, "cannot be used as an output (" + errno_text(errno) + ")");
        }
        const std::string name = fs::path(path).filename().string();
        if (name.empty() || name == "." || name == "..")
            throw Error(path, "names a folder; an output must be a file name");
        const std::string key = resolved(path);
        bool in_output_folder = false;
        for (const Folder& folder : folders) {
            if (!inside(key, folder.key)) continue;
            in_output_folder = true;
            // A folder of files not known beforehand is staged whole and renamed into place:
            // another output of the run inside it would be staged into the folder the rename
            // replaces.
            if (!folder.output->every_file_listed &&
                (folder.output->origin.empty() || folder.output->origin != output.origin))
                throw Error(path, "is inside " + folder.output->path +
                                      ", a folder this run writes whole; an output may not lie "
                                      "inside it");
        }
        if (!in_output_folder) check_writable_folder(path, folder_of(path), false);
        for (const Input& input : inputs) {
            if (input.key == key || (id && input.id && *id == *input.id)) {
                throw Error(path,
                            (input.path == path
                                 ? std::string("is the same file as an input of this run")
                                 : "is the same file as the input " + input.path + " of this run") +
                                "; an output may not replace an input");
            }
        }
        for (const auto& [other_key, other] : keys) {
            if (other_key != key) continue;
            std::string cause = "is written twice by this run";
            if (!other->origin.empty() && !output.origin.empty() && other->origin != output.origin)
                cause += " (as " + other->origin + " and as " + output.origin + ")";
            else if (other->path != path)
                cause += " (also as " + other->path + ")";
            throw Error(path, cause);
        }
        // After the inputs: replacing one is the graver cause.
        if (!output.extension.empty() && !has_extension(name, output.extension))
            throw Error(path, "is written as a " + format_of(output.extension) + " file; name it " +
                                  "with " + output.extension + " (leanfade writes no other " +
                                  "format there" +
                                  (fs::path(name).extension().empty()
                                       ? std::string()
                                       : ", and " + fs::path(name).extension().string() +
                                             " would hold " + format_of(output.extension) +
                                             " bytes") +
                                  ")");
        keys.emplace_back(key, &output);
    }
    // Every existing file the run may replace is claimed: a reader that opens one of them later
    // (a file another input names, which no list of inputs above knew) refuses it before reading
    // (input_text.hpp, claim_output_file).
    for (const Output& output : outputs_) {
        struct stat info {};
        if (!output.folder) {
            if (::lstat(output.path.c_str(), &info) == 0 && S_ISREG(info.st_mode))
                claim_output_file(info.st_dev, info.st_ino, output.path);
            continue;
        }
        // A folder whose every file is listed: those are claimed above. Another may have any
        // of its files replaced.
        if (output.every_file_listed) continue;
        std::error_code error;
        for (fs::directory_iterator it(output.path, error), end; !error && it != end;
             it.increment(error))
            if (::lstat(it->path().c_str(), &info) == 0 && S_ISREG(info.st_mode))
                claim_output_file(info.st_dev, info.st_ino, it->path().string());
    }
    for (const Output& output : outputs_) remove_stale_temporaries(output.path);
}

CreatedFolders::CreatedFolders(const std::string& path) {
    if (path.empty()) return;
    std::vector<fs::path> missing;
    std::error_code error;
    for (fs::path p = fs::path(path).lexically_normal(); !p.empty(); p = p.parent_path()) {
        const fs::file_status status = fs::symlink_status(p, error);
        if (status.type() != fs::file_type::not_found) {
            if (!fs::is_directory(p, error))
                throw Error(path, p == fs::path(path).lexically_normal()
                                      ? "is not a folder"
                                      : p.string() + " is not a folder");
            break;
        }
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST) {
            const std::string reason = std::strerror(errno);
            for (auto made = created_.rbegin(); made != created_.rend(); ++made)
                ::rmdir(made->c_str());
            throw Error(path,
                        "cannot create the output folder " + it->string() + " (" + reason + ")");
        }
        created_.push_back(it->string());
    }
}

CreatedFolders::~CreatedFolders() {
    for (auto it = created_.rbegin(); it != created_.rend(); ++it) ::rmdir(it->c_str());
    created_.clear();
}

// One staged output: a temporary file or folder, and where it goes.
struct OutputTransaction::Staged {
    std::string target;
    std::string temporary;
    bool folder = false;
    TemporaryRegistration registration;
};

OutputTransaction::OutputTransaction(Durability durability) : durability_(durability) {}

OutputTransaction::~OutputTransaction() {
    if (published_) return;
    for (const auto& staged : staged_) {
        std::error_code error;
        if (staged->folder)
            fs::remove_all(staged->temporary, error);
        else
            ::unlink(staged->temporary.c_str());
        staged->registration.release();
    }
}

std::string OutputTransaction::stage(const std::string& path) {
    if (published_) throw Error(path, "staged after the outputs were published");
    if (path.empty()) throw Error("", "an output file name is empty");
    auto staged = std::make_unique<Staged>();
    staged->target = path;
    staged->temporary = temporary_path_for(path);
    staged->registration = TemporaryRegistration(staged->temporary);
    staged_.push_back(std::move(staged));
    return staged_.back()->temporary;
}

Error OutputTransaction::named(const Error& error) const {
    std::vector<const Staged*> longest_first;
    for (const auto& staged : staged_) longest_first.push_back(staged.get());
    std::sort(longest_first.begin(), longest_first.end(), [](const Staged* a, const Staged* b) {
        return a->temporary.size() > b->temporary.size();
    });
    std::string file = error.file(), cause = error.cause();
    for (std::string* text : {&file, &cause})
        for (const Staged* staged : longest_first)
            for (std::size_t at = text->find(staged->temporary); at != std::string::npos;
                 at = text->find(staged->temporary, at + staged->target.size()))
                text->replace(at, staged->temporary.size(), staged->target);
    return Error(error.kind(), file, cause, error.mentioned_settings());
}

std::string OutputTransaction::stage_folder(const std::string& path) {
    if (published_) throw Error(path, "staged after the outputs were published");
    std::string target = path;
    while (target.size() > 1 && target.back() == '/') target.pop_back();
    if (target.empty()) throw Error("", "an output folder name is empty");
    std::error_code error;
    const fs::path parent = fs::path(target).parent_path();
    if (!parent.empty()) fs::create_directories(parent, error);
    auto staged = std::make_unique<Staged>();
    staged->target = target;
    staged->folder = true;
    staged->temporary = temporary_path_for(target);
    staged->registration = TemporaryRegistration(staged->temporary, true);
    if (::mkdir(staged->temporary.c_str(), 0777) != 0) {
        throw Error(target, "cannot create the temporary folder " + staged->temporary + " (" +
                                errno_text(errno) + ")");
    }
    staged_.push_back(std::move(staged));
    return staged_.back()->temporary;
}

void OutputTransaction::publish() {
    if (published_) throw Error("", "outputs published twice");
    // Every rename to do: the temporary, the output, and whether it is a whole folder.
    struct Move {
        std::string from;
        std::string to;
        bool folder = false;
        std::string backup;  // a second name of the file it replaces, kept until the end
        TemporaryRegistration backup_registration;
        bool done = false;
    };
    std::vector<Move> moves;
    auto add_move = [&moves](std::string from, std::string to, bool folder) {
        Move move;
        move.from = std::move(from);
        move.to = std::move(to);
        move.folder = folder;
        moves.push_back(std::move(move));
    };
    std::vector<std::string> folders_to_create;
    for (const auto& staged : staged_) {
        struct stat info {};
        if (!staged->folder) {
            if (::lstat(staged->temporary.c_str(), &info) != 0)
                throw Error(staged->target, "was not written");
            add_move(staged->temporary, staged->target, false);
            continue;
        }
        if (::lstat(staged->target.c_str(), &info) != 0 && errno == ENOENT) {
            add_move(staged->temporary, staged->target, true);
            continue;
        }
        // An existing folder: each file goes into it.
        std::error_code error;
        for (fs::recursive_directory_iterator it(staged->temporary, error), end;
             !error && it != end; it.increment(error)) {
            const fs::path relative = fs::relative(it->path(), staged->temporary);
            const std::string to = (fs::path(staged->target) / relative).string();
            if (it->is_directory()) {
                folders_to_create.push_back(to);
            } else {
                add_move(it->path().string(), to, false);
            }
        }
        if (error)
            throw Error(staged->temporary, "cannot list the folder (" + error.message() + ")");
    }
    // Check every output before the first rename.
    for (const std::string& folder : folders_to_create) {
        struct stat info {};
        if (::stat(folder.c_str(), &info) == 0 && !S_ISDIR(info.st_mode))
            throw Error(folder, "is " + kind_of(info.st_mode) + ", not a folder");
    }
    for (const Move& move : moves) {
        struct stat info {};
        if (move.folder) continue;
        if (::lstat(move.to.c_str(), &info) == 0 && !S_ISREG(info.st_mode))
            throw Error(move.to, not_regular_cause(info.st_mode));
    }

    std::vector<std::string> created;
    auto roll_back = [&] {
        for (auto it = moves.rbegin(); it != moves.rend(); ++it) {
            if (!it->done) continue;
            if (!it->backup.empty())
                std::rename(it->backup.c_str(), it->to.c_str());
            else
                std::rename(it->to.c_str(), it->from.c_str());
        }
        for (auto it = created.rbegin(); it != created.rend(); ++it) ::rmdir(it->c_str());
    };
    for (const std::string& folder : folders_to_create) {
        if (::mkdir(folder.c_str(), 0777) == 0) {
            created.push_back(folder);
        } else if (errno != EEXIST) {
            const int error_number = errno;
            roll_back();
            throw Error(folder, "cannot create the folder (" + errno_text(error_number) + ")");
        }
    }
    for (Move& move : moves) {
        struct stat info {};
        if (!move.folder && ::lstat(move.to.c_str(), &info) == 0 && S_ISREG(info.st_mode)) {
            std::string backup = temporary_path_for(move.to);
            TemporaryRegistration registration(backup);
            if (::link(move.to.c_str(), backup.c_str()) == 0) {
                move.backup = std::move(backup);
                move.backup_registration = std::move(registration);
            }
        }
        if (std::rename(move.from.c_str(), move.to.c_str()) != 0) {
            const int error_number = errno;
            if (!move.backup.empty()) ::unlink(move.backup.c_str());
            move.backup.clear();
            roll_back();
            for (Move& other : moves)
                if (!other.backup.empty()) ::unlink(other.backup.c_str());
            throw Error(move.to, "cannot replace the file (" + errno_text(error_number) + ")");
        }
        move.done = true;
    }
    published_ = true;
    for (Move& move : moves) {
        if (!move.backup.empty()) ::unlink(move.backup.c_str());
        move.backup_registration.release();
    }
    for (const auto& staged : staged_) {
        std::error_code error;
        if (staged->folder) fs::remove_all(staged->temporary, error);  // what is left: folders
        staged->registration.release();
        if (durability_ == Durability::Flush) fsync_folder(folder_of(staged->target));
    }
}

bool has_extension(const std::string& path, const std::string& extension) {
    // The file name's: a name that is only the extension (".png") is a hidden file without one.
    const std::string name = fs::path(path).filename().string();
    if (name.size() <= extension.size()) return false;
    for (std::size_t i = 0; i < extension.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(name[name.size() - extension.size() + i])) !=
            std::tolower(static_cast<unsigned char>(extension[i])))
            return false;
    return true;
}

}  // namespace leanfade::io
