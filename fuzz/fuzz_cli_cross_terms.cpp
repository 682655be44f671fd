// fuzz_cli links the GL-free subcommands only; `bake --cross-terms` reads bump sources through
// the rendering commands' loaders (GL), so this fuzz build refuses it with the usual one-line
// error instead of linking them.
#include "cli_bake_cross_terms.hpp"

#include "leanfade/core/error.hpp"

namespace leanfade::cli {

int run_bake_cross_terms(const CrossTermBakeArgs&) {
    throw Error("--cross-terms", "not part of the fuzz build of the command line");
}

}  // namespace leanfade::cli
