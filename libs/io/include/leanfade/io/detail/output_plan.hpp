#pragma once
// The outputs of a run: checked before any work (OutputPlan), then written to temporaries and
// published together (OutputTransaction).
//
// The rule: an output may only create or replace a regular file that is not an input of the same
// run and not another output of it, in a folder that exists and is writable. Anything else (a
// device, FIFO, socket, folder or symbolic link at the output's name, an input, an output named
// twice) is refused before the run reads or writes anything. Every failure throws
// leanfade::Error(output, cause). GL-free.
#include <memory>
#include <string>
#include <vector>

#include "leanfade/core/error.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

namespace leanfade::io {

// True when the file name of `path` ends with `extension` (".png"), in any case, and is longer
// than it (".png" alone is a hidden file without an extension, as std::filesystem has it).
bool has_extension(const std::string& path, const std::string& extension);

class OutputPlan {
  public:
    // A file the run reads. One that does not exist is allowed (reading it fails later, with its
    // own message), but no output may take its name.
    void add_input(const std::string& path);
    // A file the run creates or replaces. `origin` (optional) says what it is the output of, for
    // the message when two outputs have the same name ("the output of b/x.png"). `extension`
    // (optional, ".png"): the run writes this one format there, so the name must end with it
    // (any case); another extension (`-o x.jpg`) is refused instead of holding bytes of another
    // format.
    void add_output(const std::string& path, const std::string& origin = {},
                    const std::string& extension = {});
    // A folder the run writes files into, created (with its missing parents) when missing. The
    // files the run will write there should be added with add_output too; unless
    // `every_file_listed` (each file it writes there is an add_output), the run may write files
    // of names not known beforehand, so no input may lie anywhere inside the folder, and no
    // output file either but those of the folder's own `origin` (the files the run writes into
    // the staged folder, e.g. "the report"): the folder is staged whole and published by a
    // rename, so another output of the run inside it would be staged into the folder replaced.
    void add_output_folder(const std::string& path, bool every_file_listed = false,
                           const std::string& origin = {});

    // Checks every output against the rule (paths resolved: the real path of the folder plus the
    // name; existing files compared by device and inode) and throws for the first that breaks
    // it. Then removes the stale temporaries of every output (remove_stale_temporaries).
    void check() const;

  private:
    struct Output {
        std::string path;
        std::string origin;
        std::string extension;
        bool folder = false;
        bool every_file_listed = false;
    };
    std::vector<std::string> inputs_;
    std::vector<Output> outputs_;
};

// Outputs that belong together, written to temporaries and published together by publish(): each
// temporary is renamed over its output. If a rename fails, the outputs already published are put
// back as they were (the previous files are kept under a second name until the end) and publish()
// throws. If publish() is never reached, the destructor removes every temporary and no output is
// touched. Temporaries are registered for removal on SIGINT, SIGTERM and SIGHUP. Not copyable.
// An output folder that may not exist yet: the constructor creates each missing folder of
// `path` (Error(path, cause) when one cannot be created or a part of it is not a folder); the
// destructor removes again those it created that are still empty, so that a run that fails
// leaves no folder behind and one that wrote its outputs keeps it.
class CreatedFolders {
  public:
    explicit CreatedFolders(const std::string& path);
    ~CreatedFolders();
    CreatedFolders(const CreatedFolders&) = delete;
    CreatedFolders& operator=(const CreatedFolders&) = delete;

  private:
    std::vector<std::string> created_;  // outermost first
};

class OutputTransaction {
  public:
    explicit OutputTransaction(Durability durability = Durability::Rename);
    ~OutputTransaction();
    OutputTransaction(const OutputTransaction&) = delete;
    OutputTransaction& operator=(const OutputTransaction&) = delete;

    // The temporary name (`<path>.tmp-<pid>-<n>`, beside `path`) to write `path` to, with any
    // writer (write_png, AtomicFile, ...). It must have been written by publish().
    std::string stage(const std::string& path);
    // A new empty temporary folder beside `path` (its missing parents are created) to write the
    // files of the folder `path` into. publish() renames it to `path` when `path` does not exist,
    // and otherwise moves each of its files into `path` (replacing files of the same name, keeping
    // the others).
    std::string stage_folder(const std::string& path);

    // Publishes every staged output (see above). Throws leanfade::Error(output, cause).
    void publish();
    // `error` (thrown while writing a staged output) with each temporary name in it replaced by
    // its output's name: messages name the output, never the temporary.
    Error named(const Error& error) const;
    bool published() const noexcept { return published_; }

  private:
    struct Staged;
    Durability durability_;
    std::vector<std::unique_ptr<Staged>> staged_;
    bool published_ = false;
};

}  // namespace leanfade::io
