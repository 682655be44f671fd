// The registry of live temporaries, its signal handler, and the removal of stale temporaries.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <new>
#include <string>
#include <system_error>

#include "leanfade/core/detail/platform.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

namespace leanfade::io {
namespace {

// One registered path. state: 0 free, 1 being filled (skipped by the handler), 2 live.
struct Slot {
    std::atomic<int> state{0};
    char* path = nullptr;  // owned; kept for reuse when the slot is freed
    std::size_t capacity = 0;
    bool folder = false;
};

// Slots come in chunks that are never freed, so that the handler can walk them at any time.
struct Chunk {
    static constexpr std::size_t kSlots = 256;
    Slot slots[kSlots];
    std::atomic<Chunk*> next{nullptr};
};

Chunk first_chunk;

Slot* claim_slot() {
    for (Chunk* chunk = &first_chunk;;) {
        for (Slot& slot : chunk->slots) {
            int expected = 0;
            if (slot.state.load(std::memory_order_relaxed) == 0 &&
                slot.state.compare_exchange_strong(expected, 1, std::memory_order_acquire))
                return &slot;
        }
        Chunk* next = chunk->next.load(std::memory_order_acquire);
        if (next == nullptr) {
            auto* fresh = new Chunk;
            if (chunk->next.compare_exchange_strong(next, fresh, std::memory_order_acq_rel)) {
                next = fresh;
            } else {
                delete fresh;  // another thread added one: use it
            }
        }
        chunk = next;
    }
}

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

}  // namespace

// The signal handler: C language linkage, as sigaction expects, and internal linkage (static: in
// the unnamed namespace a function of C language linkage would still be a global symbol).
extern "C" {

static void remove_temporaries_and_reraise(int signal_number) {
    const int saved_errno = errno;
    for (Chunk* chunk = &first_chunk; chunk != nullptr;
         chunk = chunk->next.load(std::memory_order_acquire)) {
        for (Slot& slot : chunk->slots) {
            if (slot.state.load(std::memory_order_acquire) != 2) continue;
            if (slot.folder)
                platform::remove_tree_signal_safe(slot.path, 8);
            else
                ::unlink(slot.path);
        }
    }
    struct sigaction default_action {};
    default_action.sa_handler = SIG_DFL;
    sigemptyset(&default_action.sa_mask);
    ::sigaction(signal_number, &default_action, nullptr);
    errno = saved_errno;
    // Delivered with the default action (the process ends) as soon as the handler returns and
    // the signal is unblocked.
    ::raise(signal_number);
}

}  // extern "C"

namespace {

struct TemporaryName {
    long pid = 0;        // 0: not a temporary name
    std::string run_id;  // "" for a name without one (an older leanfade)
};

// "<pid>-<n>[-<run id>]" optionally followed by more ".tmp-<pid>-<n>[-<run id>]": the first pid
// and run id, or pid 0 when `rest` is not that.
TemporaryName temporary_name(const std::string& rest) {
    std::size_t at = 0;
    TemporaryName name;
    const auto is_hex = [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); };
    for (bool first = true;; first = false) {
        const std::size_t pid_start = at;
        long value = 0;
        while (at < rest.size() && rest[at] >= '0' && rest[at] <= '9' && at - pid_start < 10)
            value = value * 10 + (rest[at++] - '0');
        if (at == pid_start || at >= rest.size() || rest[at] != '-') return {};
        ++at;
        const std::size_t counter_start = at;
        while (at < rest.size() && rest[at] >= '0' && rest[at] <= '9') ++at;
        if (at == counter_start) return {};
        std::string run_id;
        if (at + 9 <= rest.size() && rest[at] == '-' &&
            std::all_of(rest.begin() + std::ptrdiff_t(at + 1),
                        rest.begin() + std::ptrdiff_t(at + 9), is_hex)) {
            run_id = rest.substr(at + 1, 8);
            at += 9;
        }
        if (first) name = {value, run_id};
        if (at == rest.size()) return name;
        if (rest.compare(at, 5, ".tmp-") != 0) return {};
        at += 5;
    }
}

// FNV-1a, 32 bits: stable across builds and machines (std::hash is not).
std::uint32_t fnv1a(const std::string& text) {
    std::uint32_t hash = 2166136261u;
    for (const char c : text) {
        hash ^= std::uint8_t(c);
        hash *= 16777619u;
    }
    return hash;
}

std::string first_line_of(const char* path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    return line;
}

bool process_is_running(long pid) {
    if (pid == long(::getpid())) return true;
    return ::kill(pid_t(pid), 0) == 0 || errno != ESRCH;
}

}  // namespace

TemporaryRegistration::TemporaryRegistration(const std::string& path, bool folder) {
    Slot* slot = claim_slot();
    if (slot->capacity < path.size() + 1) {
        delete[] slot->path;
        slot->path = nullptr;
        slot->capacity = 0;
        try {
            slot->path = new char[path.size() + 1];
        } catch (...) {
            slot->state.store(0, std::memory_order_release);
            throw;
        }
        slot->capacity = path.size() + 1;
    }
    std::memcpy(slot->path, path.c_str(), path.size() + 1);
    slot->folder = folder;
    slot->state.store(2, std::memory_order_release);
    slot_ = slot;
}

TemporaryRegistration& TemporaryRegistration::operator=(TemporaryRegistration&& other) noexcept {
    if (this != &other) {
        release();
        slot_ = other.slot_;
        other.slot_ = nullptr;
    }
    return *this;
}

void TemporaryRegistration::release() noexcept {
    if (slot_ == nullptr) return;
    static_cast<Slot*>(slot_)->state.store(0, std::memory_order_release);
    slot_ = nullptr;
}

const std::string& temporary_run_id() {
    static const std::string id = [] {
        // The boot (a pid of another boot is another process), the PID namespace (a container's
        // pids are not the host's) and the host (a shared or network folder).
        std::string where = first_line_of("/proc/sys/kernel/random/boot_id");
        struct stat info {};
        if (::stat("/proc/self/ns/pid", &info) == 0)
            where += " ns " + std::to_string(info.st_dev) + ":" + std::to_string(info.st_ino);
        char host[256] = {};
        if (::gethostname(host, sizeof host - 1) == 0) where += " host " + std::string(host);
        char text[9];
        std::snprintf(text, sizeof text, "%08x", unsigned(fnv1a(where)));
        return std::string(text);
    }();
    return id;
}

void remove_temporaries_on_signals() {
    // SIGXFSZ's default action ends the process (status 153) with no message and every
    // temporary left; ignored, the write fails with EFBIG and the run fails as for a full disk.
    ::signal(SIGXFSZ, SIG_IGN);
    for (int signal_number : kSignals) {
        struct sigaction current {};
        if (::sigaction(signal_number, nullptr, &current) != 0) continue;
        if (current.sa_handler == SIG_IGN) continue;  // e.g. nohup: keep ignoring it
        struct sigaction action {};
        action.sa_handler = remove_temporaries_and_reraise;
        sigemptyset(&action.sa_mask);
        for (int other : kSignals) sigaddset(&action.sa_mask, other);
        ::sigaction(signal_number, &action, nullptr);
    }
}

std::size_t remove_stale_temporaries(const std::string& path) noexcept {
    namespace fs = std::filesystem;
    std::size_t removed = 0;
    try {
        const fs::path target(path);
        const std::string prefix = target.filename().string() + ".tmp-";
        if (prefix.size() == 5) return 0;
        const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
        std::error_code error;
        for (fs::directory_iterator it(folder, error), end; !error && it != end;
             it.increment(error)) {
            const std::string name = it->path().filename().string();
            if (name.compare(0, prefix.size(), prefix) != 0) continue;
            const TemporaryName temporary = temporary_name(name.substr(prefix.size()));
            if (temporary.pid <= 0) continue;
            struct stat info {};
            if (::lstat(it->path().c_str(), &info) != 0) continue;
            if (info.st_uid != ::geteuid()) continue;
            if (!S_ISREG(info.st_mode) && !S_ISDIR(info.st_mode)) continue;
            if (temporary.run_id == temporary_run_id()) {
                if (process_is_running(temporary.pid)) continue;
            } else {
                // Its pid is another machine's, container's or boot's: judged by its age.
                const std::time_t age = std::time(nullptr) - info.st_mtime;
                if (age <= kStaleForeignTemporarySeconds) continue;
            }
            std::error_code remove_error;
            if (fs::remove_all(it->path(), remove_error) > 0 && !remove_error) ++removed;
        }
    } catch (...) {
        // Best effort: a folder that cannot be listed keeps its files.
    }
    return removed;
}

}  // namespace leanfade::io
