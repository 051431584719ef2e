#pragma once
// A headless OpenGL 3.3 core context through EGL: no window, no display server (doc/meshrender.md,
// "OpenGL context"). EGL devices (EGL_PLATFORM_DEVICE_EXT: NVIDIA GPUs, Mesa's render nodes and its
// software device) are tried first, hardware before software, then Mesa's surfaceless platform. The
// context is made current with no surface; rendering goes into framebuffer objects.
//
// Every GL function is loaded with eglGetProcAddress (EGL 1.5 and EGL_KHR_client_get_all_proc_addresses
// return core functions too), so nothing links libGL or libOpenGL.
#include <string>

#include <GL/glcorearb.h>

namespace vs {

// The GL functions MeshRender calls; one X-macro list declares and loads them.
#define VS_GL_FUNCTIONS(X)                                                            \
  X(PFNGLGETSTRINGPROC, GetString)                                                     \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                 \
  X(PFNGLGETERRORPROC, GetError)                                                       \
  X(PFNGLENABLEPROC, Enable)                                                           \
  X(PFNGLDISABLEPROC, Disable)                                                         \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                     \
  X(PFNGLDEPTHRANGEPROC, DepthRange)                                                   \
  X(PFNGLVIEWPORTPROC, Viewport)                                                       \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                 \
  X(PFNGLFINISHPROC, Finish)                                                           \
  X(PFNGLFLUSHPROC, Flush)                                                             \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                         \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                         \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                   \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                                   \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                                   \
  X(PFNGLBUFFERDATAPROC, BufferData)                                                   \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                             \
  X(PFNGLMAPBUFFERRANGEPROC, MapBufferRange)                                           \
  X(PFNGLUNMAPBUFFERPROC, UnmapBuffer)                                                 \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                             \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                 \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                         \
  X(PFNGLCREATESHADERPROC, CreateShader)                                               \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                               \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                             \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                 \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                       \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                               \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                             \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                               \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                 \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                               \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                     \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                             \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                                   \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                   \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                                       \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                                     \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                                     \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                                     \
  X(PFNGLUNIFORM1FVPROC, Uniform1fv)                                                   \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                             \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                                 \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                                 \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                                   \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                             \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                           \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                         \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                         \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                         \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                           \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                   \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                                       \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                       \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                                 \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                 \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                                 \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                                   \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                                   \
  X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                                             \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)

struct GlFunctions {
#define VS_GL_DECLARE(type, name) type name = nullptr;
  VS_GL_FUNCTIONS(VS_GL_DECLARE)
#undef VS_GL_DECLARE
};

// Whether an EGL implementation whose client extension string is `clientExtensions` (a space-separated
// list, may be null) can enumerate devices and open a display on one: EGL_EXT_platform_device, with
// either EGL_EXT_device_enumeration or EGL_EXT_device_base, the older extension that holds both
// enumeration and query (NVIDIA's driver 580 names only EGL_EXT_device_base).
bool eglOffersDevicePlatform(const char* clientExtensions);

class EglContext {
public:
  // Creates the display, an OpenGL 3.3 core context, makes it current on this thread and loads the GL
  // functions. Throws InputError naming every EGL platform and device tried and why each failed, and
  // what to install, when none gives a context.
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Makes this context current on the calling thread (a no-op when it already is). EGL lets a context
  // be current on one thread at a time: a context created on another thread can be made current here
  // only after that thread released it (releaseCurrentContext).
  void makeCurrent() const;
  // Releases whatever context is current on the calling thread and frees the thread's EGL state, so
  // that another thread can make it current: called by a thread that created a context for another
  // (MeshSynthesizer creates its renderer on a thread of its own) before it ends.
  static void releaseCurrentContext();
  const GlFunctions& gl() const { return gl_; }
  // "NVIDIA Corporation, NVIDIA H100 ..., 4.6.0 NVIDIA ..." or "Mesa, llvmpipe (LLVM 15 ...), 4.5 (Core Profile) Mesa ...",
  // followed by the EGL platform it came from.
  const std::string& description() const { return description_; }

private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  GlFunctions gl_;
  std::string description_;
};

}  // namespace vs
