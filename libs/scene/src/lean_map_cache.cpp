// The LEAN-map cache (leanfade/scene/lean_map_cache.hpp) and its SHA-256 key.
#include "leanfade/scene/lean_map_cache.hpp"

#include <algorithm>
#include <cctype>
#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "leanfade/core/error.hpp"
#include "leanfade/core/input_text.hpp"
#include "leanfade/io/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;

// SHA-256 as FIPS 180-4 §6.2 describes it: 64-byte blocks, a message schedule of 64 words, 64
// rounds with the constants K (the first 32 bits of the fractional parts of the cube roots of
// the first 64 primes), the length in bits appended big-endian after a 1 bit and zero padding.
class Sha256 {
  public:
    void update(const void* data, std::size_t size) {
        const auto* bytes = static_cast<const std::uint8_t*>(data);
        length_ += size;
        while (size > 0) {
            const std::size_t take = std::min(size, block_.size() - used_);
            std::memcpy(block_.data() + used_, bytes, take);
            used_ += take;
            bytes += take;
            size -= take;
            if (used_ == block_.size()) {
                compress();
                used_ = 0;
            }
        }
    }

    std::string hex() {
        const std::uint64_t bits = length_ * 8;
        const std::uint8_t one = 0x80;
        update(&one, 1);
        const std::uint8_t zero = 0;
        while (used_ != 56) update(&zero, 1);
        std::uint8_t tail[8];
        for (int i = 0; i < 8; ++i) tail[i] = std::uint8_t(bits >> (56 - 8 * i));
        update(tail, 8);
        static const char* digits = "0123456789abcdef";
        std::string out;
        for (std::uint32_t word : state_)
            for (int shift = 28; shift >= 0; shift -= 4) out += digits[(word >> shift) & 15];
        return out;
    }

  private:
    static std::uint32_t rotr(std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

    void compress() {
        static constexpr std::uint32_t k[64] = {
            0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
            0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
            0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
            0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
            0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
            0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
            0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
            0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
            0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
            0xc67178f2};
        std::uint32_t w[64];
        for (int i = 0; i < 16; ++i)
            w[i] = std::uint32_t(block_[4 * i]) << 24 | std::uint32_t(block_[4 * i + 1]) << 16 |
                   std::uint32_t(block_[4 * i + 2]) << 8 | std::uint32_t(block_[4 * i + 3]);
        for (int i = 16; i < 64; ++i) {
            const std::uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
            const std::uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
            w[i] = w[i - 16] + s0 + w[i - 7] + s1;
        }
        std::uint32_t a = state_[0], b = state_[1], c = state_[2], d = state_[3];
        std::uint32_t e = state_[4], f = state_[5], g = state_[6], h = state_[7];
        for (int i = 0; i < 64; ++i) {
            const std::uint32_t s1 = rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25);
            const std::uint32_t choice = (e & f) ^ (~e & g);
            const std::uint32_t t1 = h + s1 + choice + k[i] + w[i];
            const std::uint32_t s0 = rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22);
            const std::uint32_t majority = (a & b) ^ (a & c) ^ (b & c);
            const std::uint32_t t2 = s0 + majority;
            h = g;
            g = f;
            f = e;
            e = d + t1;
            d = c;
            c = b;
            b = a;
            a = t1 + t2;
        }
        state_[0] += a;
        state_[1] += b;
        state_[2] += c;
        state_[3] += d;
        state_[4] += e;
        state_[5] += f;
        state_[6] += g;
        state_[7] += h;
    }

    std::array<std::uint32_t, 8> state_{0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                                        0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
    std::array<std::uint8_t, 64> block_{};
    std::size_t used_ = 0;
    std::uint64_t length_ = 0;
};

}  // namespace

std::string sha256_hex(const void* data, std::size_t size) {
    Sha256 hash;
    hash.update(data, size);
    return hash.hex();
}

std::string lean_cache_key(const std::vector<std::uint8_t>& source, const std::string& settings) {
    // Each part is preceded by its length, so that no two different inputs hash the same text.
    const std::string header = std::string("leanfade LEAN map cache\n") + LEANFADE_VERSION + "\n" +
                               std::to_string(kLeanBakeVersion) + "\n";
    Sha256 hash;
    for (const std::string* part : {&header, &settings}) {
        const std::string length = std::to_string(part->size()) + ":";
        hash.update(length.data(), length.size());
        hash.update(part->data(), part->size());
    }
    const std::string length = std::to_string(source.size()) + ":";
    hash.update(length.data(), length.size());
    hash.update(source.data(), source.size());
    return hash.hex();
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
                                                                 const std::string& suffix) const {
    if (!enabled() || !safe_suffix(suffix)) return std::nullopt;
    if (!cleaned_) {
        cleaned_ = true;
        clean({});
    }
    try {
        const std::string text = read_regular_file((fs::path(folder_) / (key + suffix)).string(),
                                                   std::uint64_t(1) << 32, "cache entry");
        return std::vector<std::uint8_t>(text.begin(), text.end());
    } catch (const Error&) {
        return std::nullopt;
    } catch (const std::bad_alloc&) {
        return std::nullopt;
    }
}

std::string LeanMapCache::store_file(const std::string& key, const std::string& suffix,
                                     const std::vector<std::uint8_t>& bytes) const {
    if (!enabled()) return {};
    if (!safe_suffix(suffix)) return "cache entry suffix '" + suffix + "' is not a plain name";
    const std::string path = (fs::path(folder_) / (key + suffix)).string();
    try {
        std::error_code error;
        fs::create_directories(folder_, error);
        if (error) return folder_ + ": " + error.message();
        io::AtomicFile file(path);
        file.write(bytes.data(), bytes.size());
        file.commit();
        clean(path);
        return {};
    } catch (const Error& e) {
        return e.what();
    }
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
            std::memcpy(targets[l].lean1, map.levels[l].lean1.data(), layer);
            std::memcpy(targets[l].lean2, map.levels[l].lean2.data(), layer);
            if (map.has_plateau()) {
                if (map.levels[l].plateau.size() != layer)
                    throw Error(entry_path(key), "level " + std::to_string(l) +
                                                     " does not have the size of its plateau layer");
                std::memcpy(targets[l].plateau, map.levels[l].plateau.data(), layer);
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
