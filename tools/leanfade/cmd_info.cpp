// leanfade info: a LEAN map's KTX2 header, levels, metadata and moment statistics.
#include <cmath>
#include <cstdio>
#include <memory>

#include "command.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::cli {
namespace {

// Every check first (inspect_ktx2's structure, then read_ktx2's: the checks of `--bumps`), then
// the output: a refused file prints its one-line error and nothing else.
int run_info(const std::string& path) {
    const io::Ktx2Info info = io::inspect_ktx2(path);
    const LeanMapSummary s = summarize(unpack_lean_map(io::read_ktx2(path)));
    std::printf("%s", io::describe(info).c_str());
    std::printf("moments: slope |B| mean %.4f, max %.4f; coarsest covariance (xx %.5f, yy %.5f, "
                "xy %.5f), anisotropy %.3g\n",
                s.mean_slope, s.max_slope, s.coarsest_covariance.x, s.coarsest_covariance.y,
                s.coarsest_covariance.z, s.coarsest_anisotropy);
    return 0;
}

const CommandRegistration registration{
    "info", "Print a LEAN map's (.ktx2) header, levels and metadata", [](CLI::App& app) -> Runner {
        auto path = std::make_shared<std::string>();
        app.add_option("file", *path, "LEAN map written by leanfade bake")->required();
        return [path] { return run_info(*path); };
    }};

}  // namespace
}  // namespace leanfade::cli
