// leanfade: bake LEAN maps, render, view, evaluate and benchmark specular fading.
#include "cli_app.hpp"
#include "leanfade/io/detail/atomic_file.hpp"

int main(int argc, char** argv) {
    // An interrupted run (Ctrl-C, kill) leaves no temporary file behind.
    leanfade::io::remove_temporaries_on_signals();
    return leanfade::cli::run_leanfade(argc, argv);
}
