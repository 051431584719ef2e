#include "Mesh/GlMeshRenderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "Common/Error.h"

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
layout(location = 1) in float boundary;
uniform mat4 clipFromReference;
out vec3 referencePixel;
out vec2 inverseDepthRatio;
out float edge;
flat out vec2 pointClipZW;
void main() {
  gl_Position = clipFromReference * vertex;
  referencePixel = vertex.xyz;
  inverseDepthRatio = vec2(vertex.w, gl_Position.w);
  edge = boundary;
  pointClipZW = gl_Position.zw;
}
)";

// Texture look-up by hand with texelFetch, in float, never with the hardware filter (whose weights
// are 8-bit fixed point on most GPUs and on llvmpipe). Two ways:
// - ViewSyn's sampling (SubPixelSampler, Precision and Filter): the position is rounded to the
//   1/precision grid and the separable kernel of that phase is applied, with the same kernels.
// - exact bilinear at the unrounded position.
// Texel (i, j) sits at texel position (i, j); outside the plane the border texels repeat.
const char* const kFragmentShader = R"(#version 330 core
in vec3 referencePixel;
in vec2 inverseDepthRatio;
in float edge;
flat in vec2 pointClipZW;
uniform int drawingPoints;  // 1: a point; its fragments look up where their own centre looks
uniform float drawnMark;    // 1: drawn; 2: a locally farthest orphan (kept only in a lone hole)
uniform mat4 referenceFromClip;
uniform vec2 viewportSize;
uniform sampler2D referenceTexture;
uniform vec2 texelMap;      // texel position = texelMap.x * reference pixel + texelMap.y
uniform int exactBilinear;  // 1: bilinear at the exact position; 0: the kernels below
uniform float kernelPrecision;  // 1, 2 or 4
uniform int taps;           // kernel taps (2, 4 or 6)
uniform int firstTap;       // offset of the first tap from the integer part
uniform float kernel[24];   // kernelPrecision x taps weights, phase-major
layout(location = 0) out vec4 colourAndDepth;
layout(location = 1) out vec4 referenceAndFlags;
vec4 texel(ivec2 p, ivec2 size) { return texelFetch(referenceTexture, clamp(p, ivec2(0), size - 1), 0); }
vec4 sampleTexture(vec2 p) {
  ivec2 size = textureSize(referenceTexture, 0);
  if (exactBilinear == 1) {
    vec2 base = floor(p);
    vec2 f = p - base;
    ivec2 i = ivec2(base);
    vec4 top = mix(texel(i, size), texel(i + ivec2(1, 0), size), f.x);
    vec4 bottom = mix(texel(i + ivec2(0, 1), size), texel(i + ivec2(1, 1), size), f.x);
    return mix(top, bottom, f.y);
  }
  vec2 grid = floor(p * kernelPrecision + 0.5);
  vec2 base = floor(grid / kernelPrecision);
  ivec2 phase = ivec2(grid - base * kernelPrecision);
  ivec2 i = ivec2(base) + ivec2(firstTap);
  if (phase == ivec2(0)) return texel(ivec2(base), size);
  vec4 sum = vec4(0.0);
  for (int ty = 0; ty < taps; ++ty) {
    float wy = kernel[phase.y * taps + ty];
    if (wy == 0.0) continue;
    vec4 row = vec4(0.0);
    for (int tx = 0; tx < taps; ++tx) {
      float wx = kernel[phase.x * taps + tx];
      if (wx != 0.0) row += wx * texel(i + ivec2(tx, ty), size);
    }
    sum += wy * row;
  }
  return sum;
}
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
  colourAndDepth = vec4(sampleTexture(reference * texelMap.x + texelMap.y).rgb, inverseDepth);
  referenceAndFlags = vec4(reference, edge > 0.0 ? 1.0 : 0.0, drawnMark);
}
)";

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

}  // namespace

struct GlMeshRenderer::Impl {
  EglContext context;
  const GlFunctions& gl;
  GLuint program = 0, vertexArray = 0, vertexBuffer = 0, boundaryBuffer = 0, indexBuffer = 0, texture = 0;
  GLsizei pointCount = 0;
  std::vector<uint32_t> indices;  // triangles, then points
  GLuint framebuffer = 0, colourBuffers[2] = {0, 0}, depthBuffer = 0;
  GLint clipLocation = -1, referenceFromClipLocation = -1, viewportLocation = -1, drawingPointsLocation = -1,
        texelMapLocation = -1, exactBilinearLocation = -1, precisionLocation = -1, tapsLocation = -1,
        firstTapLocation = -1, kernelLocation = -1, drawnMarkLocation = -1;
  GLsizei orphanCount = 0;  // locally farthest orphans, after the points in `indices`
  int framebufferWidth = 0, framebufferHeight = 0;
  GLsizei triangleIndexCount = 0;  // indices of the triangles at the start of `indices`
  int textureChannels = 0;
  GLint maxRenderbufferSize = 0, maxTextureSize = 0, maxViewport[2] = {0, 0};
  std::vector<float> readBack, texels;

  Impl() : gl(context.gl()) {
    const GLuint vertexShader = compileShader(gl, GL_VERTEX_SHADER, kVertexShader);
    GLuint fragmentShader = 0;
    try {
      fragmentShader = compileShader(gl, GL_FRAGMENT_SHADER, kFragmentShader);
    } catch (...) {
      gl.DeleteShader(vertexShader);
      throw;
    }
    program = gl.CreateProgram();
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
    clipLocation = gl.GetUniformLocation(program, "clipFromReference");
    referenceFromClipLocation = gl.GetUniformLocation(program, "referenceFromClip");
    viewportLocation = gl.GetUniformLocation(program, "viewportSize");
    drawingPointsLocation = gl.GetUniformLocation(program, "drawingPoints");
    texelMapLocation = gl.GetUniformLocation(program, "texelMap");
    exactBilinearLocation = gl.GetUniformLocation(program, "exactBilinear");
    precisionLocation = gl.GetUniformLocation(program, "kernelPrecision");
    tapsLocation = gl.GetUniformLocation(program, "taps");
    firstTapLocation = gl.GetUniformLocation(program, "firstTap");
    kernelLocation = gl.GetUniformLocation(program, "kernel");
    drawnMarkLocation = gl.GetUniformLocation(program, "drawnMark");
    VS_CHECK(clipLocation >= 0 && referenceFromClipLocation >= 0 && viewportLocation >= 0 && drawingPointsLocation >= 0 &&
             texelMapLocation >= 0 && exactBilinearLocation >= 0 && precisionLocation >= 0 &&
             tapsLocation >= 0 && firstTapLocation >= 0 && kernelLocation >= 0 && drawnMarkLocation >= 0);
    gl.UseProgram(program);
    gl.Uniform1i(exactBilinearLocation, 1);

    gl.GenVertexArrays(1, &vertexArray);
    gl.BindVertexArray(vertexArray);
    gl.GenBuffers(1, &vertexBuffer);
    gl.GenBuffers(1, &boundaryBuffer);
    gl.GenBuffers(1, &indexBuffer);
    gl.BindBuffer(GL_ARRAY_BUFFER, vertexBuffer);
    gl.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, boundaryBuffer);
    gl.VertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(1);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer);  // part of the vertex array's state

    gl.GenTextures(1, &texture);
    gl.BindTexture(GL_TEXTURE_2D, texture);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);

    gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRenderbufferSize);
    gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize);
    gl.GetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    checkErrors("setting up the renderer");
  }

  ~Impl() {
    context.makeCurrent();
    gl.DeleteFramebuffers(1, &framebuffer);
    gl.DeleteRenderbuffers(2, colourBuffers);
    gl.DeleteRenderbuffers(1, &depthBuffer);
    gl.DeleteTextures(1, &texture);
    gl.DeleteBuffers(1, &vertexBuffer);
    gl.DeleteBuffers(1, &boundaryBuffer);
    gl.DeleteBuffers(1, &indexBuffer);
    gl.DeleteVertexArrays(1, &vertexArray);
    gl.DeleteProgram(program);
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
      gl.GenRenderbuffers(2, colourBuffers);
      gl.GenRenderbuffers(1, &depthBuffer);
    }
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    for (int k = 0; k < 2; ++k) {
      gl.BindRenderbuffer(GL_RENDERBUFFER, colourBuffers[k]);
      gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA32F, framebufferWidth, framebufferHeight);
      gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + k, GL_RENDERBUFFER, colourBuffers[k]);
    }
    gl.BindRenderbuffer(GL_RENDERBUFFER, depthBuffer);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, framebufferWidth, framebufferHeight);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthBuffer);
    const GLenum drawBuffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl.DrawBuffers(2, drawBuffers);
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
};

GlMeshRenderer::GlMeshRenderer() : impl_(std::make_unique<Impl>()) {}

GlMeshRenderer::~GlMeshRenderer() = default;

const std::string& GlMeshRenderer::description() const { return impl_->context.description(); }

void GlMeshRenderer::setSampling(const SubPixelSampler* sampler) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  s.context.makeCurrent();
  gl.UseProgram(s.program);
  gl.Uniform1i(s.exactBilinearLocation, sampler ? 0 : 1);
  if (sampler) {
    const int count = sampler->precision() * sampler->taps();
    VS_CHECK(count <= 24);
    gl.Uniform1f(s.precisionLocation, float(sampler->precision()));
    gl.Uniform1i(s.tapsLocation, sampler->taps());
    gl.Uniform1i(s.firstTapLocation, sampler->first());
    gl.Uniform1fv(s.kernelLocation, count, sampler->kernel(0));
  }
  s.checkErrors("setting the texture sampling");
}

void GlMeshRenderer::uploadMesh(const DepthMesh& mesh) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  s.context.makeCurrent();
  VS_CHECK(mesh.vertices.size() == mesh.vertexCount() * 4 && mesh.boundary.size() == mesh.vertexCount());
  VS_CHECK(mesh.triangles.size() + mesh.points.size() + mesh.farthestOrphans.size() <=
           size_t(std::numeric_limits<GLsizei>::max()));
  gl.BindVertexArray(s.vertexArray);
  gl.BindBuffer(GL_ARRAY_BUFFER, s.vertexBuffer);
  gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.vertices.size() * sizeof(float)), mesh.vertices.data(), GL_STREAM_DRAW);
  gl.BindBuffer(GL_ARRAY_BUFFER, s.boundaryBuffer);
  gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.boundary.size() * sizeof(float)), mesh.boundary.data(), GL_STREAM_DRAW);
  s.indices = mesh.triangles;
  s.indices.insert(s.indices.end(), mesh.points.begin(), mesh.points.end());
  s.indices.insert(s.indices.end(), mesh.farthestOrphans.begin(), mesh.farthestOrphans.end());
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(s.indices.size() * sizeof(uint32_t)), s.indices.data(),
                GL_STREAM_DRAW);
  s.triangleIndexCount = GLsizei(mesh.triangles.size());
  s.pointCount = GLsizei(mesh.points.size());
  s.orphanCount = GLsizei(mesh.farthestOrphans.size());
  s.checkErrors("uploading the mesh");
}

void GlMeshRenderer::uploadTexture(const std::vector<const Plane*>& planes) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  s.context.makeCurrent();
  VS_CHECK(!planes.empty() && planes.size() <= 3);
  const int width = planes[0]->width, height = planes[0]->height, channels = int(planes.size());
  for (const Plane* plane : planes) VS_CHECK(plane->width == width && plane->height == height);
  if (width > s.maxTextureSize || height > s.maxTextureSize)
    throw InputError("a " + std::to_string(width) + " x " + std::to_string(height) +
                     " reference picture exceeds this OpenGL's texture size limit " + std::to_string(s.maxTextureSize) +
                     " (" + s.context.description() + ")");
  const size_t n = size_t(width) * size_t(height);
  s.texels.resize(n * size_t(channels));
  for (int c = 0; c < channels; ++c) {
    const uint16_t* samples = planes[size_t(c)]->samples.data();
    for (size_t i = 0; i < n; ++i) s.texels[i * size_t(channels) + size_t(c)] = float(samples[i]);
  }
  static const GLint internalFormats[3] = {GL_R32F, GL_RG32F, GL_RGB32F};
  static const GLenum formats[3] = {GL_RED, GL_RG, GL_RGB};
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, s.texture);
  // Row 0 of the upload is image row 0: the same row order as the framebuffer (MeshProjection.h).
  gl.TexImage2D(GL_TEXTURE_2D, 0, internalFormats[channels - 1], width, height, 0, formats[channels - 1], GL_FLOAT,
                s.texels.data());
  s.textureChannels = channels;
  s.checkErrors("uploading the reference texture");
}

void GlMeshRenderer::render(const Mat4& clip, const RenderGrid& grid, const TexelMap& texelMap, WarpedLayer& layer,
                            RenderExtras* extras) {
  Impl& s = *impl_;
  const GlFunctions& gl = s.gl;
  s.context.makeCurrent();
  VS_CHECK(s.textureChannels > 0 && grid.width > 0 && grid.height > 0);
  s.ensureFramebuffer(grid.width, grid.height);

  gl.BindFramebuffer(GL_FRAMEBUFFER, s.framebuffer);
  gl.Viewport(0, 0, grid.width, grid.height);
  const float clearColour[4] = {0.0f, 0.0f, 0.0f, float(kNoDepth)};
  const float clearReference[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float clearDepth = 1.0f;
  gl.ClearBufferfv(GL_COLOR, 0, clearColour);
  gl.ClearBufferfv(GL_COLOR, 1, clearReference);
  gl.ClearBufferfv(GL_DEPTH, 0, &clearDepth);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);  // smaller z_ndc is larger q: nearer
  gl.Disable(GL_CULL_FACE);
  gl.Disable(GL_BLEND);

  gl.UseProgram(s.program);
  float matrix[16];
  toGlMatrix(clip, matrix);
  gl.UniformMatrix4fv(s.clipLocation, 1, GL_FALSE, matrix);
  // Points look up the texture along their fragments' own rays (the shader's drawingPoints); where the
  // matrix cannot be inverted they keep the vertex's position.
  Mat4 back;
  const bool invertible = inverse(clip, back);
  toGlMatrix(back, matrix);
  gl.UniformMatrix4fv(s.referenceFromClipLocation, 1, GL_FALSE, matrix);
  gl.Uniform2f(s.viewportLocation, float(grid.width), float(grid.height));
  gl.Uniform1i(s.drawingPointsLocation, 0);
  gl.Uniform1f(s.drawnMarkLocation, 1.0f);
  gl.Uniform2f(s.texelMapLocation, float(texelMap.scale), float(texelMap.offset));
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, s.texture);
  gl.BindVertexArray(s.vertexArray);
  if (s.triangleIndexCount > 0) gl.DrawElements(GL_TRIANGLES, s.triangleIndexCount, GL_UNSIGNED_INT, nullptr);
  // One-pixel points (the default point size) after the triangles: the depth test keeps the nearer.
  gl.Uniform1i(s.drawingPointsLocation, invertible ? 1 : 0);
  if (s.pointCount > 0)
    gl.DrawElements(GL_POINTS, s.pointCount, GL_UNSIGNED_INT,
                    reinterpret_cast<const void*>(size_t(s.triangleIndexCount) * sizeof(uint32_t)));
  // Locally farthest orphans last, only where nothing is drawn: every fragment's window depth is 1, the
  // cleared value, and passes GL_LEQUAL there only. Marked 2; kept below only in a lone hole.
  if (s.orphanCount > 0) {
    gl.Uniform1f(s.drawnMarkLocation, 2.0f);
    gl.DepthRange(1.0, 1.0);
    gl.DepthFunc(GL_LEQUAL);
    gl.DrawElements(GL_POINTS, s.orphanCount, GL_UNSIGNED_INT,
                    reinterpret_cast<const void*>(size_t(s.triangleIndexCount + s.pointCount) * sizeof(uint32_t)));
    gl.DepthRange(0.0, 1.0);
    gl.DepthFunc(GL_LESS);
  }

  // Framebuffer row 0 is image row 0 (MeshProjection.h): read back as it lies.
  const size_t n = size_t(grid.width) * size_t(grid.height);
  s.readBack.resize(n * 8);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.ReadPixels(0, 0, grid.width, grid.height, GL_RGBA, GL_FLOAT, s.readBack.data());
  gl.ReadBuffer(GL_COLOR_ATTACHMENT1);
  gl.ReadPixels(0, 0, grid.width, grid.height, GL_RGBA, GL_FLOAT, s.readBack.data() + n * 4);
  s.checkErrors("rendering the mesh");

  const int channels = s.textureChannels;
  layer.reset(grid.width, grid.height, channels);
  if (extras) {
    extras->referenceU.assign(n, std::nanf(""));
    extras->referenceV.assign(n, std::nanf(""));
  }
  const float* colour = s.readBack.data();
  const float* reference = s.readBack.data() + n * 4;
  // A locally farthest orphan (mark 2) stays only in a hole of its own: a sample whose 4 neighbours
  // in the grid are drawn. In a disocclusion it would be a speck of background (DepthMesh.h).
  const int width = grid.width, height = grid.height;
  auto drawn = [&](int x, int y) { return x < 0 || y < 0 || x >= width || y >= height || reference[(size_t(y) * width + x) * 4 + 3] != 0.0f; };
  for (size_t i = 0; i < n; ++i) {
    const float* c = colour + i * 4;
    const float* r = reference + i * 4;
    if (r[3] == 0.0f) continue;  // nothing drawn
    if (r[3] == 2.0f) {
      const int x = int(i % size_t(width)), y = int(i / size_t(width));
      if (!(drawn(x - 1, y) && drawn(x + 1, y) && drawn(x, y - 1) && drawn(x, y + 1))) continue;
    }
    layer.inverseDepth[i] = double(c[3]);
    for (int k = 0; k < channels; ++k) layer.colour[k][i] = c[k];
    layer.edge[i] = r[2] > 0.5f ? 1 : 0;
    if (extras) {
      extras->referenceU[i] = r[0];
      extras->referenceV[i] = r[1];
    }
  }
}

}  // namespace vs
