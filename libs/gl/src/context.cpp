// EGL headless context creation (device platform, Mesa surfaceless) and GL_KHR_debug output.
#include "leanfade/gl/detail/context.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <utility>

#include "leanfade/core/error.hpp"

namespace leanfade::gl {
namespace {

bool has_word(const char* list, const std::string& word) {
    if (list == nullptr) return false;
    std::istringstream in(list);
    std::string token;
    while (in >> token)
        if (token == word) return true;
    return false;
}

std::string egl_error_name(EGLint code) {
    switch (code) {
        case EGL_SUCCESS:
            return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED:
            return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS:
            return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC:
            return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE:
            return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG:
            return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT:
            return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY:
            return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH:
            return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER:
            return "EGL_BAD_PARAMETER";
        default: {
            char buffer[32];
            std::snprintf(buffer, sizeof buffer, "EGL error 0x%04x", unsigned(code));
            return buffer;
        }
    }
}

const char* gl_error_name(GLenum code) {
    switch (code) {
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        case GL_STACK_OVERFLOW:
            return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW:
            return "GL_STACK_UNDERFLOW";
        default:
            return "unknown GL error";
    }
}

}  // namespace

struct Context::Impl {
    ContextOptions options;
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string platform;
    std::string renderer;
    std::string version;
    std::vector<std::string> errors;
    std::mutex errors_mutex;
    bool adopted = false;  // Context::adopt_current: the context belongs to someone else

    // Tries to make a 4.5 core context on `candidate`; on failure returns the cause and leaves
    // nothing behind.
    std::string try_display(EGLDisplay candidate, const std::string& name);
    static void GLAPIENTRY debug_callback(GLenum source, GLenum type, GLuint id, GLenum severity,
                                          GLsizei length, const GLchar* message, const void* user);
};

std::string Context::Impl::try_display(EGLDisplay candidate, const std::string& name) {
    if (candidate == EGL_NO_DISPLAY) return name + ": no display";
    EGLint major = 0, minor = 0;
    if (!eglInitialize(candidate, &major, &minor))
        return name + ": eglInitialize failed (" + egl_error_name(eglGetError()) + ")";
    auto fail = [&](const std::string& cause) { return name + ": " + cause; };
    if (!eglBindAPI(EGL_OPENGL_API)) return fail("no desktop OpenGL API");

    const char* extensions = eglQueryString(candidate, EGL_EXTENSIONS);
    EGLConfig config = nullptr;
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0,
                                        EGL_NONE};
    EGLint config_count = 0;
    if (!eglChooseConfig(candidate, config_attributes, &config, 1, &config_count) ||
        config_count < 1) {
        config = nullptr;
        if (!has_word(extensions, "EGL_KHR_no_config_context") &&
            !has_word(extensions, "EGL_MESA_configless_context"))
            return fail("no OpenGL config");
    }
    if (!has_word(extensions, "EGL_KHR_surfaceless_context"))
        return fail("no EGL_KHR_surfaceless_context");

    const bool debug = options.debug || options.record_errors;
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         4,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         5,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_CONTEXT_OPENGL_DEBUG,
                                         debug ? EGL_TRUE : EGL_FALSE,
                                         EGL_NONE};
    EGLContext created = eglCreateContext(candidate, config, EGL_NO_CONTEXT, context_attributes);
    if (created == EGL_NO_CONTEXT) {
        const std::string code = egl_error_name(eglGetError());
        // Say what the driver offers instead: the newest core version it makes a context of.
        for (const auto& [probe_major, probe_minor] :
             {std::pair{4, 4}, {4, 3}, {4, 2}, {4, 1}, {4, 0}, {3, 3}, {3, 2}}) {
            const EGLint probe_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                               probe_major,
                                               EGL_CONTEXT_MINOR_VERSION,
                                               probe_minor,
                                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                               EGL_NONE};
            EGLContext probe =
                eglCreateContext(candidate, config, EGL_NO_CONTEXT, probe_attributes);
            if (probe == EGL_NO_CONTEXT) continue;
            eglDestroyContext(candidate, probe);
            return fail("the driver offers OpenGL " + std::to_string(probe_major) + "." +
                        std::to_string(probe_minor) +
                        " core at most, below the required 4.5 core (" + code + ")");
        }
        return fail("no OpenGL 4.5 core context (" + code +
                    "), nor any core context of version 3.2 or later");
    }
    if (!eglMakeCurrent(candidate, EGL_NO_SURFACE, EGL_NO_SURFACE, created)) {
        eglDestroyContext(candidate, created);
        return fail("eglMakeCurrent failed (" + egl_error_name(eglGetError()) + ")");
    }
    const int gl_version = epoxy_gl_version();
    if (!epoxy_is_desktop_gl() || gl_version < 45) {
        eglMakeCurrent(candidate, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(candidate, created);
        return fail("context is OpenGL " + std::to_string(gl_version / 10) + "." +
                    std::to_string(gl_version % 10) + ", below the required 4.5");
    }
    display = candidate;
    context = created;
    platform = name;
    renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return {};
}

void GLAPIENTRY Context::Impl::debug_callback(GLenum source, GLenum type, GLuint id,
                                              GLenum severity, GLsizei /*length*/,
                                              const GLchar* message, const void* user) {
    auto* self = static_cast<Context::Impl*>(const_cast<void*>(user));
    // Shader compiler diagnostics reach the caller as leanfade::Error from build_program.
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    const bool is_error = type == GL_DEBUG_TYPE_ERROR;
    if (self->options.record_errors) {
        if (is_error) {
            std::lock_guard<std::mutex> lock(self->errors_mutex);
            self->errors.push_back("GL debug error " + std::to_string(id) + ": " + message);
        }
        return;
    }
    if (is_error || severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM)
        std::fprintf(stderr, "leanfade: GL debug (%s): %s\n", is_error ? "error" : "warning",
                     message);
}

Context::Context(const ContextOptions& options) : impl_(std::make_unique<Impl>()) {
    impl_->options = options;
    int device = options.device;
    if (device < 0) {
        if (const char* env = std::getenv("LEANFADE_EGL_DEVICE"); env != nullptr && *env != 0) {
            char* end = nullptr;
            const long value = std::strtol(env, &end, 10);
            if (*end != 0 || value < 0 || value > 1024)
                throw Error("EGL", "LEANFADE_EGL_DEVICE must be a device index >= 0, got '" +
                                       std::string(env) + "'");
            device = int(value);
        }
    }

    if (!epoxy_has_egl()) throw Error("EGL", "libEGL could not be loaded");
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool has_devices =
        has_word(client, "EGL_EXT_device_enumeration") || has_word(client, "EGL_EXT_device_base");
    const bool has_device_platform = has_word(client, "EGL_EXT_platform_device");
    std::vector<EGLDeviceEXT> devices;
    if (has_devices) {
        EGLint count = 0;
        if (eglQueryDevicesEXT(0, nullptr, &count) && count > 0) {
            devices.resize(std::size_t(count));
            eglQueryDevicesEXT(count, devices.data(), &count);
            devices.resize(std::size_t(count));
        }
    }
    auto device_name = [&](std::size_t i) {
        std::string name = "device " + std::to_string(i);
        const char* device_extensions = nullptr;
        if (has_word(client, "EGL_EXT_device_query"))
            device_extensions = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
        if (has_word(device_extensions, "EGL_EXT_device_drm")) {
            if (const char* file = eglQueryDeviceStringEXT(devices[i], EGL_DRM_DEVICE_FILE_EXT))
                name += std::string(" (") + file + ")";
        } else if (has_word(device_extensions, "EGL_MESA_device_software")) {
            name += " (software)";
        }
        return name;
    };
    auto is_software = [&](std::size_t i) {
        if (!has_word(client, "EGL_EXT_device_query")) return false;
        return has_word(eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS),
                        "EGL_MESA_device_software");
    };
    auto device_display = [&](std::size_t i) {
        return eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    };

    std::vector<std::string> causes;
    auto attempt = [&](EGLDisplay candidate, const std::string& name) {
        const std::string cause = impl_->try_display(candidate, name);
        if (cause.empty()) return true;
        causes.push_back(cause);
        return false;
    };
    bool made = false;
    if (device >= 0) {
        if (!has_devices || !has_device_platform)
            throw Error("EGL", "device " + std::to_string(device) +
                                   " requested but EGL has no device platform "
                                   "(EGL_EXT_device_enumeration / EGL_EXT_platform_device)");
        if (std::size_t(device) >= devices.size())
            throw Error("EGL", "device " + std::to_string(device) + " requested but only " +
                                   std::to_string(devices.size()) + " EGL device(s) found");
        made = attempt(device_display(std::size_t(device)), device_name(std::size_t(device)));
    } else {
        if (has_device_platform) {
            for (std::size_t i = 0; i < devices.size() && !made; ++i)
                if (!is_software(i)) made = attempt(device_display(i), device_name(i));
        }
        if (!made && has_word(client, "EGL_MESA_platform_surfaceless"))
            made = attempt(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                    EGL_DEFAULT_DISPLAY, nullptr),
                           "surfaceless");
        if (has_device_platform) {
            for (std::size_t i = 0; i < devices.size() && !made; ++i)
                if (is_software(i)) made = attempt(device_display(i), device_name(i));
        }
        if (!made && causes.empty())
            made = attempt(eglGetDisplay(EGL_DEFAULT_DISPLAY), "default display");
    }
    if (!made) {
        // No display at all (no EGL driver: glvnd found no vendor library, or none offers a
        // platform leanfade can use) is a different fault from a driver without OpenGL 4.5.
        const bool no_display = std::all_of(causes.begin(), causes.end(), [](const std::string& c) {
            const std::string suffix = ": no display";
            return c.size() >= suffix.size() &&
                   c.compare(c.size() - suffix.size(), suffix.size(), suffix) == 0;
        });
        if (no_display) {
            std::string tried;
            for (const std::string& c : causes)
                tried += (tried.empty() ? "" : ", ") + c.substr(0, c.size() - 12);
            throw Error("EGL", "no EGL display" + (tried.empty() ? "" : " (tried: " + tried + ")") +
                                   ": libEGL found no driver to render with; install a GPU "
                                   "driver's EGL or Mesa's (Debian: libegl-mesa0)");
        }
        std::string cause = "no OpenGL 4.5 core context could be made";
        for (const std::string& c : causes) cause += "; " + c;
        throw Error("EGL", cause);
    }

    install_debug_output();
}

void Context::install_debug_output() {
    const ContextOptions& options = impl_->options;
    if ((options.debug || options.record_errors) &&
        (epoxy_gl_version() >= 43 || epoxy_has_gl_extension("GL_KHR_debug"))) {
        glEnable(GL_DEBUG_OUTPUT);
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(&Impl::debug_callback, impl_.get());
        glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
    }
}

std::unique_ptr<Context> Context::adopt_current(const ContextOptions& options,
                                                const std::string& platform) {
    return std::unique_ptr<Context>(new Context(Adopt{}, options, platform));
}

Context::Context(Adopt, const ContextOptions& options, const std::string& platform)
    : impl_(std::make_unique<Impl>()) {
    impl_->options = options;
    impl_->adopted = true;
    const GLubyte* version = glGetString(GL_VERSION);
    const GLubyte* renderer = glGetString(GL_RENDERER);
    if (version == nullptr || renderer == nullptr)
        throw Error("GL", "no OpenGL context is current on this thread");
    const int gl_version = epoxy_gl_version();
    GLint profile = 0;
    if (gl_version >= 32) glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    if (!epoxy_is_desktop_gl() || gl_version < 45 || (profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0)
        throw Error("GL", "the current context is OpenGL " + std::to_string(gl_version / 10) + "." +
                              std::to_string(gl_version % 10) +
                              ((profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0 ? " core" : "") +
                              ", not the required 4.5 core");
    impl_->platform = platform;
    impl_->renderer = reinterpret_cast<const char*>(renderer);
    impl_->version = reinterpret_cast<const char*>(version);
    install_debug_output();
}

Context::~Context() {
    if (impl_->adopted) {
        if (impl_->options.debug || impl_->options.record_errors)
            glDebugMessageCallback(nullptr, nullptr);
        return;
    }
    // The display is not terminated: EGL displays are per-process singletons and stay initialised
    // until the process exits, a later context reuses them, and eglTerminate would unload Mesa's
    // driver with a few of its allocations still live (LeakSanitizer reports them).
    if (impl_->context != EGL_NO_CONTEXT) {
        if (eglGetCurrentContext() == impl_->context) {
            if (impl_->options.debug || impl_->options.record_errors)
                glDebugMessageCallback(nullptr, nullptr);
            eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        }
        eglDestroyContext(impl_->display, impl_->context);
        eglReleaseThread();
    }
}

void Context::make_current() {
    if (impl_->adopted) return;
    if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
        throw Error("EGL", "eglMakeCurrent failed (" + egl_error_name(eglGetError()) + ")");
}

std::string Context::description() const {
    return "OpenGL " + impl_->version + " / " + impl_->renderer + " (" +
           (impl_->adopted ? "" : "EGL ") + impl_->platform + ")";
}

const std::string& Context::platform() const {
    return impl_->platform;
}
const std::string& Context::renderer() const {
    return impl_->renderer;
}

bool Context::has_extension(const std::string& name) const {
    return epoxy_has_gl_extension(name.c_str());
}

float Context::max_anisotropy() const {
    if (epoxy_gl_version() < 46 && !has_extension("GL_EXT_texture_filter_anisotropic") &&
        !has_extension("GL_ARB_texture_filter_anisotropic"))
        return 1.0f;
    GLfloat value = 1.0f;
    glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &value);
    return value;
}

std::vector<std::string> Context::take_errors() {
    std::vector<std::string> result;
    for (GLenum code = glGetError(); code != GL_NO_ERROR; code = glGetError())
        result.push_back(std::string("glGetError: ") + gl_error_name(code));
    std::lock_guard<std::mutex> lock(impl_->errors_mutex);
    result.insert(result.begin(), impl_->errors.begin(), impl_->errors.end());
    impl_->errors.clear();
    return result;
}

void Context::check(const std::string& where) {
    const std::vector<std::string> errors = take_errors();
    if (errors.empty()) return;
    std::string cause = where + ": " + errors.front();
    if (errors.size() > 1) cause += " (and " + std::to_string(errors.size() - 1) + " more)";
    throw Error("GL", cause);
}

}  // namespace leanfade::gl
