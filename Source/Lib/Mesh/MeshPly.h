#pragma once
// MeshPlyOutput: a reference view's mesh as a PLY file for MeshLab or Blender (doc/meshrender.md, "PLY").
//
// binary_little_endian 1.0; vertex: float x, y, z (world coordinates, the camera file's units), uchar
// red, green, blue (the reference texture at the vertex's pixel, BT.601 as ColorSpace 1 converts,
// scaled to 8 bits); face: list uchar int vertex_indices (triangles). Vertices at infinity (Zfar = inf)
// have no finite position: they and their triangles are left out.
#include <string>

#include "Common/SafeOutput.h"

#include "Common/Camera.h"
#include "Common/Frame.h"
#include "Mesh/DepthMesh.h"

namespace vs {

// Writes `mesh`, built from `reference`'s depth, coloured from `texture` (the same frame). Throws
// InputError naming the file when it cannot be written.
void writeMeshPly(const std::string& path, const DepthMesh& mesh, const Camera& reference, const Frame& texture);
// The same into `file` (not committed: the caller renames it into place when its run ends well).
void writeMeshPly(SafeOutputFile& file, const DepthMesh& mesh, const Camera& reference, const Frame& texture);

// The file of one view: "dir/mesh.ply" with label "Left" -> "dir/mesh_left.ply"; a name without the
// .ply extension gets it appended after the label.
std::string plyPathForView(const std::string& path, const std::string& label);

}  // namespace vs
