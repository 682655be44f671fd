// The program that loads the plugin of examples/plugin (dlopen, as an engine or an editor loads
// its plugins) and calls it: exit 0 when it returns the expected number of mip levels.
//
// Usage: plugin_host PLUGIN.so
#include <dlfcn.h>

#include <cstdio>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: plugin_host PLUGIN.so\n");
        return 2;
    }
    void* plugin = ::dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (plugin == nullptr) {
        std::fprintf(stderr, "plugin_host: %s\n", ::dlerror());
        return 1;
    }
    using Bake = int (*)(int, int);
    const auto bake = reinterpret_cast<Bake>(::dlsym(plugin, "leanfade_plugin_bake"));
    if (bake == nullptr) {
        std::fprintf(stderr, "plugin_host: %s\n", ::dlerror());
        return 1;
    }
    const int levels = bake(48, 20);  // 48x20: mip levels 48x20 ... 1x1
    if (levels != 6) {
        std::fprintf(stderr, "plugin_host: FAILED: the plugin read back %d levels, not 6\n",
                     levels);
        return 1;
    }
    std::printf("plugin_host: %s baked and read back a LEAN map of %d levels\n", argv[1], levels);
    ::dlclose(plugin);
    return 0;
}
