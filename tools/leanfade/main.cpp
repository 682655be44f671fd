// leanfade: bake LEAN maps, render, view, evaluate and benchmark specular fading.
#include "cli_app.hpp"

int main(int argc, char** argv) {
    return leanfade::cli::run_leanfade(argc, argv);
}
