#pragma once
// Headless OpenGL 4.5 core contexts through EGL, with functions loaded by libepoxy.
//
// Platforms, tried in this order unless a device is named:
//   1. the EGL device platform (EGL_EXT_device_enumeration + EGL_PLATFORM_DEVICE_EXT) on each
//      hardware device (NVIDIA's driver, Mesa's DRM devices);
//   2. Mesa's surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA): llvmpipe on machines without
//      a GPU, or the Mesa driver of the GPU;
//   3. Mesa's software device on the device platform.
// A device index (ContextOptions::device, or the environment variable LEANFADE_EGL_DEVICE) uses
// only that device. When no context can be made, the constructor throws
// leanfade::Error("EGL", cause): "no EGL display (tried: ...)" when no platform gives a display
// (no EGL driver installed or usable), otherwise "no OpenGL 4.5 core context could be made" and
// what each attempt gave, e.g. "surfaceless: the driver offers OpenGL 3.3 core at most, below
// the required 4.5 core (EGL_BAD_MATCH)".
//
// Rendering is offscreen (framebuffer objects); the context has no window surface.
//
// Context::adopt_current() instead wraps a context made by someone else (a GLFW window's, for the
// interactive viewer): nothing is created or destroyed, and the renderer works in it unchanged.
#include <memory>
#include <string>
#include <vector>

namespace leanfade::gl {

#ifdef NDEBUG
inline constexpr bool kDebugBuild = false;
#else
inline constexpr bool kDebugBuild = true;
#endif

struct ContextOptions {
    // EGL device index (order of eglQueryDevicesEXT); -1: LEANFADE_EGL_DEVICE when set, otherwise
    // automatic.
    int device = -1;
    // Install the GL_KHR_debug callback (a debug context): messages of medium and high severity
    // are printed to stderr. On by default in debug builds.
    bool debug = kDebugBuild;
    // Record every GL error (debug messages of type error, and glGetError) so that check() and
    // take_errors() report them; used by the tests, which fail on any GL error. Implies debug
    // output, but nothing is printed.
    bool record_errors = false;
};

class Context {
  public:
    explicit Context(const ContextOptions& options = {});
    ~Context();

    // Adopts the OpenGL context current on the calling thread (for example a GLFW window's):
    // nothing is created, make_current() does nothing, and the destructor leaves the context to
    // its owner (it must still be current then; the debug callback is removed). `platform` names
    // it ("GLFW window"); options.device is ignored. Throws leanfade::Error("GL", cause) when no
    // context is current or it is not OpenGL 4.5 core or newer.
    static std::unique_ptr<Context> adopt_current(const ContextOptions& options,
                                                  const std::string& platform);
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // Makes the context current on the calling thread (done by the constructor).
    void make_current();

    // "OpenGL 4.5 (Core Profile) Mesa 22.3.6 / llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string description() const;
    // The EGL platform used: "device 0 (/dev/dri/card0)", "surfaceless", ...
    const std::string& platform() const;
    const std::string& renderer() const;

    bool has_extension(const std::string& name) const;
    // Largest supported anisotropic filtering ratio; 1 when neither GL 4.6 nor
    // GL_EXT_texture_filter_anisotropic / GL_ARB_texture_filter_anisotropic is available.
    float max_anisotropy() const;

    // Recorded errors since the last call (record_errors only; glGetError is polled too).
    std::vector<std::string> take_errors();
    // Polls glGetError and the recorded debug errors; throws leanfade::Error("GL", where + cause)
    // if there is any.
    void check(const std::string& where);

    struct Impl;

  private:
    struct Adopt {};
    Context(Adopt, const ContextOptions& options, const std::string& platform);
    void install_debug_output();
    std::unique_ptr<Impl> impl_;
};

}  // namespace leanfade::gl
