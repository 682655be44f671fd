#include "leanfade/core/detail/input_text.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <tuple>
#include <vector>
#include <system_error>

#include "leanfade/core/error.hpp"

namespace leanfade {
namespace {

// Closes the descriptor on every path.
struct Descriptor {
    int value = -1;
    ~Descriptor() {
        if (value >= 0) ::close(value);
    }
};

// Line and paragraph separators, bidirectional marks, embeddings, overrides and isolates,
// invisible format characters (zero-width space and joiners, word joiner, invisible operators,
// interlinear annotation, tags) and the byte order mark: they change how a line reads.
bool is_format_code_point(std::uint32_t code) {
    return code == 0x00AD || code == 0x061C || code == 0x180E ||
           (code >= 0x200B && code <= 0x200F) || (code >= 0x2028 && code <= 0x202E) ||
           (code >= 0x2060 && code <= 0x206F) || code == 0xFEFF ||
           (code >= 0xFFF9 && code <= 0xFFFB) || (code >= 0xE0000 && code <= 0xE007F);
}

// Decodes the valid UTF-8 sequence at text[at]: its length (0 when invalid, overlong, a
// surrogate or out of range) and its code point.
std::size_t utf8_sequence(std::string_view text, std::size_t at, std::uint32_t& code) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(at);
    std::size_t length = 0;
    code = 0;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
        code = lead & 0x1Fu;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        code = lead & 0x0Fu;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        code = lead & 0x07u;
    } else {
        return 0;
    }
    if (at + length > text.size()) return 0;
    for (std::size_t i = 1; i < length; ++i) {
        if ((byte(at + i) & 0xC0u) != 0x80u) return 0;
        code = (code << 6) | (byte(at + i) & 0x3Fu);
    }
    const std::uint32_t smallest[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < smallest[length] || code > 0x10FFFF) return 0;  // overlong or out of range
    if (code >= 0xD800 && code <= 0xDFFF) return 0;            // surrogates
    return length;
}

// Length of the valid UTF-8 sequence of a printable character at text[at], or 0.
std::size_t printable_utf8_length(std::string_view text, std::size_t at) {
    std::uint32_t code = 0;
    const std::size_t length = utf8_sequence(text, at, code);
    if (length == 0 || code <= 0x9F || is_format_code_point(code)) return 0;  // C1, format
    return length;
}

}  // namespace

std::string read_regular_file(const std::string& path, std::uint64_t max_bytes,
                              const std::string& kind) {
    if (path.empty()) throw Error("", "the name of " + kind + " is empty");
    Descriptor file;
    // O_NONBLOCK: opening a FIFO without a writer would otherwise wait forever (it is refused
    // below); it changes nothing for a regular file.
    file.value = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (file.value < 0) {
        if (errno == ENOENT) throw Error(path, "file not found");
        throw Error(path, std::string("cannot open (") + std::strerror(errno) + ")");
    }
    struct stat status {};
    if (::fstat(file.value, &status) != 0)
        throw Error(path, std::string("cannot stat (") + std::strerror(errno) + ")");
    if (S_ISDIR(status.st_mode)) throw Error(path, "is a directory, not " + kind);
    if (!S_ISREG(status.st_mode))
        throw Error(path, "is not a regular file");  // FIFO, device, socket
    if (const std::string output = claimed_output(status.st_dev, status.st_ino); !output.empty())
        throw Error(path, claimed_output_cause(output));
    const auto size = std::uint64_t(status.st_size);
    if (size > max_bytes) {
        throw Error(path, "file of " + std::to_string(size) + " bytes exceeds the limit of " +
                              std::to_string(max_bytes) + " bytes for " + kind);
    }
    std::string text(std::size_t(size), '\0');
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t count = ::read(file.value, text.data() + done, text.size() - done);
        if (count < 0) {
            if (errno == EINTR) continue;
            throw Error(path, std::string("read error (") + std::strerror(errno) + ")");
        }
        if (count == 0) break;  // shrank while being read
        done += std::size_t(count);
    }
    text.resize(done);
    return text;
}

std::string escape_text(std::string_view text, std::size_t max_bytes) {
    std::string escaped;
    for (std::size_t at = 0; at < text.size();) {
        if (escaped.size() >= max_bytes) {
            escaped += "...";
            break;
        }
        const auto byte = static_cast<unsigned char>(text[at]);
        if (byte >= 0x20 && byte < 0x7F && byte != '\\') {
            escaped.push_back(char(byte));
            ++at;
            continue;
        }
        if (const std::size_t length = printable_utf8_length(text, at); length > 0) {
            escaped.append(text.substr(at, length));
            at += length;
            continue;
        }
        char buffer[8];
        std::snprintf(buffer, sizeof buffer, "\\x%02X", unsigned(byte));
        escaped += buffer;
        ++at;
    }
    return escaped;
}

std::string terminal_text(std::string_view text) {
    std::string shown;
    shown.reserve(text.size());
    char buffer[16];
    for (std::size_t at = 0; at < text.size();) {
        const auto byte = static_cast<unsigned char>(text[at]);
        if (byte >= 0x20 && byte < 0x7F) {
            shown.push_back(char(byte));
            ++at;
            continue;
        }
        if (byte < 0x80) {  // C0 controls and DEL
            std::snprintf(buffer, sizeof buffer, "\\x%02X", unsigned(byte));
            shown += buffer;
            ++at;
            continue;
        }
        std::uint32_t code = 0;
        const std::size_t length = utf8_sequence(text, at, code);
        if (length == 0) {  // invalid UTF-8: the byte
            std::snprintf(buffer, sizeof buffer, "\\x%02X", unsigned(byte));
            shown += buffer;
            ++at;
            continue;
        }
        if (code <= 0x9F || is_format_code_point(code)) {  // C1 controls, bidi and format
            std::snprintf(buffer, sizeof buffer, "\\u{%04X}", unsigned(code));
            shown += buffer;
        } else {
            shown.append(text.substr(at, length));
        }
        at += length;
    }
    return shown;
}

namespace {

struct ClaimedOutputs {
    std::mutex mutex;
    std::vector<std::tuple<std::uint64_t, std::uint64_t, std::string>> files;
};

ClaimedOutputs& claimed_outputs() {
    static ClaimedOutputs claimed;
    return claimed;
}

}  // namespace

void claim_output_file(std::uint64_t device, std::uint64_t inode, const std::string& output) {
    ClaimedOutputs& claimed = claimed_outputs();
    const std::lock_guard<std::mutex> lock(claimed.mutex);
    for (const auto& [d, i, name] : claimed.files)
        if (d == device && i == inode) return;
    claimed.files.emplace_back(device, inode, output);
}

std::string claimed_output(std::uint64_t device, std::uint64_t inode) {
    ClaimedOutputs& claimed = claimed_outputs();
    const std::lock_guard<std::mutex> lock(claimed.mutex);
    for (const auto& [d, i, name] : claimed.files)
        if (d == device && i == inode) return name;
    return {};
}

std::string claimed_output_cause(const std::string& output) {
    return "is the same file as the output " + output +
           " of this run (an input named by another input); an output may not replace an input";
}

bool resolves_inside(const std::string& path, const std::string& folder) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::path root = fs::weakly_canonical(fs::absolute(folder.empty() ? "." : folder), error);
    if (error) return false;
    const fs::path resolved = fs::weakly_canonical(fs::absolute(path), error);
    if (error) return false;
    const fs::path inside = resolved.lexically_relative(root);
    return !inside.empty() && *inside.begin() != ".." && inside != ".";
}

}  // namespace leanfade
