// The LEAN-map cache (leanfade/scene/detail/lean_map_cache.hpp) and its SHA-256 key (OpenSSL libcrypto).
#include "leanfade/scene/detail/lean_map_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/input_text.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/version.hpp"

#include <openssl/evp.h>

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;

// SHA-256 (FIPS 180-4) through OpenSSL's libcrypto, which uses the processor's SHA extensions
// where there are some: the key of a cached bake hashes the whole encoded texture, tens of MB.
class Sha256 {
  public:
    Sha256() : context_(EVP_MD_CTX_new()) {
        if (context_ == nullptr || EVP_DigestInit_ex(context_, EVP_sha256(), nullptr) != 1)
            fail("cannot start a SHA-256 digest");
    }
    ~Sha256() { EVP_MD_CTX_free(context_); }
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;

    void update(const void* data, std::size_t size) {
        if (size > 0 && EVP_DigestUpdate(context_, data, size) != 1) fail("SHA-256 digest failed");
    }

    std::string hex() {
        unsigned char digest[EVP_MAX_MD_SIZE];
        unsigned int length = 0;
        if (EVP_DigestFinal_ex(context_, digest, &length) != 1 || length != 32)
            fail("SHA-256 digest failed");
        static const char* digits = "0123456789abcdef";
        std::string out;
        for (unsigned int i = 0; i < length; ++i) {
            out += digits[digest[i] >> 4];
            out += digits[digest[i] & 15];
        }
        return out;
    }

  private:
    [[noreturn]] static void fail(const char* what) { throw Error("libcrypto", what); }

    EVP_MD_CTX* context_;
};

}  // namespace

std::string sha256_hex(const void* data, std::size_t size) {
    Sha256 hash;
    hash.update(data, size);
    return hash.hex();
}

std::string sha256_file_hex(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) throw Error(path, std::string("cannot open (") + std::strerror(errno) + ")");
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode))
        throw Error(path, "is not a regular file");
    Sha256 hash;
    std::vector<char> buffer(std::size_t(1) << 20);
    for (;;) {
        const ssize_t got = ::read(fd, buffer.data(), buffer.size());
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw Error(path, std::string("read error (") + std::strerror(errno) + ")");
        if (got == 0) break;
        hash.update(buffer.data(), std::size_t(got));
    }
    return hash.hex();
}

std::string lean_cache_key(std::span<const std::span<const std::uint8_t>> sources,
                           const std::string& settings) {
    // Each part is preceded by its length, so that no two different inputs hash the same text.
    const std::string header = std::string("leanfade LEAN map cache\n") + LEANFADE_VERSION + "\n" +
                               std::to_string(kLeanBakeVersion) + "\n";
    Sha256 hash;
    for (const std::string* part : {&header, &settings}) {
        const std::string length = std::to_string(part->size()) + ":";
        hash.update(length.data(), length.size());
        hash.update(part->data(), part->size());
    }
    for (const std::span<const std::uint8_t> source : sources) {
        const std::string length = std::to_string(source.size()) + ":";
        hash.update(length.data(), length.size());
        hash.update(source.data(), source.size());
    }
    return hash.hex();
}

std::string lean_cache_key(const std::vector<std::uint8_t>& source, const std::string& settings) {
    const std::span<const std::uint8_t> only(source);
    return lean_cache_key(std::span<const std::span<const std::uint8_t>>(&only, 1), settings);
}

std::string default_lean_cache_folder() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg != nullptr && xdg[0] == '/') return (fs::path(xdg) / "leanfade").string();
    const char* home = std::getenv("HOME");
    if (home != nullptr && home[0] == '/') return (fs::path(home) / ".cache" / "leanfade").string();
    return {};
}

std::string LeanMapCache::entry_path(const std::string& key) const {
    return (fs::path(folder_) / (key + ".ktx2")).string();
}

namespace {

// What an entry records of its key: a suffix of the KTX2 writer string.
std::string key_tag(const std::string& key) {
    return " [cache " + key + "]";
}

bool is_temporary_name(const std::string& name) {
    return name.find(".tmp-") != std::string::npos;
}

}  // namespace

std::optional<PackedLeanMap> LeanMapCache::find(const std::string& key,
                                                std::optional<Storage> storage) const {
    if (!enabled()) return std::nullopt;
    if (!cleaned_) {  // the first use: temporaries of killed runs, entries beyond the bound
        cleaned_ = true;
        clean({});
    }
    const std::string path = entry_path(key);
    std::error_code error;
    if (!fs::is_regular_file(path, error)) return std::nullopt;
    try {
        io::ReadOptions options;
        options.max_dimension = 1 << 20;  // written by store(): the bake's own limit applied
        PackedLeanMap map = io::read_ktx2(path, options);
        // The entry must be the one its name promises: its key recorded, its storage.
        const std::string tag = key_tag(key);
        if (map.generator.size() < tag.size() ||
            map.generator.compare(map.generator.size() - tag.size(), tag.size(), tag) != 0)
            return std::nullopt;
        if (storage && map.storage != *storage) return std::nullopt;
        map.generator.resize(map.generator.size() - tag.size());
        return map;
    } catch (const Error&) {
        return std::nullopt;  // corrupt or foreign: baked again and overwritten
    } catch (const std::bad_alloc&) {
        return std::nullopt;
    }
}

namespace {

bool safe_suffix(const std::string& suffix) {
    if (suffix.empty() || suffix.size() > 64) return false;
    for (const char c : suffix)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_'))
            return false;
    return true;
}

}  // namespace

std::optional<std::vector<std::uint8_t>> LeanMapCache::find_file(const std::string& key,
                                                                 const std::string& suffix,
                                                                 std::uint64_t max_bytes) const {
    if (!enabled() || !safe_suffix(suffix)) return std::nullopt;
    if (!cleaned_) {
        cleaned_ = true;
        clean({});
    }
    try {
        const std::string text = read_regular_file((fs::path(folder_) / (key + suffix)).string(),
                                                   max_bytes, "cache entry");
        return std::vector<std::uint8_t>(text.begin(), text.end());
    } catch (const Error&) {
        return std::nullopt;
    } catch (const std::bad_alloc&) {
        return std::nullopt;
    }
}

std::string LeanMapCache::store_file_entry(
    const std::string& key, const std::string& suffix,
    const std::function<void(io::AtomicFile&)>& fill) const {
    if (!enabled()) return {};
    if (!safe_suffix(suffix)) return "cache entry suffix '" + suffix + "' is not a plain name";
    const std::string path = (fs::path(folder_) / (key + suffix)).string();
    try {
        std::error_code error;
        fs::create_directories(folder_, error);
        if (error) return folder_ + ": " + error.message();
        io::AtomicFile file(path);
        fill(file);
        file.commit();
        clean(path);
        return {};
    } catch (const Error& e) {
        return e.what();
    }
}

std::string LeanMapCache::store_file(const std::string& key, const std::string& suffix,
                                     const std::vector<std::uint8_t>& bytes) const {
    return store_file_entry(key, suffix,
                            [&](io::AtomicFile& file) { file.write(bytes.data(), bytes.size()); });
}

std::string LeanMapCache::regular_file_entry(const std::string& key,
                                             const std::string& suffix) const {
    if (!enabled() || !safe_suffix(suffix)) return {};
    if (!cleaned_) {
        cleaned_ = true;
        clean({});
    }
    const std::string path = (fs::path(folder_) / (key + suffix)).string();
    std::error_code error;
    const fs::file_status status = fs::symlink_status(path, error);
    if (error || !fs::is_regular_file(status)) return {};  // missing, or a link not followed
    return path;
}

bool LeanMapCache::copy_file_to(const std::string& key, const std::string& suffix,
                                std::uint64_t size, io::AtomicFile& output) const {
    const std::string path = regular_file_entry(key, suffix);
    if (path.empty()) return false;
    std::error_code error;
    const std::uintmax_t bytes = fs::file_size(path, error);
    if (error || bytes != size) return false;
    output.copy_from(path, size);
    return true;
}

std::string LeanMapCache::store_file_copy(const std::string& key, const std::string& suffix,
                                          const std::string& source, std::uint64_t size) const {
    return store_file_entry(key, suffix,
                            [&](io::AtomicFile& file) { file.copy_from(source, size); });
}

std::string LeanMapCache::store_file_link(const std::string& key, const std::string& suffix,
                                          const std::string& source, std::uint64_t size) const {
    if (!enabled()) return {};
    if (!safe_suffix(suffix)) return "cache entry suffix '" + suffix + "' is not a plain name";
    const std::string path = (fs::path(folder_) / (key + suffix)).string();
    std::error_code error;
    fs::create_directories(folder_, error);
    if (error) return folder_ + ": " + error.message();
    const std::string temporary = io::temporary_path_for(path);
    fs::create_hard_link(source, temporary, error);
    if (!error) {
        const fs::file_status status = fs::symlink_status(temporary, error);
        if (!error && fs::is_regular_file(status) && fs::file_size(temporary, error) == size &&
            !error) {
            fs::rename(temporary, path, error);
            if (!error) {
                clean(path);
                return {};
            }
        }
        std::error_code ignored;
        fs::remove(temporary, ignored);
    }
    // Another file system (or one without hard links): a copy.
    return store_file_copy(key, suffix, source, size);
}

bool LeanMapCache::serve_file_to(const std::string& key, const std::string& suffix,
                                 std::uint64_t size, const std::string& sha256,
                                 const std::string& output) const {
    const std::string path = regular_file_entry(key, suffix);
    if (path.empty()) return false;
    std::error_code error;
    // A link beside the output pins the entry's file: what is checked is what appears.
    const std::string temporary = io::temporary_path_for(output);
    fs::create_hard_link(path, temporary, error);
    if (!error) {
        bool good = false;
        try {
            good = fs::file_size(temporary, error) == size && !error &&
                   sha256_file_hex(temporary) == sha256;
        } catch (const Error&) {
            good = false;
        }
        if (good) fs::rename(temporary, output, error);
        std::error_code ignored;
        if (!good || error) fs::remove(temporary, ignored);
        if (good && error) throw Error(output, "cannot be written (" + error.message() + ")");
        return good;
    }
    // Another file system: a checked copy.
    io::AtomicFile file(output);
    if (!copy_file_to(key, suffix, size, file)) return false;
    if (sha256_file_hex(file.temporary_path()) != sha256) return false;
    file.commit();
    return true;
}

std::string LeanMapCache::store(const std::string& key, const PackedLeanMap& map) const {
    if (!enabled()) return {};
    try {
        std::error_code error;
        fs::create_directories(folder_, error);
        if (error) return folder_ + ": " + error.message();
        // The map's metadata, with the key recorded in the writer string, and its level sizes;
        // the layers are copied straight into the file (no copy of the map in between).
        PackedLeanMap layout;
        layout.metadata() = map.metadata();
        layout.generator += key_tag(key);
        for (const PackedLevel& level : map.levels)
            layout.levels.push_back({level.width, level.height, {}, {}, {}});
        io::Ktx2Writer writer(entry_path(key), layout);
        const std::vector<PackedLevelTarget>& targets = writer.targets();
        for (std::size_t l = 0; l < map.levels.size(); ++l) {
            const auto layer = std::size_t(targets[l].lean2 - targets[l].lean1);
            if (map.levels[l].lean1.size() != layer || map.levels[l].lean2.size() != layer)
                throw Error(entry_path(key),
                            "level " + std::to_string(l) + " does not have the size of its layers");
            for (const LeanLayerInfo& row : kLeanLayers) {
                if (!map.has_layer(row.layer)) continue;
                const std::vector<std::uint8_t>& bytes = map.levels[l].slice(row.layer);
                if (bytes.size() != layer)
                    throw Error(entry_path(key), "level " + std::to_string(l) +
                                                     " does not have the size of " +
                                                     std::string(row.label));
                std::memcpy(targets[l].slice(row.layer), bytes.data(), layer);
            }
        }
        writer.commit();
        clean(entry_path(key));
        return {};
    } catch (const Error& e) {
        return e.what();
    }
}

void LeanMapCache::clean(const std::string& kept) const {
    struct Entry {
        fs::path path;
        std::uint64_t bytes;
        fs::file_time_type time;
    };
    std::vector<Entry> entries;
    std::uint64_t total = 0;
    std::error_code error;
    const auto now = fs::file_time_type::clock::now();
    for (fs::directory_iterator it(folder_, error), end; !error && it != end; it.increment(error)) {
        std::error_code e;
        if (!it->is_regular_file(e) || e) continue;
        const fs::path path = it->path();
        const std::string name = path.filename().string();
        const auto time = fs::last_write_time(path, e);
        if (e) continue;
        if (is_temporary_name(name)) {
            // Left by a killed run: removed once its process is gone (remove_stale_temporaries
            // of its entry) or, whatever its process, once it is a day old.
            const std::string entry =
                (path.parent_path() / name.substr(0, name.find(".tmp-"))).string();
            io::remove_stale_temporaries(entry);
            if (now - time > std::chrono::seconds(kStaleCacheTemporarySeconds)) fs::remove(path, e);
            continue;
        }
        const std::uint64_t bytes = it->file_size(e);
        if (e) continue;
        total += bytes;
        entries.push_back({path, bytes, time});
    }
    if (total <= max_bytes_) return;
    std::sort(entries.begin(), entries.end(),
              [](const Entry& a, const Entry& b) { return a.time < b.time; });  // oldest first
    for (const Entry& entry : entries) {
        if (total <= max_bytes_) break;
        if (entry.path.string() == kept) continue;
        std::error_code e;
        if (fs::remove(entry.path, e)) total -= entry.bytes;
    }
}

}  // namespace leanfade::scene
