// The unit primitives (docs/guide/SCENE_FORMAT.md, "nodes"), in the box [-0.5,0.5]²×[0,1], split
// into faces that each own one atlas chart (docs/internals/LIKELIHOOD.md, "Charts").
//
// face_uv convention (shared by every primitive, and by the albedo images): a face shows
// its albedo image *upright and unmirrored to a viewer outside it, with z up*. u grows to
// the viewer's right, v grows downwards, and v = 0 is the image's top row (as Image and
// SampleRepeat store it). Concretely:
//   vertical faces and roof slopes: v = 0 at the highest z; u to the right seen from outside
//     (for the box's -y face u runs along +x, for +x along +y, +y along -x, -x along -y).
//   top faces (box top, plane, cylinder top cap), seen from above: u along +x, v = 0 at y =
//     +0.5 — a map with north (+y) up.
//   bottom faces, seen from below with +y still "up": u along -x, v = 0 at y = +0.5.
//   prism gables: (0,1) bottom-left, (1,1) bottom-right, (0.5,0) the ridge end.
//   cylinder side: u = angle/360° counter-clockwise from +x seen from above (that is to the
//     right of a viewer outside), v = 1 − z. The seam at angle 0 has duplicated vertices
//     with u = 0 and u = 1.
// The cylinder caps use the top/bottom-face rule above rather than a plain (x+½, y+½), so a
// cap and a box top of the same albedo look the same.

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "engine/geometry/Mesh.h"

namespace vkr {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3f;

// Appends one vertex and returns its index.
uint32_t AddVertex(Mesh& m, const Vector3f& p, const Vector3f& n, const Vector2f& uv) {
  m.positions.push_back(p);
  m.normals.push_back(n);
  m.face_uv.push_back(uv);
  return uint32_t(m.positions.size() - 1);
}

void AddTriangle(Mesh& m, uint32_t a, uint32_t b, uint32_t c) {
  m.indices.insert(m.indices.end(), {a, b, c});
}

// Starts a face at the current end of the index list; EndFace closes it.
void BeginFace(Mesh& m) { m.faces.push_back({m.TriangleCount(), 0}); }
void EndFace(Mesh& m) { m.faces.back().triangle_count = m.TriangleCount() - m.faces.back().first_triangle; }

// A flat quad face given by its corners as a viewer outside sees them: bottom-left,
// bottom-right, top-right, top-left. That viewer's right × up is the outward normal, so the
// triangles (bl, br, tr) and (bl, tr, tl) are counter-clockwise from outside.
void AddQuadFace(Mesh& m, const Vector3f& bl, const Vector3f& br, const Vector3f& tr,
                 const Vector3f& tl) {
  const Vector3f n = (br - bl).cross(tl - bl).normalized();
  BeginFace(m);
  const uint32_t a = AddVertex(m, bl, n, {0, 1});
  const uint32_t b = AddVertex(m, br, n, {1, 1});
  const uint32_t c = AddVertex(m, tr, n, {1, 0});
  const uint32_t d = AddVertex(m, tl, n, {0, 0});
  AddTriangle(m, a, b, c);
  AddTriangle(m, a, c, d);
  EndFace(m);
}

// A triangular face: bottom-left, bottom-right and apex as seen from outside.
void AddTriangleFace(Mesh& m, const Vector3f& bl, const Vector3f& br, const Vector3f& apex) {
  const Vector3f n = (br - bl).cross(apex - bl).normalized();
  BeginFace(m);
  AddTriangle(m, AddVertex(m, bl, n, {0, 1}), AddVertex(m, br, n, {1, 1}),
              AddVertex(m, apex, n, {0.5f, 0}));
  EndFace(m);
}

// The horizontal square at height z, facing +z (up) or -z.
void AddHorizontalSquare(Mesh& m, float z, bool up) {
  if (up) {
    AddQuadFace(m, {-0.5f, -0.5f, z}, {0.5f, -0.5f, z}, {0.5f, 0.5f, z}, {-0.5f, 0.5f, z});
  } else {
    // Seen from below with +y up, the viewer's right is -x.
    AddQuadFace(m, {0.5f, -0.5f, z}, {-0.5f, -0.5f, z}, {-0.5f, 0.5f, z}, {0.5f, 0.5f, z});
  }
}

Mesh MakePlane() {
  Mesh m;
  AddHorizontalSquare(m, 0.0f, true);
  return m;
}

// Faces in the order -y, +x, +y, -x (walking around counter-clockwise), top, bottom.
Mesh MakeBox() {
  Mesh m;
  const float h = 0.5f;
  AddQuadFace(m, {-h, -h, 0}, {h, -h, 0}, {h, -h, 1}, {-h, -h, 1});  // -y, right = +x
  AddQuadFace(m, {h, -h, 0}, {h, h, 0}, {h, h, 1}, {h, -h, 1});      // +x, right = +y
  AddQuadFace(m, {h, h, 0}, {-h, h, 0}, {-h, h, 1}, {h, h, 1});      // +y, right = -x
  AddQuadFace(m, {-h, h, 0}, {-h, -h, 0}, {-h, -h, 1}, {-h, h, 1});  // -x, right = -y
  AddHorizontalSquare(m, 1.0f, true);
  AddHorizontalSquare(m, 0.0f, false);
  return m;
}

// Faces: slope facing -y, slope facing +y, gable at x=+0.5, gable at x=-0.5, base.
Mesh MakePrism() {
  Mesh m;
  const float h = 0.5f;
  AddQuadFace(m, {-h, -h, 0}, {h, -h, 0}, {h, 0, 1}, {-h, 0, 1});  // slope -y, right = +x
  AddQuadFace(m, {h, h, 0}, {-h, h, 0}, {-h, 0, 1}, {h, 0, 1});    // slope +y, right = -x
  AddTriangleFace(m, {h, -h, 0}, {h, h, 0}, {h, 0, 1});            // gable +x, right = +y
  AddTriangleFace(m, {-h, h, 0}, {-h, -h, 0}, {-h, 0, 1});         // gable -x, right = -y
  AddHorizontalSquare(m, 0.0f, false);
  return m;
}

// Faces: side, top cap, bottom cap. Side normals are smooth (radial); caps are flat fans.
Mesh MakeCylinder(int segments) {
  if (segments < 3) throw std::invalid_argument("MakePrimitive: a cylinder needs >= 3 segments");
  Mesh m;
  const double step = 2.0 * M_PI / segments;
  BeginFace(m);
  // segments + 1 columns: the last repeats the first at u = 1, so the seam does not wrap
  // the whole texture backwards across one segment.
  for (int i = 0; i <= segments; ++i) {
    const double a = i == segments ? 0.0 : i * step;
    const Vector3f n(float(std::cos(a)), float(std::sin(a)), 0.0f);
    const float u = float(i) / float(segments);
    AddVertex(m, {0.5f * n.x(), 0.5f * n.y(), 0.0f}, n, {u, 1.0f});
    AddVertex(m, {0.5f * n.x(), 0.5f * n.y(), 1.0f}, n, {u, 0.0f});
  }
  for (int i = 0; i < segments; ++i) {
    const uint32_t b0 = 2 * i, t0 = b0 + 1, b1 = b0 + 2, t1 = b0 + 3;
    AddTriangle(m, b0, b1, t1);
    AddTriangle(m, b0, t1, t0);
  }
  EndFace(m);

  for (int cap = 0; cap < 2; ++cap) {
    const bool top = cap == 0;
    const float z = top ? 1.0f : 0.0f;
    const Vector3f n(0, 0, top ? 1.0f : -1.0f);
    BeginFace(m);
    // Seen from outside, u runs along +x on the top cap and along -x on the bottom one.
    auto uv = [top](float x, float y) { return Vector2f(top ? x + 0.5f : 0.5f - x, 0.5f - y); };
    const uint32_t centre = AddVertex(m, {0, 0, z}, n, uv(0, 0));
    const uint32_t first = uint32_t(m.positions.size());
    for (int i = 0; i < segments; ++i) {
      const float x = 0.5f * float(std::cos(i * step)), y = 0.5f * float(std::sin(i * step));
      AddVertex(m, {x, y, z}, n, uv(x, y));
    }
    for (int i = 0; i < segments; ++i) {
      const uint32_t a = first + i, b = first + (i + 1) % segments;
      if (top) AddTriangle(m, centre, a, b);
      else AddTriangle(m, centre, b, a);
    }
    EndFace(m);
  }
  return m;
}

}  // namespace

Mesh MakePrimitive(PrimitiveKind kind, int cylinder_segments) {
  switch (kind) {
    case PrimitiveKind::None: return {};
    case PrimitiveKind::Plane: return MakePlane();
    case PrimitiveKind::Box: return MakeBox();
    case PrimitiveKind::Prism: return MakePrism();
    case PrimitiveKind::Cylinder: return MakeCylinder(cylinder_segments);
    case PrimitiveKind::Mesh: break;
  }
  // A mesh node's triangles come from its file (LoadGltfMesh); asking here is a bug.
  throw std::invalid_argument("MakePrimitive: PrimitiveKind::Mesh has no unit primitive");
}

}  // namespace vkr
