#pragma once
// A cache of baked LEAN maps on disk, keyed by the content of what was baked: a second run over
// the same normal textures with the same settings reads the maps instead of baking them again.
//
// Each map entry is one KTX2 file (leanfade/io/ktx2.hpp) named `<key>.ktx2` in the cache folder
// (other results are file entries `<key><suffix>`, find_file/store_file), written atomically (AtomicFile through write_ktx2), so a reader never sees half an entry. An
// entry that cannot be read back (truncated, corrupt, another version's layout) or does not hold
// what its key describes (the key recorded in the entry, its storage) is ignored and replaced by
// the next store. The folder is bounded: after each store the oldest entries (by the time they
// were written) are removed until the entries take at most max_bytes; at the first find() and after
// each store, temporaries left by killed runs are removed (docs/robustness.md). GL-free.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "leanfade/core/lean_map.hpp"

namespace leanfade::io {
class AtomicFile;
}

namespace leanfade::scene {

// Bumped whenever the bytes a bake produces for the same input and settings change (the baker's
// math, packing or metadata): every older cache entry then misses.
inline constexpr int kLeanBakeVersion = 3;  // 2: repaired normals, the convention warning;
                                            // 3: the spike window of the plateau layer

// SHA-256 (FIPS 180-4) of `size` bytes, as 64 lowercase hexadecimal digits.
std::string sha256_hex(const void* data, std::size_t size);
// The same of the regular file `path`, read in pieces (never whole in memory). Throws
// leanfade::Error(path, cause) when it cannot be read.
std::string sha256_file_hex(const std::string& path);

// The cache key of one bake: SHA-256 over a format tag, leanfade's version, kLeanBakeVersion,
// `settings` (a text naming every bake setting that changes the result) and the source's bytes
// (the encoded image file as stored).
std::string lean_cache_key(const std::vector<std::uint8_t>& source, const std::string& settings);
// The same over several sources, each hashed as its length and its bytes, in order, without
// copying them (one source gives lean_cache_key's key).
std::string lean_cache_key(std::span<const std::span<const std::uint8_t>> sources,
                           const std::string& settings);

// $XDG_CACHE_HOME/leanfade when XDG_CACHE_HOME is an absolute path, else $HOME/.cache/leanfade;
// empty when neither is set (no cache).
std::string default_lean_cache_folder();

// Largest total size of a cache folder's entries (LeanMapCache::store evicts beyond it).
inline constexpr std::uint64_t kMaxLeanCacheBytes = std::uint64_t(2) << 30;  // 2 GiB
// Largest file entry find_file reads into memory by default (manifests and other small
// records; large entries are copied with copy_file_to, never read whole).
inline constexpr std::uint64_t kMaxCacheRecordBytes = std::uint64_t(64) << 10;  // 64 KiB
// Age after which a temporary file in the cache folder is removed whatever its process.
inline constexpr int kStaleCacheTemporarySeconds = 24 * 3600;

class LeanMapCache {
  public:
    // `folder` empty: a cache that never finds anything and stores nothing.
    explicit LeanMapCache(std::string folder, std::uint64_t max_bytes = kMaxLeanCacheBytes)
        : folder_(std::move(folder)), max_bytes_(max_bytes) {}

    const std::string& folder() const noexcept { return folder_; }
    bool enabled() const noexcept { return !folder_.empty(); }
    // `<folder>/<key>.ktx2`.
    std::string entry_path(const std::string& key) const;

    // The map stored under `key`, or nothing when there is none, it cannot be read, it records
    // another key than its name or (when given) its storage is not `storage`: then it is treated
    // as missing and overwritten by the next store().
    std::optional<PackedLeanMap> find(const std::string& key,
                                      std::optional<Storage> storage = std::nullopt) const;
    // Stores `map` under `key` (creating the folder), atomically, recording the key in the entry;
    // then removes stale temporaries and the oldest entries beyond max_bytes.
    // Returns an empty string, or the one-line reason it could not be stored (the map is still
    // good to use).
    std::string store(const std::string& key, const PackedLeanMap& map) const;

    // Other results cached beside the maps (the engine textures of `bake SCENE -o OUT`): the
    // bytes of the entry `<folder>/<key><suffix>` (suffix: letters, digits, '.', '-', '_'), or
    // nothing when it is missing, unreadable or larger than `max_bytes` (then unread: its size
    // is checked before anything is allocated). store_file writes one atomically and then bounds
    // the folder as store() does (every entry counts); it returns "" or the one-line reason it
    // could not store (the bytes are still good to use). An entry of several files is complete
    // when the caller's last file (a manifest) is there.
    std::optional<std::vector<std::uint8_t>> find_file(
        const std::string& key, const std::string& suffix,
        std::uint64_t max_bytes = kMaxCacheRecordBytes) const;
    std::string store_file(const std::string& key, const std::string& suffix,
                           const std::vector<std::uint8_t>& bytes) const;
    // The same for large entries, without their bytes in memory: copy_file_to fills `output`
    // with the entry `<key><suffix>` when it exists and holds `size` bytes (returns false, and
    // leaves `output` untouched, when it does not), copied in the kernel (AtomicFile::copy_from);
    // it throws when the copy itself fails. store_file_copy stores the `size` bytes of the
    // regular file `source` (a finished output of this run) as that entry.
    bool copy_file_to(const std::string& key, const std::string& suffix, std::uint64_t size,
                      io::AtomicFile& output) const;
    std::string store_file_copy(const std::string& key, const std::string& suffix,
                                const std::string& source, std::uint64_t size) const;
    // The same without copying where the cache folder and `source` share a file system: the
    // entry becomes a hard link to `source` (no byte copied; the two share their data until
    // either is replaced, and every leanfade writer replaces a file by a rename, never in
    // place), else a copy as store_file_copy. `source` must hold `size` bytes.
    std::string store_file_link(const std::string& key, const std::string& suffix,
                                const std::string& source, std::uint64_t size) const;
    // Serves the entry `<key><suffix>` at `output` (replacing it atomically) when the entry holds
    // `size` bytes whose SHA-256 is `sha256` (64 lowercase hexadecimal digits), as a hard link
    // where the file system allows, else as a copy; the bytes checked are those of the file that
    // appears at `output`. Returns false, and leaves `output` untouched, when the entry is
    // missing or holds anything else; throws leanfade::Error(output, cause) when `output`
    // cannot be written.
    bool serve_file_to(const std::string& key, const std::string& suffix, std::uint64_t size,
                       const std::string& sha256, const std::string& output) const;

  private:
    void clean(const std::string& kept) const;
    // The path of the file entry `<key><suffix>` when it is a regular file (the folder cleaned
    // of stale temporaries first, once), else "".
    std::string regular_file_entry(const std::string& key, const std::string& suffix) const;
    // Writes the file entry `<key><suffix>` atomically with `fill` and bounds the folder: the
    // common part of store_file and store_file_copy, with their return value.
    std::string store_file_entry(const std::string& key, const std::string& suffix,
                                 const std::function<void(io::AtomicFile&)>& fill) const;

    std::string folder_;
    std::uint64_t max_bytes_ = kMaxLeanCacheBytes;
    mutable bool cleaned_ = false;
};

}  // namespace leanfade::scene
