#include "Mesh/MeshPly.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <vector>

#include "Common/Error.h"
#include "Synth/Colour.h"

namespace vs {

namespace {

void putLittleEndian(std::vector<char>& out, uint32_t value) {
  for (int k = 0; k < 4; ++k) out.push_back(char((value >> (8 * k)) & 0xff));
}

void putFloat(std::vector<char>& out, float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  putLittleEndian(out, bits);
}

uint8_t to8Bit(uint16_t sample, int bitDepth) {
  if (bitDepth == 8) return uint8_t(sample);
  const int shift = bitDepth - 8;
  return uint8_t(std::min(255, (int(sample) + (1 << (shift - 1))) >> shift));
}

}  // namespace

std::string plyPathForView(const std::string& path, const std::string& label) {
  std::string lower = label;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  const bool hasExtension = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  std::string extension = hasExtension ? path.substr(dot) : std::string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (extension == ".ply") return path.substr(0, dot) + "_" + lower + path.substr(dot);
  return path + "_" + lower + ".ply";
}

void writeMeshPly(const std::string& path, const DepthMesh& mesh, const Camera& reference, const Frame& texture) {
  SafeOutputFile file(path, {}, "MeshPlyOutput");
  writeMeshPly(file, mesh, reference, texture);
  file.commit();
}

void writeMeshPly(SafeOutputFile& file, const DepthMesh& mesh, const Camera& reference, const Frame& texture) {
  const FrameFormat& format = texture.format;
  Frame rgb;
  const bool colour = format.chroma != ChromaFormat::Yuv400;
  if (colour) yuvToRgb(texture, rgb);

  std::vector<int64_t> newIndex(mesh.vertexCount(), -1);
  std::vector<char> vertexBytes;
  int64_t vertexCount = 0;
  for (int r = 0; r < mesh.rows; ++r)
    for (int c = 0; c < mesh.columns; ++c) {
      const size_t i = size_t(r) * size_t(mesh.columns) + size_t(c);
      if (!mesh.valid[i]) continue;
      const float* v = &mesh.vertices[i * 4];
      if (!(v[3] > 0.0f)) continue;  // at infinity
      const double u = mesh.gridU[size_t(c)], vv = mesh.gridV[size_t(r)];
      // The vertex's depth: z = a / w, or for an ERP camera the distance 1 / w (Mesh/MeshErp.h).
      const double depth = reference.isEquirectangular() ? 1.0 / double(v[3]) : double(v[2]) / double(v[3]);
      const Vec3 world = reference.cameraToWorld(reference.pixelToCamera(u, vv, depth));
      if (!isFinite(world)) continue;
      newIndex[i] = vertexCount++;
      putFloat(vertexBytes, float(world.x));
      putFloat(vertexBytes, float(world.y));
      putFloat(vertexBytes, float(world.z));
      const long column = std::lround(u);  // an ERP wrap column (u = W) shows column 0
      const int px = std::clamp(int(reference.isEquirectangular() ? column % format.width : column), 0, format.width - 1);
      const int py = std::clamp(int(std::lround(vv)), 0, format.height - 1);
      for (int k = 0; k < 3; ++k) {
        const uint16_t sample = colour ? rgb.planes[k].at(px, py) : texture.planes[0].at(px, py);
        vertexBytes.push_back(char(to8Bit(sample, format.bitDepth)));
      }
    }
  std::vector<char> faceBytes;
  int64_t faceCount = 0;
  for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const int64_t a = newIndex[mesh.triangles[t]], b = newIndex[mesh.triangles[t + 1]], c = newIndex[mesh.triangles[t + 2]];
    if (a < 0 || b < 0 || c < 0) continue;
    faceBytes.push_back(char(3));
    for (int64_t index : {a, b, c}) putLittleEndian(faceBytes, uint32_t(index));
    ++faceCount;
  }

  file.write("ply\nformat binary_little_endian 1.0\ncomment MeshRender mesh of camera " + reference.name +
             " (world coordinates)\nelement vertex " + std::to_string(vertexCount) +
             "\nproperty float x\nproperty float y\nproperty float z\n"
             "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face " +
             std::to_string(faceCount) + "\nproperty list uchar int vertex_indices\nend_header\n");
  file.write(vertexBytes.data(), vertexBytes.size());
  file.write(faceBytes.data(), faceBytes.size());
}

}  // namespace vs
