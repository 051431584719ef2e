#include "Mesh/GlMeshRenderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "Common/Error.h"
#include "Synth/Parallel.h"

namespace vs {

namespace {

// The vertex is (a u, a v, a, w) in reference pixel form (DepthMesh.h). Everything the fragment needs
// is interpolated with perspective correction, that is linearly in the homogeneous 4-vectors, and
// divided per fragment:
// - the reference position as the homogeneous triple (a u, a v, a): the reference pixel of the surface
//   point under the fragment, also where a varies from vertex to vertex (DepthType 1);
// - q = 1 / z_virtual as w / w_clip (w_clip = z_virtual w): exact, and 0 at infinity.
// (q is affine in window coordinates, so a noperspective varying would do in theory; Mesa's clipper
// interpolates those wrongly where it cuts a triangle at the viewport border.)
const char* const kVertexShader = R"(#version 330 core
layout(location = 0) in vec4 vertex;
uniform mat4 clipFromReference;
out vec3 referencePixel;
out vec2 inverseDepthRatio;
flat out vec2 pointClipZW;
void main() {
  gl_Position = clipFromReference * vertex;
  referencePixel = vertex.xyz;
  inverseDepthRatio = vec2(vertex.w, gl_Position.w);
  pointClipZW = gl_Position.zw;
}
)";

// The fragment writes where it looks in the reference, not a colour: the reference pixel position
// (u, v), q and its flags, in one RGBA32F target. The colour is looked up on the CPU afterwards with
// ViewSyn's own sampler (GlMeshRenderer::render), so each sample is shaded once, whatever the overdraw,
// and chroma needs no render of its own. Flags: the drawn mark (1 a triangle, 3 a point, 2 a locally
// farthest orphan). The edge flag is looked up on the CPU too (DepthMesh::edgeAt).
const char* const kFragmentShader = R"(#version 330 core
in vec3 referencePixel;
in vec2 inverseDepthRatio;
flat in vec2 pointClipZW;
uniform int drawingPoints;  // 1: a point; its fragments look where their own centre looks
uniform float drawnMark;    // 1: a triangle; 3: a point; 2: a locally farthest orphan (kept only in a lone hole)
uniform mat4 referenceFromClip;
uniform vec2 viewportSize;
layout(location = 0) out vec4 referenceDepthFlags;
void main() {
  vec2 reference = referencePixel.xy / referencePixel.z;
  if (drawingPoints == 1) {
    // The fragment centre's ray at the point's depth: the clip position (ndc w, z, w) taken back to
    // the reference's homogeneous pixel form (a u, a v, a, w).
    vec2 ndc = 2.0 * gl_FragCoord.xy / viewportSize - 1.0;
    vec4 back = referenceFromClip * vec4(ndc * pointClipZW.y, pointClipZW.x, pointClipZW.y);
    if (back.z > 0.0) reference = back.xy / back.z;
  }
  float inverseDepth = max(inverseDepthRatio.x / inverseDepthRatio.y, 0.0);
  referenceDepthFlags = vec4(reference, inverseDepth, drawnMark);
}
)";

// The projected pass (ERP cameras, Mesh/MeshErp.h): the vertices come in clip coordinates, computed on
// the CPU, with (u, v, n, d) per vertex: the reference pixel and q = n / d, interpolated with
// perspective correction like the pinhole pass's. Points show their vertex's own reference position.
const char* const kProjectedVertexShader = R"(#version 330 core
layout(location = 0) in vec4 position;
layout(location = 1) in vec4 reference;
out vec4 referenceDepth;
void main() {
  gl_Position = position;
  referenceDepth = reference;
}
)";

const char* const kProjectedFragmentShader = R"(#version 330 core
in vec4 referenceDepth;
uniform float drawnMark;
layout(location = 0) out vec4 referenceDepthFlags;
void main() {
  referenceDepthFlags = vec4(referenceDepth.xy, max(referenceDepth.z / referenceDepth.w, 0.0), drawnMark);
}
)";

// The triangles' own pair of shaders: the same values as the pair above with drawingPoints 0 and
// drawnMark 1, from two varyings instead of three. llvmpipe stores every varying's plane equations
// with each binned triangle (48 bytes each), and binning ~200 000 triangles a view touches tens of
// megabytes of fresh memory, which costs more than the rasterisation on this machine.
const char* const kTriangleVertexShader = R"(#version 330 core
layout(location = 0) in vec4 vertex;
uniform mat4 clipFromReference;
out vec4 referenceVertex;
void main() {
  gl_Position = clipFromReference * vertex;
  referenceVertex = vertex;
}
)";

const char* const kTriangleFragmentShader = R"(#version 330 core
in vec4 referenceVertex;
layout(location = 0) out vec4 referenceDepthFlags;
void main() {
  referenceDepthFlags = vec4(referenceVertex.xy / referenceVertex.z, max(referenceVertex.w * gl_FragCoord.w, 0.0), 1.0);
}
)";

// Parts a view's triangles are drawn in (GlMeshRenderer::render). llvmpipe keeps each flushed part's
// binned triangles until it is rasterised: smaller parts hold less memory at a time (Art view 3: 8 parts
// touch about 7 MB less fresh heap than 4, the same CPU time; doc/meshrender.md).
constexpr int kDrawParts = 8;

// The set bits of a word, inline: the baseline x86-64 build has no POPCNT instruction, and GCC's
// __builtin_popcountll then calls libgcc's table loop (half of uploadMesh's time on Art).
inline uint32_t countBits(uint64_t w) {
  w -= (w >> 1) & 0x5555555555555555ull;
  w = (w & 0x3333333333333333ull) + ((w >> 2) & 0x3333333333333333ull);
  w = (w + (w >> 4)) & 0x0f0f0f0f0f0f0f0full;
  return uint32_t((w * 0x0101010101010101ull) >> 56);
}

// Inverse of a 4x4 matrix by Gauss-Jordan elimination with partial pivoting, in double; false when
// it is singular (a pivot below 1e-12 of the largest entry).
bool inverse(const Mat4& a, Mat4& result) {
  double m[4][8];
  double largest = 0.0;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      m[r][c] = a.m[r][c];
      m[r][c + 4] = r == c ? 1.0 : 0.0;
      largest = std::max(largest, std::fabs(a.m[r][c]));
    }
  if (!(largest > 0.0) || !std::isfinite(largest)) return false;
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::fabs(m[r][c]) > std::fabs(m[pivot][c])) pivot = r;
    if (!(std::fabs(m[pivot][c]) > 1e-12 * largest)) return false;
    for (int k = 0; k < 8; ++k) std::swap(m[c][k], m[pivot][k]);
    const double scale = 1.0 / m[c][c];
    for (int k = 0; k < 8; ++k) m[c][k] *= scale;
    for (int r = 0; r < 4; ++r) {
      if (r == c || m[r][c] == 0.0) continue;
      const double factor = m[r][c];
      for (int k = 0; k < 8; ++k) m[r][k] -= factor * m[c][k];
    }
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) result.m[r][c] = m[r][c + 4];
  return true;
}

GLuint compileShader(const GlFunctions& gl, GLenum type, const char* source) {
  const GLuint shader = gl.CreateShader(type);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {0};
    gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
    gl.DeleteShader(shader);
    // A driver without GLSL 3.30 is unusable input, not a bug of ours.
    throw InputError(std::string("the OpenGL driver cannot compile MeshRender's GLSL 3.30 shader: ") + log);
  }
  return shader;
}

// Plain bilinear at (x, y) in the plane's sample coordinates; outside the plane the edge samples repeat.
float bilinear(const Plane& plane, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  const int x0 = int(fx), y0 = int(fy);
  auto at = [&](int px, int py) {
    return double(plane.row(std::clamp(py, 0, plane.height - 1))[std::clamp(px, 0, plane.width - 1)]);
  };
  const double top = at(x0, y0) + ax * (at(x0 + 1, y0) - at(x0, y0));
  const double bottom = at(x0, y0 + 1) + ax * (at(x0 + 1, y0 + 1) - at(x0, y0 + 1));
  return float(top + ay * (bottom - top));
}

// bilinear() for a plane that continues beyond its edges as `edges` says (SubPixelSampler's
// sampleSphereTaps rule): columns round the wrap; a row beyond a pole is the one as far on the other
// side of it, read half a turn round.
float bilinearSphere(const Plane& plane, double x, double y, const SphereEdges& edges) {
  const long long width = plane.width, maxY = plane.height - 1;
  const double fy = std::floor(y), ay = y - fy;
  auto rowValue = [&](long long py) {
    double cx = x;
    if (py < 0 && edges.north) {
      py = -1 - py;
      cx += 0.5 * double(width);
    } else if (py > maxY && edges.south) {
      py = 2 * maxY + 1 - py;
      cx += 0.5 * double(width);
    }
    const uint16_t* row = plane.row(int(std::clamp(py, 0LL, maxY)));
    const double fx = std::floor(cx), ax = cx - fx;
    auto at = [&](long long px) {
      return double(row[edges.wrap ? (px % width + width) % width : std::clamp(px, 0LL, width - 1)]);
    };
    const long long x0 = (long long)fx;
    return at(x0) + ax * (at(x0 + 1) - at(x0));
  };
  const long long y0 = (long long)fy;
  const double top = rowValue(y0), bottom = rowValue(y0 + 1);
  return float(top + ay * (bottom - top));
}

// SubPixelSampler::sampleTaps<4> (ViewSyn's bicubic, the default Filter), bit for bit, faster where all
// 16 taps lie inside the plane: the four rows' sums side by side in the lanes of one SSE register, each
// ((0 + k0 t0) + k1 t1) + k2 t2) + k3 t3 as the sampler computes it, then the rows weighted and added in
// row order. The sampler skips a row of weight 0; adding its 0 * sum (+0 or -0, the row sums being
// finite) leaves the total as it is, and the total is never -0 (it starts at +0, and a sum of two
// numbers is -0 only when both are), so the value is the same. Anywhere else, and without SSE2, the
// sampler's own code. The rounding to the 1/precision grid is the sampler's (gridPosition).
class FourTapSampler {
public:
  explicit FourTapSampler(const SubPixelSampler& sampler)
      : sampler_(sampler), precision_(sampler.precision()), mask_(sampler.precision() - 1), first_(sampler.first()) {
    while ((1 << shift_) < precision_) ++shift_;
  }
  float operator()(const Plane& plane, double x, double y) const {
#if defined(__SSE2__)
    Taps taps;
    if (inside(plane, x, y, taps)) return interior(plane, taps);
#endif
    return sampler_.sampleTaps<4>(plane, x, y);
  }
  // Two planes of one size at one position (U and V): the rounding and the kernels found once.
  void both(const Plane& a, const Plane& b, double x, double y, float& valueA, float& valueB) const {
#if defined(__SSE2__)
    Taps taps;
    if (inside(a, x, y, taps)) {
      valueA = interior(a, taps);
      valueB = interior(b, taps);
      return;
    }
#endif
    valueA = sampler_.sampleTaps<4>(a, x, y);
    valueB = sampler_.sampleTaps<4>(b, x, y);
  }

private:
  struct Taps {
    long long ix, iy;  // the rounded position's integer parts
    int px, py;        // and phases
  };
  // Whether all 16 taps at (x, y) lie inside the plane (then `taps` holds them).
  bool inside(const Plane& plane, double x, double y, Taps& taps) const {
    if (!gridPosition(x, taps.ix, taps.px) || !gridPosition(y, taps.iy, taps.py)) return false;
    const long long left = taps.ix + first_, top = taps.iy + first_;
    return left >= 0 && top >= 0 && left + 3 <= plane.width - 1 && top + 3 <= plane.height - 1;
  }
#if defined(__SSE2__)
  float interior(const Plane& plane, const Taps& taps) const {
    const int px = taps.px, py = taps.py;
    if (px == 0 && py == 0) return float(plane.at(int(taps.ix), int(taps.iy)));
    const long long left = taps.ix + first_, top = taps.iy + first_;
    auto load = [&](long long row) {
      return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(plane.row(int(row)) + left));
    };
    const __m128i rows01 = _mm_unpacklo_epi16(load(top), load(top + 1));      // r0[0] r1[0] r0[1] r1[1] ...
    const __m128i rows23 = _mm_unpacklo_epi16(load(top + 2), load(top + 3));  // r2[0] r3[0] r2[1] r3[1] ...
    const __m128i columns01 = _mm_unpacklo_epi32(rows01, rows23);              // column 0, then column 1
    const __m128i columns23 = _mm_unpackhi_epi32(rows01, rows23);              // column 2, then column 3
    const __m128i zero = _mm_setzero_si128();
    const float* kx = sampler_.kernel(px);
    __m128 rowSums = _mm_setzero_ps();
    rowSums = _mm_add_ps(rowSums, _mm_mul_ps(_mm_set1_ps(kx[0]), _mm_cvtepi32_ps(_mm_unpacklo_epi16(columns01, zero))));
    rowSums = _mm_add_ps(rowSums, _mm_mul_ps(_mm_set1_ps(kx[1]), _mm_cvtepi32_ps(_mm_unpackhi_epi16(columns01, zero))));
    rowSums = _mm_add_ps(rowSums, _mm_mul_ps(_mm_set1_ps(kx[2]), _mm_cvtepi32_ps(_mm_unpacklo_epi16(columns23, zero))));
    rowSums = _mm_add_ps(rowSums, _mm_mul_ps(_mm_set1_ps(kx[3]), _mm_cvtepi32_ps(_mm_unpackhi_epi16(columns23, zero))));
    alignas(16) float weighted[4];
    _mm_store_ps(weighted, _mm_mul_ps(_mm_loadu_ps(sampler_.kernel(py)), rowSums));
    float sum = 0.0f;
    for (const float term : weighted) sum += term;
    return sum;
  }
#endif
  // SubPixelSampler's rounding: false far outside any plane (the sampler's own code then).
  bool gridPosition(double x, long long& whole, int& phase) const {
    const double g = std::floor(x * precision_ + 0.5);
    if (!(std::fabs(g) < 4503599627370496.0)) return false;  // 2^52
    const long long index = (long long)g;
    whole = index >> shift_;
    phase = int(index & mask_);
    return true;
  }

  const SubPixelSampler& sampler_;
  int precision_, mask_, first_, shift_ = 0;
};

// The values of planes a and b at (x, y), through the pass's sampler (Impl::withSampling).
template <class Sample>
void sampleBoth(const Sample& sample, const Plane& a, const Plane& b, double x, double y, float& valueA, float& valueB) {
  valueA = sample(a, x, y);
  valueB = sample(b, x, y);
}
void sampleBoth(const FourTapSampler& sample, const Plane& a, const Plane& b, double x, double y, float& valueA,
                float& valueB) {
  sample.both(a, b, x, y, valueA, valueB);
}

// Compiles and links a vertex and a fragment shader into a program; throws InputError when the driver
// cannot.
GLuint linkProgram(const GlFunctions& gl, const char* vertexSource, const char* fragmentSource) {
  const GLuint vertexShader = compileShader(gl, GL_VERTEX_SHADER, vertexSource);
  GLuint fragmentShader = 0;
  try {
    fragmentShader = compileShader(gl, GL_FRAGMENT_SHADER, fragmentSource);
  } catch (...) {
    gl.DeleteShader(vertexShader);
    throw;
  }
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vertexShader);
  gl.AttachShader(program, fragmentShader);
  gl.LinkProgram(program);
  gl.DeleteShader(vertexShader);
  gl.DeleteShader(fragmentShader);
  GLint linked = 0;
  gl.GetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    char log[4096] = {0};
    gl.GetProgramInfoLog(program, sizeof log, nullptr, log);
    gl.DeleteProgram(program);
    throw InputError(std::string("the OpenGL driver cannot link MeshRender's shaders: ") + log);
  }
  return program;
}

}  // namespace

// The GL objects of the projected pass, created on its first use.
struct ProjectedPass {
  GLuint program = 0, vertexArray = 0, positionBuffer = 0, attributeBuffer = 0, indexBuffer = 0;
  GLint drawnMarkLocation = -1;
  GLsizeiptr positionBytes = 0, attributeBytes = 0, indexBytes = 0;
  GLsizei triangleIndexCount = 0, pointCount = 0, orphanCount = 0;
  std::vector<uint32_t> indices;  // triangles, then points, then locally farthest orphans
};

// One uploaded mesh (uploadMesh's slot): its vertex array, buffers and lists' sizes.
struct MeshSlot {
  GLuint vertexArray = 0, vertexBuffer = 0, indexBuffer = 0;
  GLsizeiptr vertexBytes = 0, indexBytes = 0;  // buffer sizes, kept across frames
  GLsizei triangleIndexCount = 0;  // indices of the triangles, first in the index buffer
  GLsizei pointCount = 0;          // then the points
  GLsizei orphanCount = 0;         // then the locally farthest orphans
  const DepthMesh* mesh = nullptr;  // its edge flags (null: none uploaded, or released)
};

struct GlMeshRenderer::Impl {
  EglContext context;
  const GlFunctions& gl;
  GLuint program = 0, triangleProgram = 0;
  std::vector<MeshSlot> slots;  // uploadMesh's meshes, by slot
  size_t slot = 0;              // the one the next render draws (useMesh)
  GLuint framebuffer = 0, colourBuffer = 0, depthBuffer = 0;
  GLint triangleClipLocation = -1;
  GLint clipLocation = -1, referenceFromClipLocation = -1, viewportLocation = -1, drawingPointsLocation = -1,
        drawnMarkLocation = -1;
  int framebufferWidth = 0, framebufferHeight = 0;
  GLint maxRenderbufferSize = 0, maxViewport[2] = {0, 0};
  std::vector<const Plane*> planes;         // the "texture": the reference planes (the caller's), sampled on the CPU
  std::unique_ptr<SubPixelSampler> sampler;  // null: exact bilinear
  std::vector<float> readBack;              // last render: (u, v, q, flags) per sample
  std::vector<uint8_t> edges;               // last render: edgeAt() of each drawn sample
  std::vector<uint64_t> usedVertices;       // uploadMesh: one bit a grid vertex, set where a list uses it
  std::vector<uint32_t> usedBefore;         // uploadMesh: used vertices before each 64-bit word
  const DepthMesh* mesh = nullptr;          // the uploaded mesh (its edge flags)
  int renderedWidth = 0, renderedHeight = 0;
  std::unique_ptr<ProjectedPass> projected;  // ERP cameras (uploadProjectedMesh)
  SphereEdges sphere;                        // setReferenceSphere: how the reference continues beyond its edges

  Impl() : gl(context.gl()) {
    program = linkProgram(gl, kVertexShader, kFragmentShader);
    try {
      triangleProgram = linkProgram(gl, kTriangleVertexShader, kTriangleFragmentShader);
    } catch (...) {
      gl.DeleteProgram(program);
      throw;
    }
    triangleClipLocation = gl.GetUniformLocation(triangleProgram, "clipFromReference");
    VS_CHECK(triangleClipLocation >= 0);
    clipLocation = gl.GetUniformLocation(program, "clipFromReference");
    referenceFromClipLocation = gl.GetUniformLocation(program, "referenceFromClip");
    viewportLocation = gl.GetUniformLocation(program, "viewportSize");
    drawingPointsLocation = gl.GetUniformLocation(program, "drawingPoints");
    drawnMarkLocation = gl.GetUniformLocation(program, "drawnMark");
    VS_CHECK(clipLocation >= 0 && referenceFromClipLocation >= 0 && viewportLocation >= 0 && drawingPointsLocation >= 0 &&
             drawnMarkLocation >= 0);
    gl.UseProgram(program);

    addSlot();

    gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRenderbufferSize);
    gl.GetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    checkErrors("setting up the renderer");
  }

  ~Impl() {
    context.makeCurrent();
    if (projected) {
      gl.DeleteBuffers(1, &projected->positionBuffer);
      gl.DeleteBuffers(1, &projected->attributeBuffer);
      gl.DeleteBuffers(1, &projected->indexBuffer);
      gl.DeleteVertexArrays(1, &projected->vertexArray);
      gl.DeleteProgram(projected->program);
    }
    gl.DeleteFramebuffers(1, &framebuffer);
    gl.DeleteRenderbuffers(1, &colourBuffer);
    gl.DeleteRenderbuffers(1, &depthBuffer);
    for (MeshSlot& mesh : slots) {
      gl.DeleteBuffers(1, &mesh.vertexBuffer);
      gl.DeleteBuffers(1, &mesh.indexBuffer);
      gl.DeleteVertexArrays(1, &mesh.vertexArray);
    }
    gl.DeleteProgram(program);
    gl.DeleteProgram(triangleProgram);
  }

  // A vertex array with a vertex buffer (attribute 0: the vertex) and an index buffer.
  void addSlot() {
    MeshSlot mesh;
    gl.GenVertexArrays(1, &mesh.vertexArray);
    gl.BindVertexArray(mesh.vertexArray);
    gl.GenBuffers(1, &mesh.vertexBuffer);
    gl.GenBuffers(1, &mesh.indexBuffer);
    gl.BindBuffer(GL_ARRAY_BUFFER, mesh.vertexBuffer);
    gl.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(0);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.indexBuffer);  // part of the vertex array's state
    slots.push_back(mesh);
  }

  void checkErrors(const char* what) const {
    GLenum error = gl.GetError();
    if (error == GL_NO_ERROR) return;
    bool outOfMemory = false;
    std::string codes;
    for (; error != GL_NO_ERROR; error = gl.GetError()) {
      outOfMemory = outOfMemory || error == GL_OUT_OF_MEMORY;
      char code[16];
      std::snprintf(code, sizeof code, "0x%04x", unsigned(error));
      codes += (codes.empty() ? "" : ", ") + std::string(code);
    }
    if (outOfMemory) throw InputError(std::string("OpenGL ran out of memory ") + what + " (" + context.description() + ")");
    VS_CHECK_MSG(false, (std::string("OpenGL error ") + codes + " " + what).c_str());
  }

  // Uploads `bytes` into `buffer`: storage is reallocated only when it grows, so from the second frame
  // on a mesh of similar size is written into the buffer the driver already has. Null `data`: the
  // storage only (bound to `target`), for the caller to write.
  void upload(GLenum target, GLuint buffer, GLsizeiptr bytes, const void* data, GLsizeiptr& capacity) {
    gl.BindBuffer(target, buffer);
    if (bytes > capacity) {
      capacity = bytes + bytes / 8;
      gl.BufferData(target, capacity, nullptr, GL_DYNAMIC_DRAW);
    }
    if (bytes > 0 && data) gl.BufferSubData(target, 0, bytes, data);
  }

  void ensureFramebuffer(int width, int height) {
    if (width <= framebufferWidth && height <= framebufferHeight) return;
    if (width > maxRenderbufferSize || height > maxRenderbufferSize || width > maxViewport[0] || height > maxViewport[1])
      throw InputError("a " + std::to_string(width) + " x " + std::to_string(height) +
                       " render target exceeds this OpenGL's limits (renderbuffer " + std::to_string(maxRenderbufferSize) +
                       ", viewport " + std::to_string(maxViewport[0]) + " x " + std::to_string(maxViewport[1]) + "; " +
                       context.description() + ")");
    framebufferWidth = std::max(width, framebufferWidth);
    framebufferHeight = std::max(height, framebufferHeight);
    if (!framebuffer) {
      gl.GenFramebuffers(1, &framebuffer);
      gl.GenRenderbuffers(1, &colourBuffer);
      gl.GenRenderbuffers(1, &depthBuffer);
    }
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    gl.BindRenderbuffer(GL_RENDERBUFFER, colourBuffer);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA32F, framebufferWidth, framebufferHeight);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colourBuffer);
    gl.BindRenderbuffer(GL_RENDERBUFFER, depthBuffer);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, framebufferWidth, framebufferHeight);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthBuffer);
    const GLenum drawBuffers[1] = {GL_COLOR_ATTACHMENT0};
    gl.DrawBuffers(1, drawBuffers);
    checkErrors("allocating the float framebuffer");
    const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      char code[16];
      std::snprintf(code, sizeof code, "0x%04x", unsigned(status));
      throw InputError(std::string("this OpenGL cannot render into RGBA32F colour with a 32-bit float depth buffer "
                                   "(framebuffer status ") +
                       code + "; " + context.description() + ")");
    }
  }

  // Binds the framebuffer for `grid`, cleared, with the depth test on.
  void beginRender(const RenderGrid& grid) {
    context.makeCurrent();
    VS_CHECK(!planes.empty() && grid.width > 0 && grid.height > 0);
    bindClearedFramebuffer(grid.width, grid.height);
  }

  void bindClearedFramebuffer(int width, int height) {
    ensureFramebuffer(width, height);
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    gl.Viewport(0, 0, width, height);
    const float clearReference[4] = {0.0f, 0.0f, float(kNoDepth), 0.0f};
    const float clearDepth = 1.0f;
    gl.ClearBufferfv(GL_COLOR, 0, clearReference);
    gl.ClearBufferfv(GL_DEPTH, 0, &clearDepth);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);  // smaller z_ndc is larger q: nearer
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_BLEND);
  }

  // The draws of a render: the slot's triangles (in parts), then its points, then its locally farthest
  // orphans, into the bound framebuffer of width x height.
  void draw(const MeshSlot& drawn, const Mat4& clip, int width, int height) {
    float matrix[16];
    toGlMatrix(clip, matrix);
    gl.BindVertexArray(drawn.vertexArray);
    if (drawn.triangleIndexCount > 0) {
      gl.UseProgram(triangleProgram);
      gl.UniformMatrix4fv(triangleClipLocation, 1, GL_FALSE, matrix);
      // In parts, each flushed: a software rasteriser (llvmpipe) bins a part's triangles on this thread
      // and rasterises a flushed part on its own threads, so binning the next part overlaps rasterising
      // this one instead of leaving the other cores idle. Same triangles in the same order: same pixels.
      const GLsizei triangles = drawn.triangleIndexCount / 3;
      for (int part = 0; part < kDrawParts; ++part) {
        const GLsizei first = GLsizei(int64_t(triangles) * part / kDrawParts), last = GLsizei(int64_t(triangles) * (part + 1) / kDrawParts);
        if (last == first) continue;
        gl.DrawElements(GL_TRIANGLES, 3 * (last - first), GL_UNSIGNED_INT,
                        reinterpret_cast<const void*>(size_t(first) * 3 * sizeof(uint32_t)));
        if (part + 1 < kDrawParts) gl.Flush();
      }
    }
    gl.UseProgram(program);
    gl.UniformMatrix4fv(clipLocation, 1, GL_FALSE, matrix);
    // Points look along their fragments' own rays (the shader's drawingPoints); where the matrix cannot
    // be inverted they keep the vertex's position.
    Mat4 back;
    const bool invertible = inverse(clip, back);
    toGlMatrix(back, matrix);
    gl.UniformMatrix4fv(referenceFromClipLocation, 1, GL_FALSE, matrix);
    gl.Uniform2f(viewportLocation, float(width), float(height));
    // One-pixel points (the default point size) after the triangles: the depth test keeps the nearer.
    // Marked 3: drawn, and on an edge.
    gl.Uniform1i(drawingPointsLocation, invertible ? 1 : 0);
    gl.Uniform1f(drawnMarkLocation, 3.0f);
    if (drawn.pointCount > 0)
      gl.DrawElements(GL_POINTS, drawn.pointCount, GL_UNSIGNED_INT,
                      reinterpret_cast<const void*>(size_t(drawn.triangleIndexCount) * sizeof(uint32_t)));
    drawOrphans(drawnMarkLocation, drawn.orphanCount, size_t(drawn.triangleIndexCount + drawn.pointCount));
  }

  // Locally farthest orphans last, only where nothing is drawn: every fragment's window depth is 1, the
  // cleared value, and passes GL_LEQUAL there only. Marked 2; kept below only in a lone hole. `count`
  // indices from `firstIndex` of the bound index buffer, with the bound program's mark at `markLocation`.
  void drawOrphans(GLint markLocation, GLsizei count, size_t firstIndex) {
    if (count <= 0) return;
    gl.Uniform1f(markLocation, 2.0f);
    gl.DepthRange(1.0, 1.0);
    gl.DepthFunc(GL_LEQUAL);
    gl.DrawElements(GL_POINTS, count, GL_UNSIGNED_INT, reinterpret_cast<const void*>(firstIndex * sizeof(uint32_t)));
    gl.DepthRange(0.0, 1.0);
    gl.DepthFunc(GL_LESS);
  }

  // The edge flag of a sample: every point is on an edge (a border vertex, or an orphan); a triangle's
  // fragment is when the grid triangle under its reference position touches a dropped one.
  bool edgeAt(const float* sample) const { return sample[3] != 1.0f || (mesh && mesh->edgeAt(sample[0], sample[1])); }

  // The colour of plane `k` at texel position (x, y). An ERP reference's texture is read round its wrap
  // and across its poles within four samples of its edges (as ViewSyn's warps: Synth/TextureWarp.cpp),
  // where alone the two rules may differ; everywhere else, and for any other reference, as it was.
  float sample(const Plane& plane, double x, double y) const {
    if (sphere.any() && SubPixelSampler::nearEdge(x, y, plane.width, plane.height)) {
      if (!sampler) return bilinearSphere(plane, x, y, sphere);
      return sampler->withTaps([&](auto taps) {
        return sampler->sampleSphereTaps<decltype(taps)::value>(plane, x, y, sphere);
      });
    }
    return sampler ? sampler->sample(plane, x, y) : bilinear(plane, x, y);
  }

  // Calls f(sample) with a callable sample(plane, x, y) that gives sample()'s value, bit for bit, its
  // kind (sphere edges, ViewSyn's sampler and its tap count, plain bilinear) chosen once for a whole
  // pass instead of once per sample.
  template <class F>
  void withSampling(F&& f) const {
    if (sphere.any() || !sampler) {
      f([this](const Plane& plane, double x, double y) { return sample(plane, x, y); });
      return;
    }
    const SubPixelSampler& chosen = *sampler;
    if (chosen.taps() == 4) {
      const FourTapSampler fourTaps(chosen);
      f(fourTaps);
      return;
    }
    chosen.withTaps([&](auto taps) {
      f([&chosen](const Plane& plane, double x, double y) {
        return chosen.sampleTaps<decltype(taps)::value>(plane, x, y);
      });
    });
  }
};

GlMeshRenderer::GlMeshRenderer() : impl_(std::make_unique<Impl>()) {}

GlMeshRenderer::~GlMeshRenderer() = default;

const std::string& GlMeshRenderer::description() const { return impl_->context.description(); }

void GlMeshRenderer::setSampling(const SubPixelSampler* sampler) {
  impl_->sampler = sampler ? std::make_unique<SubPixelSampler>(*sampler) : nullptr;
}

void GlMeshRenderer::uploadMesh(const DepthMesh& mesh, size_t slot) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  s.context.makeCurrent();
  VS_CHECK(slot < 64);
  while (s.slots.size() <= slot) s.addSlot();
  MeshSlot& target = s.slots[slot];
  VS_CHECK(mesh.vertices.size() == mesh.vertexCount() * 4 && mesh.boundary.size() == mesh.vertexCount());
  VS_CHECK(mesh.triangles.size() + mesh.points.size() + mesh.farthestOrphans.size() <=
           size_t(std::numeric_limits<GLsizei>::max()));
  gl.BindVertexArray(target.vertexArray);
  // Only the vertices that the triangles, points and orphans use go to the driver, in grid order (an
  // adaptive mesh uses about a sixth of the grid's on Art): the lists' indices are renumbered into them by
  // rank, each vertex keeps its values and each triangle its corners in their order, so the renders
  // are the same to the bit, with less to copy and a smaller buffer for the driver to hold. Used
  // vertices: one bit each; the rank of vertex v is the used vertices before its word plus those
  // before it within the word.
  const std::vector<uint32_t>* lists[3] = {&mesh.triangles, &mesh.points, &mesh.farthestOrphans};
  const size_t vertexCount = mesh.vertexCount(), words = (vertexCount + 63) / 64;
  s.usedVertices.assign(words, 0);
  for (const std::vector<uint32_t>* list : lists)
    for (const uint32_t v : *list) {
      VS_CHECK(v < vertexCount);
      s.usedVertices[v >> 6] |= uint64_t(1) << (v & 63);
    }
  s.usedBefore.resize(words);
  uint32_t used = 0;
  for (size_t w = 0; w < words; ++w) {
    s.usedBefore[w] = used;
    used += countBits(s.usedVertices[w]);
  }
  auto rank = [&](uint32_t v) {
    const uint64_t below = s.usedVertices[v >> 6] & ((uint64_t(1) << (v & 63)) - 1);
    return s.usedBefore[v >> 6] + countBits(below);
  };
  // Written straight into the driver's buffers (mapped), with no copy on this side.
  auto mapped = [&](GLenum target, GLuint buffer, GLsizeiptr bytes, GLsizeiptr& capacity) -> void* {
    s.upload(target, buffer, bytes, nullptr, capacity);
    if (bytes == 0) return nullptr;
    void* memory = gl.MapBufferRange(target, 0, bytes, GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
    if (!memory) s.checkErrors("mapping a buffer");
    VS_CHECK(memory != nullptr);
    return memory;
  };
  auto unmap = [&](GLenum target) {
    if (gl.UnmapBuffer(target) != GL_TRUE) throw InputError("OpenGL lost a buffer's content while MeshRender wrote it (" + s.context.description() + ")");
  };
  if (auto* to = static_cast<float*>(mapped(GL_ARRAY_BUFFER, target.vertexBuffer, GLsizeiptr(size_t(used) * 4 * sizeof(float)), target.vertexBytes))) {
    for (size_t w = 0; w < words; ++w)
      for (uint64_t bits = s.usedVertices[w]; bits != 0; bits &= bits - 1) {
        const size_t v = w * 64 + size_t(__builtin_ctzll(bits));
        std::memcpy(to, mesh.vertices.data() + v * 4, 4 * sizeof(float));
        to += 4;
      }
    unmap(GL_ARRAY_BUFFER);
  }
  // Triangles, then points, then locally farthest orphans, one after the other.
  const size_t indexCount = mesh.triangles.size() + mesh.points.size() + mesh.farthestOrphans.size();
  if (auto* to = static_cast<uint32_t*>(mapped(GL_ELEMENT_ARRAY_BUFFER, target.indexBuffer, GLsizeiptr(indexCount * sizeof(uint32_t)), target.indexBytes))) {
    for (const std::vector<uint32_t>* list : lists)
      for (const uint32_t v : *list) *to++ = rank(v);
    unmap(GL_ELEMENT_ARRAY_BUFFER);
  }
  target.triangleIndexCount = GLsizei(mesh.triangles.size());
  target.pointCount = GLsizei(mesh.points.size());
  target.orphanCount = GLsizei(mesh.farthestOrphans.size());
  target.mesh = &mesh;
  s.checkErrors("uploading the mesh");
  useMesh(slot);
}

void GlMeshRenderer::useMesh(size_t slot) {
  Impl& s = *impl_;
  VS_CHECK(slot < s.slots.size() && s.slots[slot].mesh != nullptr);
  s.slot = slot;
  s.mesh = s.slots[slot].mesh;
}

void GlMeshRenderer::uploadTexture(const std::vector<const Plane*>& planes) {
  Impl& s = *impl_;
  VS_CHECK(!planes.empty() && planes.size() <= 3);
  for (const Plane* plane : planes) VS_CHECK(plane->width == planes[0]->width && plane->height == planes[0]->height);
  s.planes = planes;
}

void GlMeshRenderer::warmUp() {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  s.context.makeCurrent();
  // A triangle, a point and a locally farthest orphan on three vertices (u, v, 1, w) in slot 0's
  // buffers, which its first uploadMesh replaces; drawn as render() draws, into a 16 x 16 framebuffer
  // (the real one is sized by the first render), and read back.
  constexpr int kSize = 16;
  const float vertices[12] = {2, 2, 1, 1, 12, 3, 1, 1, 4, 13, 1, 1};
  const uint32_t indices[5] = {0, 1, 2, 0, 1};
  MeshSlot& slot = s.slots[0];
  gl.BindVertexArray(slot.vertexArray);
  s.upload(GL_ARRAY_BUFFER, slot.vertexBuffer, sizeof vertices, vertices, slot.vertexBytes);
  s.upload(GL_ELEMENT_ARRAY_BUFFER, slot.indexBuffer, sizeof indices, indices, slot.indexBytes);
  MeshSlot drawn = slot;
  drawn.triangleIndexCount = 3;
  drawn.pointCount = 1;
  drawn.orphanCount = 1;
  // Reference pixels to clip coordinates: x and y onto [-1, 1] of the small framebuffer, z = 0.5 w.
  Mat4 clip{};
  clip.m[0][0] = 2.0 / kSize;
  clip.m[0][3] = -1.0;
  clip.m[1][1] = 2.0 / kSize;
  clip.m[1][3] = -1.0;
  clip.m[2][3] = 0.5;
  clip.m[3][3] = 1.0;
  s.bindClearedFramebuffer(kSize, kSize);
  s.draw(drawn, clip, kSize, kSize);
  std::vector<float> readBack(size_t(kSize) * kSize * 4);
  gl.ReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_FLOAT, readBack.data());
  s.checkErrors("drawing the first mesh");
  EglContext::releaseCurrentContext();
}

void GlMeshRenderer::render(const Mat4& clip, const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer,
                            RenderExtras* extras) {
  Impl& s = *impl_;
  s.beginRender(grid);
  const MeshSlot& drawn = s.slots[s.slot];
  VS_CHECK(drawn.mesh != nullptr && drawn.mesh == s.mesh);
  s.draw(drawn, clip, grid.width, grid.height);
  finishRender(grid, texelMap, layer, extras);
}

void GlMeshRenderer::finishRender(const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer,
                                  RenderExtras* extras) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  // Framebuffer row 0 is image row 0 (MeshProjection.h): read back as it lies.
  const int width = grid.width, height = grid.height;
  const size_t n = size_t(width) * size_t(height);
  s.readBack.resize(n * 4);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, s.readBack.data());
  s.checkErrors("rendering the mesh");
  s.renderedWidth = width;
  s.renderedHeight = height;

  // One pass over the read-back, on the threads, row by row: each sample's orphan rule, edge flag,
  // depth and colour, every sample of the layer written once (holes included). The read-back is not
  // written during the pass, so the orphan rule reads the marks as drawn; its rejections are applied
  // to the read-back afterwards (the chroma and the extras read them).
  // A locally farthest orphan (mark 2) stays only in a hole of its own: a sample whose 4 neighbours
  // in the grid are drawn. In a disocclusion it would be a speck of background (DepthMesh.h).
  float* samples = s.readBack.data();
  auto drawn = [&](int x, int y) {
    return x < 0 || y < 0 || x >= width || y >= height || samples[(size_t(y) * size_t(width) + size_t(x)) * 4 + 3] != 0.0f;
  };
  auto rejectedOrphan = [&](int x, int y) {
    return !(drawn(x - 1, y) && drawn(x + 1, y) && drawn(x, y - 1) && drawn(x, y + 1));
  };
  const int channels = int(s.planes.size());
  VS_CHECK(channels >= 1 && channels <= 3);
  layer.resize(width, height, channels);
  s.edges.resize(n);
  std::mutex rejectedMutex;
  std::vector<size_t> rejected;
  s.withSampling([&](const auto& sample) {
    parallelRanges(height, [&](int y0, int y1) {
      for (int y = y0; y < y1; ++y) {
        const size_t rowStart = size_t(y) * size_t(width);
        for (int x = 0; x < width; ++x) {
          const size_t i = rowStart + size_t(x);
          const float* r = samples + i * 4;
          if (r[3] == 0.0f || (r[3] == 2.0f && rejectedOrphan(x, y))) {
            if (r[3] != 0.0f) {
              const std::lock_guard<std::mutex> lock(rejectedMutex);
              rejected.push_back(i);
            }
            s.edges[i] = 0;
            layer.inverseDepth[i] = kNoDepth;
            for (int k = 0; k < channels; ++k) layer.colour[k][i] = 0.0f;
            layer.edge[i] = 0;
            continue;
          }
          const uint8_t edge = s.edgeAt(r) ? 1 : 0;
          s.edges[i] = edge;
          const double u = texelMap.scale * r[0] + texelMap.offset, v = texelMap.scale * r[1] + texelMap.offset;
          layer.inverseDepth[i] = double(r[2]);
          for (int k = 0; k < channels; ++k) layer.colour[k][i] = sample(*s.planes[size_t(k)], u, v);
          layer.edge[i] = edge;
        }
      }
    });
  });
  for (size_t i : rejected) samples[i * 4 + 3] = 0.0f;

  if (extras) {
    extras->referenceU.assign(n, std::nanf(""));
    extras->referenceV.assign(n, std::nanf(""));
    for (size_t i = 0; i < n; ++i)
      if (samples[i * 4 + 3] != 0.0f) {
        extras->referenceU[i] = samples[i * 4];
        extras->referenceV[i] = samples[i * 4 + 1];
      }
  }
}

void GlMeshRenderer::setReferenceSphere(const SphereEdges& edges) { impl_->sphere = edges; }

void GlMeshRenderer::reuseForReadBack(std::vector<float>&& storage) {
  Impl& s = *impl_;
  if (storage.capacity() > s.readBack.capacity()) s.readBack.swap(storage);
  std::vector<float>().swap(storage);
}

void GlMeshRenderer::releaseRenderBuffers() {
  Impl& s = *impl_;
  std::vector<float>().swap(s.readBack);
  std::vector<uint8_t>().swap(s.edges);
  std::vector<const Plane*>().swap(s.planes);
  s.mesh = nullptr;
  for (MeshSlot& mesh : s.slots) mesh.mesh = nullptr;
  s.renderedWidth = s.renderedHeight = 0;
}

void GlMeshRenderer::uploadProjectedMesh(const ProjectedMesh& mesh) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  s.context.makeCurrent();
  VS_CHECK(mesh.mesh && mesh.attributes.size() == mesh.positions.size());
  VS_CHECK(mesh.triangles.size() + mesh.points.size() + mesh.farthestOrphans.size() <=
           size_t(std::numeric_limits<GLsizei>::max()));
  if (!s.projected) {
    auto pass = std::make_unique<ProjectedPass>();
    pass->program = linkProgram(gl, kProjectedVertexShader, kProjectedFragmentShader);
    pass->drawnMarkLocation = gl.GetUniformLocation(pass->program, "drawnMark");
    VS_CHECK(pass->drawnMarkLocation >= 0);
    gl.GenVertexArrays(1, &pass->vertexArray);
    gl.BindVertexArray(pass->vertexArray);
    gl.GenBuffers(1, &pass->positionBuffer);
    gl.GenBuffers(1, &pass->attributeBuffer);
    gl.GenBuffers(1, &pass->indexBuffer);
    gl.BindBuffer(GL_ARRAY_BUFFER, pass->positionBuffer);
    gl.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, pass->attributeBuffer);
    gl.VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(1);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, pass->indexBuffer);
    s.projected = std::move(pass);
  }
  ProjectedPass& p = *s.projected;
  gl.BindVertexArray(p.vertexArray);
  s.upload(GL_ARRAY_BUFFER, p.positionBuffer, GLsizeiptr(mesh.positions.size() * sizeof(float)), mesh.positions.data(),
           p.positionBytes);
  s.upload(GL_ARRAY_BUFFER, p.attributeBuffer, GLsizeiptr(mesh.attributes.size() * sizeof(float)),
           mesh.attributes.data(), p.attributeBytes);
  p.indices = mesh.triangles;
  p.indices.insert(p.indices.end(), mesh.points.begin(), mesh.points.end());
  p.indices.insert(p.indices.end(), mesh.farthestOrphans.begin(), mesh.farthestOrphans.end());
  s.upload(GL_ELEMENT_ARRAY_BUFFER, p.indexBuffer, GLsizeiptr(p.indices.size() * sizeof(uint32_t)), p.indices.data(),
           p.indexBytes);
  p.triangleIndexCount = GLsizei(mesh.triangles.size());
  p.pointCount = GLsizei(mesh.points.size());
  p.orphanCount = GLsizei(mesh.farthestOrphans.size());
  s.mesh = mesh.mesh;
  s.checkErrors("uploading the projected mesh");
}

void GlMeshRenderer::renderProjected(const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer,
                                     RenderExtras* extras) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  VS_CHECK(s.projected != nullptr);
  const ProjectedPass& p = *s.projected;
  s.beginRender(grid);
  gl.UseProgram(p.program);
  gl.BindVertexArray(p.vertexArray);
  // As render(): triangles, then points (mark 3), then the locally farthest orphans where nothing is drawn.
  gl.Uniform1f(p.drawnMarkLocation, 1.0f);
  if (p.triangleIndexCount > 0) gl.DrawElements(GL_TRIANGLES, p.triangleIndexCount, GL_UNSIGNED_INT, nullptr);
  gl.Uniform1f(p.drawnMarkLocation, 3.0f);
  if (p.pointCount > 0)
    gl.DrawElements(GL_POINTS, p.pointCount, GL_UNSIGNED_INT,
                    reinterpret_cast<const void*>(size_t(p.triangleIndexCount) * sizeof(uint32_t)));
  s.drawOrphans(p.drawnMarkLocation, p.orphanCount, size_t(p.triangleIndexCount + p.pointCount));
  finishRender(grid, texelMap, layer, extras);
}

void GlMeshRenderer::sampleRender(const std::vector<Plane>& planes, const TexelMap& texelMap, WarpedLayer& layer) const {
  const Impl& s = *impl_;
  const int width = s.renderedWidth, height = s.renderedHeight, channels = int(planes.size());
  VS_CHECK(channels >= 1 && channels <= 3 && width > 0);
  layer.reset(width, height, channels);
  const float* samples = s.readBack.data();
  s.withSampling([&](const auto& sample) {
    parallelRanges(height, [&](int y0, int y1) {
      for (size_t i = size_t(y0) * size_t(width); i < size_t(y1) * size_t(width); ++i) {
        const float* r = samples + i * 4;
        if (r[3] == 0.0f) continue;  // nothing drawn
        const double x = texelMap.scale * r[0] + texelMap.offset, y = texelMap.scale * r[1] + texelMap.offset;
        layer.inverseDepth[i] = double(r[2]);
        for (int k = 0; k < channels; ++k) layer.colour[k][i] = sample(planes[size_t(k)], x, y);
        layer.edge[i] = s.edges[i];
      }
    });
  });
}

void GlMeshRenderer::sampleChroma420(const std::vector<const Plane*>& planes, double sameSurface, WarpedLayer& layer) const {
  const Impl& s = *impl_;
  VS_CHECK(planes.size() == 2 && s.renderedWidth > 0);
  const int lumaWidth = s.renderedWidth, lumaHeight = s.renderedHeight;
  const int width = planes[0]->width, height = planes[0]->height;
  VS_CHECK(width == (lumaWidth + 1) / 2 && height == (lumaHeight + 1) / 2);
  layer.reset(width, height, 2);
  const float* samples = s.readBack.data();
  // Reference columns in a turn: the uploaded texture's width, for a reference that wraps; 0 none.
  const double turn = s.sphere.wrap && !s.planes.empty() ? double(s.planes[0]->width) : 0.0;
  s.withSampling([&](const auto& sample) {
  parallelRanges(height, [&](int j0, int j1) {
    for (int j = j0; j < j1; ++j)
      for (int i = 0; i < width; ++i) {
        // The 2 x 2 luma samples around chroma sample (i, j), whose centre is luma (2i + 0.5, 2j + 0.5).
        const float* block[2][2] = {{nullptr, nullptr}, {nullptr, nullptr}};
        const float* front = nullptr;
        int frontX = 0, frontY = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int x = 2 * i + dx, y = 2 * j + dy;
            if (x >= lumaWidth || y >= lumaHeight) continue;
            const float* r = samples + (size_t(y) * size_t(lumaWidth) + size_t(x)) * 4;
            if (r[3] == 0.0f) continue;
            block[dy][dx] = r;
            if (!front || r[2] > front[2]) front = r, frontX = dx, frontY = dy;
          }
        if (!front) continue;  // a hole
        auto onFront = [&](const float* r) { return r && double(r[2]) >= (1.0 - sameSurface) * double(front[2]); };
        // The column a sample shows, within half a turn of the front sample's for a reference that wraps
        // (a full-circle ERP one: setReferenceSphere), so samples on both sides of its seam average well.
        auto column = [&](const float* r) {
          const double u = r[0];
          return turn > 0.0 ? u + turn * std::round((front[0] - u) / turn) : u;
        };
        // Where the front surface shows at the chroma centre: from the front sample, half a luma pixel
        // right or left and down or up, along the reference positions of its neighbours in the block on
        // the same surface (where there is none, one reference pixel per luma pixel).
        const float* across = block[frontY][1 - frontX];
        const float* down = block[1 - frontY][frontX];
        const double sx = frontX == 0 ? 0.5 : -0.5, sy = frontY == 0 ? 0.5 : -0.5;
        double ux = 1.0, vx = 0.0, uy = 0.0, vy = 1.0;  // d(u, v) / dx and d(u, v) / dy
        if (onFront(across)) ux = (column(across) - front[0]) * 2.0 * sx, vx = (across[1] - front[1]) * 2.0 * sx;
        if (onFront(down)) uy = (column(down) - front[0]) * 2.0 * sy, vy = (down[1] - front[1]) * 2.0 * sy;
        double u = front[0] + sx * ux + sy * uy, v = front[1] + sx * vx + sy * vy;
        double q = front[2];
        auto edgeOf = [&](const float* r) { return s.edges[size_t(r - samples) / 4] != 0; };
        bool edge = edgeOf(front);
        // All four on one surface: their mean, which is the centre where the mapping is affine.
        if (onFront(block[0][0]) && onFront(block[0][1]) && onFront(block[1][0]) && onFront(block[1][1])) {
          u = v = q = 0.0;
          for (const auto& row : block)
            for (const float* r : row) {
              u += 0.25 * column(r);
              v += 0.25 * r[1];
              q += 0.25 * r[2];
              edge = edge || edgeOf(r);
            }
        }
        const size_t c = size_t(j) * size_t(width) + size_t(i);
        layer.inverseDepth[c] = q;
        layer.edge[c] = edge ? 1 : 0;
        // Chroma texel position of reference pixel (u, v): (u, v) / 2 - 1/4.
        sampleBoth(sample, *planes[0], *planes[1], 0.5 * u - 0.25, 0.5 * v - 0.25, layer.colour[0][c], layer.colour[1][c]);
      }
  });
  });
}

}  // namespace vs
