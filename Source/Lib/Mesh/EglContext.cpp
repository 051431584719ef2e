#include "Mesh/EglContext.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <vector>

#include "Common/Error.h"

namespace vs {

namespace {

std::string eglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: {
      char text[32];
      std::snprintf(text, sizeof text, "EGL error 0x%04x", unsigned(error));
      return text;
    }
  }
}

bool hasExtension(const char* list, const std::string& name) {
  if (!list) return false;
  const std::string all = std::string(" ") + list + " ";
  return all.find(" " + name + " ") != std::string::npos;
}

// Initialises `display` and creates a current OpenGL 3.3 core context on it. On failure returns
// nullptr with `why` set.
//
// Displays are never terminated: EGL displays are per-process singletons (one per platform and
// device) that every context on them shares, initialising one again is a no-op, and eglTerminate
// would unload Mesa's driver, which then leaves memory it never frees (LeakSanitizer reports it).
// Contexts are destroyed; the display goes with the process.
EGLContext createContext(EGLDisplay display, std::string& why) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    why = "eglInitialize failed (" + eglErrorName(eglGetError()) + ")";
    return nullptr;
  }
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why = "desktop OpenGL is not supported (eglBindAPI: " + eglErrorName(eglGetError()) + ")";
    return nullptr;
  }
  // A config is needed only where EGL_KHR_no_config_context is missing; we never draw to a surface.
  EGLConfig config = nullptr;
  if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
    const EGLint attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(display, attributes, &config, 1, &count) || count < 1) {
      why = "no EGL config renders desktop OpenGL";
      return nullptr;
    }
  }
  const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
  if (context == EGL_NO_CONTEXT) {
    why = "no OpenGL 3.3 core context (" + eglErrorName(eglGetError()) + ")";
    return nullptr;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    why = "the context cannot be made current without a surface (" + eglErrorName(eglGetError()) +
          "; EGL_KHR_surfaceless_context is needed)";
    eglDestroyContext(display, context);
    return nullptr;
  }
  return context;
}

}  // namespace

bool eglOffersDevicePlatform(const char* clientExtensions) {
  return hasExtension(clientExtensions, "EGL_EXT_platform_device") &&
         (hasExtension(clientExtensions, "EGL_EXT_device_enumeration") ||
          hasExtension(clientExtensions, "EGL_EXT_device_base"));
}

EglContext::EglContext() {
  std::vector<std::string> attempts;
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!clientExtensions || !getPlatformDisplay) {
    attempts.push_back("EGL has no client extensions or no eglGetPlatformDisplayEXT (no EGL vendor library found?)");
  } else {
    // Candidates in order: hardware devices, software devices, then Mesa's surfaceless platform.
    struct Candidate {
      EGLenum platform;
      void* nativeDisplay;
      std::string name;
    };
    std::vector<Candidate> hardware, software;
    if (eglOffersDevicePlatform(clientExtensions)) {
      auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
      auto queryDeviceString =
          reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
      EGLDeviceEXT devices[16];
      EGLint count = 0;
      if (queryDevices && queryDevices(16, devices, &count)) {
        for (EGLint i = 0; i < count; ++i) {
          const char* deviceExtensions = queryDeviceString ? queryDeviceString(devices[i], EGL_EXTENSIONS) : nullptr;
          const bool isSoftware = hasExtension(deviceExtensions, "EGL_MESA_device_software");
          Candidate candidate{EGL_PLATFORM_DEVICE_EXT, devices[i],
                              "EGL device " + std::to_string(i) + (isSoftware ? " (software)" : "")};
          (isSoftware ? software : hardware).push_back(candidate);
        }
        if (count == 0) attempts.push_back("EGL_PLATFORM_DEVICE_EXT: no devices");
      } else {
        attempts.push_back("EGL_PLATFORM_DEVICE_EXT: eglQueryDevicesEXT failed");
      }
    } else {
      attempts.push_back("EGL_PLATFORM_DEVICE_EXT: not offered by this EGL");
    }
    std::vector<Candidate> candidates = hardware;
    candidates.insert(candidates.end(), software.begin(), software.end());
    const bool surfaceless = hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless");
    if (surfaceless)
      candidates.push_back({EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "EGL_PLATFORM_SURFACELESS_MESA"});

    for (const Candidate& candidate : candidates) {
      EGLDisplay display = getPlatformDisplay(candidate.platform, candidate.nativeDisplay, nullptr);
      if (display == EGL_NO_DISPLAY) {
        attempts.push_back(candidate.name + ": no display (" + eglErrorName(eglGetError()) + ")");
        continue;
      }
      std::string why;
      EGLContext context = createContext(display, why);
      if (!context) {
        attempts.push_back(candidate.name + ": " + why);
        continue;
      }
      display_ = display;
      context_ = context;
      description_ = candidate.name;
      // Say why the candidates before it failed: a GPU machine that ends on Mesa's surfaceless
      // platform, or on software, should tell its user why its device was passed over.
      if (!attempts.empty()) {
        description_ += "; passed over:";
        for (std::size_t i = 0; i < attempts.size(); ++i) description_ += (i ? "; " : " ") + attempts[i];
      }
      break;
    }
    if (!context_ && !surfaceless) attempts.push_back("EGL_PLATFORM_SURFACELESS_MESA: not offered by this EGL");
  }
  if (!context_) {
    std::string message =
        "MeshRender needs an OpenGL 3.3 core context through EGL without a display, and none could be created:";
    for (const std::string& attempt : attempts) message += "\n  " + attempt;
    message +=
        "\nOn a machine without a GPU, install Mesa's EGL and its software rasterizer (Debian: libegl1 "
        "libegl-mesa0 libgl1-mesa-dri); on an NVIDIA machine, the driver's EGL library.";
    throw InputError(message);
  }

  std::vector<std::string> missing;
#define VS_GL_LOAD(type, name)                                                        \
  gl_.name = reinterpret_cast<type>(eglGetProcAddress("gl" #name));                  \
  if (!gl_.name) missing.push_back("gl" #name);
  VS_GL_FUNCTIONS(VS_GL_LOAD)
#undef VS_GL_LOAD
  if (!missing.empty()) {
    std::string names;
    for (const std::string& name : missing) names += (names.empty() ? "" : ", ") + name;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    throw InputError("the OpenGL context from " + description_ + " lacks " + names);
  }
  auto text = [&](GLenum name) {
    const GLubyte* value = gl_.GetString(name);
    return value ? std::string(reinterpret_cast<const char*>(value)) : std::string("?");
  };
  description_ = text(GL_VENDOR) + ", " + text(GL_RENDERER) + ", OpenGL " + text(GL_VERSION) + " (" + description_ + ")";
}

EglContext::~EglContext() {
  if (!context_) return;
  if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  // The display stays initialised (see createContext). Free this thread's EGL state unless another
  // context is current on it.
  if (eglGetCurrentContext() == EGL_NO_CONTEXT) eglReleaseThread();
}

void EglContext::releaseCurrentContext() {
  const EGLDisplay display = eglGetCurrentDisplay();
  if (display != EGL_NO_DISPLAY) eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglReleaseThread();
}

void EglContext::makeCurrent() const {
  if (eglGetCurrentContext() == context_) return;
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    VS_CHECK_MSG(false, "eglMakeCurrent failed for a context that was current before");
}

}  // namespace vs
