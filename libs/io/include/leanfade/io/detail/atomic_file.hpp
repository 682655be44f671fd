#pragma once
// All-or-nothing file output. Every leanfade writer goes through AtomicFile, so a reader never sees
// a half-written file and a failed write leaves the previous file (or no file) in place.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace leanfade::io {

// How far commit() goes before it returns.
enum class Durability {
    // Close and rename: readers (and a crashed or killed writer) never see a partial file. Like
    // most asset tools, no fsync: after a power cut the kernel may not have written the data yet.
    Rename,
    // fsync the file before the rename and the folder after it: the new file survives a power cut.
    Flush,
};

// `<path>.tmp-<pid>-<counter>-<run id>`: a new temporary name beside `path`, unique in this
// process. Every temporary of leanfade is named so (AtomicFile, OutputTransaction), which is what
// remove_stale_temporaries recognises.
std::string temporary_path_for(const std::string& path);
// The 8 hexadecimal digits that say where a process id means this process's: a hash of the
// kernel's boot id, the PID namespace and the host name. A pid in a temporary of another run id
// belongs to another machine, container or boot (a shared volume, NFS), where kill(pid, 0) here
// says nothing about it.
const std::string& temporary_run_id();
// Age after which a temporary whose process cannot be asked (another run id, or a name without
// one) is stale whatever its process: a day, as for the LEAN-map cache's temporaries.
inline constexpr int kStaleForeignTemporarySeconds = 24 * 3600;

// Live temporaries, removed if the process is killed by SIGINT, SIGTERM or SIGHUP (see
// remove_temporaries_on_signals). A registration holds the path in memory allocated beforehand,
// so that the signal handler only calls unlink (or, for a folder, removes its files). AtomicFile
// and OutputTransaction register their temporaries themselves. Move-only.
class TemporaryRegistration {
  public:
    TemporaryRegistration() = default;
    explicit TemporaryRegistration(const std::string& path, bool folder = false);
    ~TemporaryRegistration() { release(); }
    TemporaryRegistration(TemporaryRegistration&& other) noexcept : slot_(other.slot_) {
        other.slot_ = nullptr;
    }
    TemporaryRegistration& operator=(TemporaryRegistration&& other) noexcept;
    TemporaryRegistration(const TemporaryRegistration&) = delete;
    TemporaryRegistration& operator=(const TemporaryRegistration&) = delete;
    // The path is no longer removed on a signal (it was renamed or removed).
    void release() noexcept;

  private:
    void* slot_ = nullptr;
};

// Installs handlers for SIGINT, SIGTERM and SIGHUP (those not ignored) that remove every
// registered temporary, then restore the default action and raise the signal again, so that the
// process ends as it would have without the handler. Async-signal-safe: unlink, openat, getdents64,
// unlinkat, close, sigaction and raise on preallocated paths. The portable build
// (leanfade/core/detail/platform.hpp) removes a registered folder only when it is empty; what it holds
// is left to remove_stale_temporaries. Also ignores SIGXFSZ: a write beyond the file size limit
// (`ulimit -f`) then fails with EFBIG, which the writers report as one line naming the output
// and clean up after, instead of killing the process with its temporaries left behind. Call
// once, early in main().
void remove_temporaries_on_signals();

// Removes the temporaries `<name>.tmp-<pid>-<n>-<run id>...` of `path` (name: its file name) left
// in its folder by runs that were killed (SIGKILL, a power cut): those owned by this user whose
// run id is this process's and whose process <pid> is no longer running, and those of another
// run id (or none) once they are older than kStaleForeignTemporarySeconds (a live run in another
// PID namespace or on another host keeps its temporaries). Files of running processes, of other
// users and other names are kept. Returns how many were removed; never throws.
std::size_t remove_stale_temporaries(const std::string& path) noexcept;

// Writes to a temporary file `<path>.tmp-<pid>-<counter>` in the target's folder; commit() closes
// it (after an fsync with Durability::Flush) and renames it over `path`, which atomically replaces
// any existing file. If commit() is never reached (an exception, an early return) the destructor
// removes the temporary, and so does a SIGINT, SIGTERM or SIGHUP once remove_temporaries_on_signals
// is installed. Failures throw leanfade::Error(path, cause). Not copyable, not movable.
class AtomicFile {
  public:
    // Creates the temporary file (mode 0666 minus the umask). Throws if it cannot be created, for
    // example when the folder does not exist or is not writable.
    explicit AtomicFile(std::string path, Durability durability = Durability::Rename);
    ~AtomicFile();

    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    // Appends bytes to the temporary file. Throws on a write error (disk full, ...).
    void write(const void* data, std::size_t size);
    void write(const std::vector<std::uint8_t>& bytes) { write(bytes.data(), bytes.size()); }
    // Overwrites bytes already written (e.g. a header whose fields are known last): [offset,
    // offset + size) must lie inside what write() has written. Throws on a write error.
    void write_at(std::uint64_t offset, const void* data, std::size_t size);

    // Sizes the temporary file to exactly `size` bytes, with its disk space reserved (so that a
    // full disk is an error here, not a crash later), and maps it into memory for writing: the
    // caller fills the returned bytes (from several threads if it likes) instead of calling
    // write(). For large outputs this avoids a copy through write() and lets the page cache be
    // filled in parallel. Only once per file, and not after write(). Throws on failure ("cannot
    // reserve N bytes (No space left on device)").
    std::uint8_t* map(std::size_t size);

    // Fills the temporary file with the bytes of the regular file `source`, which must hold
    // exactly `size` bytes: in the kernel, with the blocks shared where the file system can
    // (leanfade/core/detail/platform.hpp, copy_file_contents). Only once per file, and not after write()
    // or map(). Throws Error(source, cause) when the source is missing, not a regular file or of
    // another size, Error(path, cause) when the copy fails.
    void copy_from(const std::string& source, std::uint64_t size);
    // [fsync] + close + rename over the target [+ fsync of the folder] (brackets: Flush only).
    // Unmaps a map()ped file first. Throws on failure (the temporary is then removed by the
    // destructor). Calling write(), map() or commit() afterwards throws.
    void commit();

    const std::string& path() const noexcept { return path_; }
    const std::string& temporary_path() const noexcept { return temporary_path_; }
    bool committed() const noexcept { return committed_; }

  private:
    std::string path_;
    std::string temporary_path_;
    Durability durability_ = Durability::Rename;
    int descriptor_ = -1;
    bool committed_ = false;
    bool written_ = false;
    std::uint8_t* mapping_ = nullptr;
    std::size_t mapping_size_ = 0;
    TemporaryRegistration registration_;
};

// Throws leanfade::Error(output, "is the same file as the input <input>") when both paths exist and
// name the same file (hard links, symbolic links and different spellings included). Call it before
// writing an output derived from an input. Does nothing when either path does not exist.
void ensure_not_same_file(const std::string& output, const std::string& input);

}  // namespace leanfade::io
