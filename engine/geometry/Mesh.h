#pragma once
// Unit primitives and meshes, split into faces; each face owns one chart of the texture
// atlas (docs/internals/LIKELIHOOD.md, "Charts"). Geometry is in the node's own frame; a hypothesis
// only changes the node matrices, never these vertices.

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "engine/scene/Scene.h"

namespace vkr {

// A face: a run of triangles sharing one planar-ish parametrisation `face_uv` ∈ [0,1]².
// face_uv places a vertex inside the face's chart, and is also the albedo texture
// coordinate (a node's albedo image covers each of its faces once).
struct Face {
  int first_triangle = 0;
  int triangle_count = 0;
};

struct Mesh {
  std::vector<Eigen::Vector3f> positions;  // node frame
  std::vector<Eigen::Vector3f> normals;    // unit, outward
  std::vector<Eigen::Vector2f> face_uv;    // per vertex, in [0,1]²
  std::vector<uint32_t> indices;           // triangles, counter-clockwise seen from outside
  std::vector<Face> faces;                 // cover all triangles, in order

  int TriangleCount() const { return int(indices.size() / 3); }
};

// The unit primitives (docs/guide/SCENE_FORMAT.md, "nodes"), in the box [-0.5,0.5]²×[0,1].
//   plane: the square at z=0 facing +z, 1 face.
//   box: 6 faces.  prism: 2 roof slopes, 2 gables, 1 base = 5 faces.
//   cylinder: `segments` around, side as 1 face (u = angle / 360°, v = 1 − z), 2 caps.
// face_uv shows an albedo image upright to a viewer outside, z up: v = 0 is the image's top
// row and the highest z of vertical faces (Primitives.cpp spells out every face).
Mesh MakePrimitive(PrimitiveKind kind, int cylinder_segments = 32);

// Triangles of every mesh of a glTF/GLB file (node transforms applied, in the file's
// frame; glTF is Y-up, converted to vkrecon's Z-up by (x, y, z) → (x, -z, y)).
// With TEXCOORD_0 all triangles form one face using those coordinates (wrapped into
// [0,1]); without, each triangle is its own face. Throws InputError naming the file.
Mesh LoadGltfMesh(const std::filesystem::path& file);

}  // namespace vkr
