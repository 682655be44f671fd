// Basis Universal UASTC KTX2 files (basis_universal.hpp): the levels handed to the encoder script
// as raw RGBA8 files in a private folder with JSON jobs, the script run by Node.js (a process per
// hardware thread at most), the headers read back by inspect_ktx2_uastc (KTX2 §3, the header and
// index; the Khronos Data Format Specification's basic descriptor block for the DFD).
#include "leanfade/io/detail/basis_universal.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "input_file.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/io/detail/node_tool.hpp"

namespace leanfade::io {

namespace fs = std::filesystem;

namespace {

constexpr std::uint8_t kKtx2Identifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32,
                                              0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr std::uint32_t kColorModelUastc = 166;     // KHR_DF_MODEL_UASTC
constexpr std::uint32_t kChannelUastcRgb = 0;       // KHR_DF_CHANNEL_UASTC_RGB
constexpr std::uint32_t kChannelUastcRgba = 3;      // KHR_DF_CHANNEL_UASTC_RGBA
constexpr std::uint32_t kTransferLinear = 1;        // KHR_DF_TRANSFER_LINEAR
constexpr std::uint32_t kPrimariesUnspecified = 0;  // KHR_DF_PRIMARIES_UNSPECIFIED

}  // namespace

void write_ktx2_uastc(const std::vector<UastcTexture>& textures, const std::string& writer,
                      const std::string& encoder) {
    if (textures.empty()) return;
    if (encoder.empty())
        throw Error::setting(
            "compress",
            "basis needs Basis Universal's encoder (npm package ktx2-encoder, run by "
            "Node.js), and none was found beside the program (share/leanfade/node; "
            "scripts/install-deps.sh installs it)");
    const ScratchFolder scratch("leanfade-basis");
    // One encoder process per texture, up to one per hardware thread (the WebAssembly encoder is
    // single-threaded): the textures dealt round-robin into that many jobs.
    const std::size_t processes =
        std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, textures.size());
    std::vector<nlohmann::json> jobs(
        processes, nlohmann::json{{"writer", writer}, {"textures", nlohmann::json::array()}});
    for (std::size_t t = 0; t < textures.size(); ++t) {
        const UastcTexture& texture = textures[t];
        nlohmann::json levels = nlohmann::json::array();
        for (std::size_t l = 0; l < texture.levels->size(); ++l) {
            const Rgba8Level& level = (*texture.levels)[l];
            if (level.texels.size() != std::size_t(level.width) * std::size_t(level.height) * 4)
                throw Error(texture.output, "level " + std::to_string(l) + " has " +
                                                std::to_string(level.texels.size()) +
                                                " bytes for its size");
            const fs::path file =
                scratch.path() / (std::to_string(t) + "_" + std::to_string(l) + ".rgba");
            std::ofstream out(file, std::ios::binary);
            out.write(reinterpret_cast<const char*>(level.texels.data()),
                      std::streamsize(level.texels.size()));
            if (!out) throw Error(scratch.path().string(), "cannot write a level for the encoder");
            levels.push_back(
                {{"file", file.string()}, {"width", level.width}, {"height", level.height}});
        }
        jobs[t % processes]["textures"].push_back({{"output", texture.output},
                                                   {"channels", texture.alpha ? "rgba" : "rgb"},
                                                   {"levels", levels}});
    }
    std::vector<std::vector<std::string>> arguments;
    std::vector<std::string> logs;
    for (std::size_t p = 0; p < processes; ++p) {
        const fs::path job_file = scratch.path() / ("job" + std::to_string(p) + ".json");
        std::ofstream(job_file) << jobs[p].dump();
        arguments.push_back({job_file.string()});
        logs.push_back((scratch.path() / ("encoder" + std::to_string(p) + ".log")).string());
    }
    const std::vector<int> statuses = run_node_scripts(encoder, arguments, logs, "compress");
    for (std::size_t p = 0; p < processes; ++p) {
        if (statuses[p] == 0) continue;
        // The script names the texture: "<output>: <cause>".
        const std::string message = first_line_of(logs[p]);
        for (const UastcTexture& texture : textures)
            if (message.rfind(texture.output + ": ", 0) == 0)
                throw Error(texture.output, "the Basis Universal encoder failed: " +
                                                message.substr(texture.output.size() + 2));
        throw Error::setting("compress",
                             "the Basis Universal encoder failed: " +
                                 (message.empty() ? std::string("no message") : message));
    }
    for (const UastcTexture& texture : textures) {
        std::error_code error;
        if (!fs::is_regular_file(texture.output, error))
            throw Error(texture.output, "the Basis Universal encoder wrote no file");
    }
}

UastcFileInfo inspect_ktx2_uastc(const std::string& path) {
    const detail::InputFile file(path);
    std::array<std::uint8_t, 80> header{};
    file.read_at(0, header.data(), header.size(), "truncated KTX2 header");
    if (!std::equal(std::begin(kKtx2Identifier), std::end(kKtx2Identifier), header.begin()))
        throw Error(path, "not a KTX2 file");
    const auto u32 = [&](std::size_t at) { return detail::load_u32_le(header.data() + at); };
    if (u32(12) != 0) throw Error(path, "not Basis Universal (vkFormat is not 0)");
    UastcFileInfo info;
    info.width = int(u32(20));
    info.height = int(u32(24));
    info.levels = int(u32(40));
    info.zstd = u32(44) == 2;
    const std::uint32_t dfd_offset = u32(48), dfd_length = u32(52);
    if (dfd_length < 4 + 24 + 16 || dfd_length > 4096 || dfd_offset + std::uint64_t(dfd_length) > file.size())
        throw Error(path, "bad data format descriptor");
    std::vector<std::uint8_t> dfd(dfd_length);
    file.read_at(dfd_offset, dfd.data(), dfd.size(), "truncated data format descriptor");
    const std::uint32_t models = detail::load_u32_le(dfd.data() + 12);
    if ((models & 0xffu) != kColorModelUastc) throw Error(path, "not UASTC (colour model)");
    info.primaries_unspecified = ((models >> 8) & 0xffu) == kPrimariesUnspecified;
    info.linear = ((models >> 16) & 0xffu) == kTransferLinear;
    const std::uint32_t channel = (detail::load_u32_le(dfd.data() + 4 + 24) >> 24) & 0x0fu;
    if (channel != kChannelUastcRgb && channel != kChannelUastcRgba)
        throw Error(path, "a UASTC channel other than RGB or RGBA");
    info.alpha = channel == kChannelUastcRgba;
    return info;
}

}  // namespace leanfade::io
