// An engine plugin: a shared object that links the installed leanfade package statically and
// exports one C function. Built by examples/plugin/CMakeLists.txt (find_package) and
// examples/plugin/Makefile (pkg-config); loaded and run by plugin_host (the test
// `package.InstallAndConsume`, tests/package).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <leanfade/leanfade.hpp>

// Bakes a LEAN map of a small height map, writes it as KTX2 to memory and reads it back. Returns
// the number of mip levels read back, or -1 after printing the error.
extern "C" __attribute__((visibility("default"))) int leanfade_plugin_bake(int width, int height) {
    try {
        leanfade::Image image(width, height, 1);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                image.at(x, y) = std::sin(0.7f * float(x)) * std::cos(0.4f * float(y));
        const leanfade::PackedBakeResult baked = leanfade::bake(
            leanfade::BakeInput(image, leanfade::BakeSource::Height),
            leanfade::BakeSettings{{}, {leanfade::Storage::Unorm16}, "leanfade plugin example"});
        const std::vector<std::uint8_t> bytes = leanfade::io::write_ktx2_to_memory(baked.packed);
        const leanfade::PackedLeanMap read = leanfade::io::read_ktx2_from_memory(bytes, "memory");
        return int(read.levels.size());
    } catch (const leanfade::Error& e) {
        std::fprintf(stderr, "leanfade plugin: %s\n", e.what());
        return -1;
    }
}
