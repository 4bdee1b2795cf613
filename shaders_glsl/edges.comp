#version 460
// Edge term (pipelines/model/EdgeEvidence.h; docs/internals/LIKELIHOOD.md, "Edges"), one camera
// of one hypothesis. One invocation per model edge: an edge between a face the camera sees and
// one it does not (an occluding contour), a sharp edge between two faces it sees (a crease),
// or the border of an open mesh, is sampled at kSamples points; each point the depth pass
// shows unoccluded is scored by the colour difference across the projected edge, half a pixel
// of the level to either side. A workgroup (one subgroup) writes Σ w·log-ratio and Σ w, with w
// the sample's share of the edge's projected length in level pixels. A dump also keeps each
// edge's sums (the sandwich's blocks of the edge term, NoiseCalibration.cpp).
#extension GL_KHR_shader_subgroup_arithmetic : require

layout(local_size_x_id = 0, local_size_y = 1) in;
layout(constant_id = 1) const uint kCheckValidity = 0u;   // 0: every pixel counts, binding 5 unread
layout(constant_id = 2) const uint kSamples = 64u;        // points per edge
layout(constant_id = 3) const uint kToleranceBits = 0u;   // relative depth tolerance, a float's bits

// Node frame. a.w: the node; c0.w, c1.w: ±1 so that ±cross(b − a, c − a) points out of the
// triangle (a, b, c); c1.w = 0: a border (one triangle).
struct Edge { vec4 a, b, c0, c1; };

layout(std430, set = 0, binding = 0) readonly buffer NodeMatrices { mat4 world_from_node[]; };
layout(std430, set = 0, binding = 1) readonly buffer Edges { Edge edges[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Partials { vec2 partials[]; };
layout(set = 0, binding = 3) uniform sampler2D reference;  // mip chain = image pyramid
layout(set = 0, binding = 4) uniform sampler2D depth_map;  // nearest, reversed depth
layout(set = 0, binding = 5) uniform sampler2D validity;   // the reference's mips: 1 = comparable
layout(std430, set = 0, binding = 6) writeonly buffer PerEdge { vec2 per_edge[]; };  // [camera][edge], dumps only

layout(push_constant) uniform Push {
  mat4 clip_from_world;  // full-resolution K: NDC does not depend on the level
  vec4 centre;           // camera centre (xyz), near plane (w)
  vec4 image;            // the level's size in pixels (xy), level (z), one level pixel in units of depth (w)
  vec4 statistic;        // 1/(2v) (x), log(1 − ε) − 1.5 log(2πv) (y), ε (z), η (w); EdgeEvidence.h
  uint node_offset, edge_count;
  uint dump_camera;  // 1 + the camera whose per-edge sums a dump keeps; 0: none
  uint partial_offset;
} pc;

// A crease is an edge whose faces' normals differ by more than 30°.
const float kCreaseCos = 0.8660254;

// log p₁(Δ)/p₀(Δ), EdgeEvidence.cpp's EdgeLogRatio.
float EdgeLogRatio(vec3 delta) {
  const float log_r = pc.statistic.y - dot(delta, delta) * pc.statistic.x;
  if (log_r > 50.0) return log(pc.statistic.w);
  const float p0 = exp(log_r) + pc.statistic.z;
  return log((1.0 - pc.statistic.w) + pc.statistic.w * p0) - log(p0);
}

vec3 World(mat4 m, vec4 p) { return (m * vec4(p.xyz, 1.0)).xyz; }

// Level pixels of a world point in front of the near plane.
vec2 Pixel(vec4 clip) { return (clip.xy / clip.w * 0.5 + 0.5) * pc.image.xy; }

vec2 ScoreEdge(uint index) {
  const Edge e = edges[index];
  const mat4 m = world_from_node[pc.node_offset + uint(e.a.w)];
  const vec3 a = World(m, e.a), b = World(m, e.b), c0 = World(m, e.c0);
  const bool border = e.c1.w == 0.0;
  const float handed = determinant(mat3(m)) < 0.0 ? -1.0 : 1.0;  // a mirror turns faces inside out
  const vec3 n0 = handed * e.c0.w * cross(b - a, c0 - a);
  const vec3 to_camera = pc.centre.xyz - a;
  const bool front0 = dot(n0, to_camera) > 0.0;
  vec3 front = n0, inside = c0;
  float cos_front = dot(normalize(n0), normalize(to_camera));
  if (border) {
    if (!front0) return vec2(0.0);
  } else {
    const vec3 c1 = World(m, e.c1);
    const vec3 n1 = handed * e.c1.w * cross(b - a, c1 - a);
    const bool front1 = dot(n1, to_camera) > 0.0;
    if (!front0 && !front1) return vec2(0.0);
    if (front0 && front1) {
      if (dot(normalize(n0), normalize(n1)) > kCreaseCos) return vec2(0.0);  // not sharp
      cos_front = max(cos_front, dot(normalize(n1), normalize(to_camera)));
    } else if (front1) {
      front = n1, inside = c1;
      cos_front = dot(normalize(n1), normalize(to_camera));
    }
  }
  const float near = pc.centre.w;
  const vec4 clip_a = pc.clip_from_world * vec4(a, 1.0), clip_b = pc.clip_from_world * vec4(b, 1.0);
  const vec4 clip_in = pc.clip_from_world * vec4(inside, 1.0);
  if (clip_a.w <= near || clip_b.w <= near || clip_in.w <= near) return vec2(0.0);
  const vec2 pa = Pixel(clip_a), pb = Pixel(clip_b);
  const float len = length(pb - pa);
  if (len < 1e-3) return vec2(0.0);
  vec2 normal = vec2(pa.y - pb.y, pb.x - pa.x) / len;
  if (dot(Pixel(clip_in) - pa, normal) < 0.0) normal = -normal;  // towards the front face
  // Depth changes across a pixel by about z·tanθ/f on a face tilted by θ (view_texture.frag).
  const float c = clamp(cos_front, 1e-3, 1.0);
  const float tan_theta = min(sqrt(max(1.0 - c * c, 0.0)) / c, 10.0);
  const float tolerance = uintBitsToFloat(kToleranceBits) + 1.5 * tan_theta * pc.image.w;
  const float weight = len / float(kSamples);
  vec2 sum = vec2(0.0);
  for (uint j = 0u; j < kSamples; ++j) {
    const float t = (float(j) + 0.5) / float(kSamples);
    const vec4 clip = mix(clip_a, clip_b, t);  // clip space is linear in world space
    const vec2 p = Pixel(clip);
    const vec2 p_in = p + 0.5 * normal, p_out = p - 0.5 * normal;
    if (any(lessThan(min(p_in, p_out), vec2(1.0))) || any(greaterThan(max(p_in, p_out), pc.image.xy - 1.0)))
      continue;  // the frame cuts the model there, no edge does
    if (near / clip.w < texture(depth_map, p / pc.image.xy).r * (1.0 - tolerance)) continue;  // occluded
    const vec2 uv_in = p_in / pc.image.xy, uv_out = p_out / pc.image.xy;
    if (kCheckValidity != 0u &&
        min(textureLod(validity, uv_in, pc.image.z).r, textureLod(validity, uv_out, pc.image.z).r) < 0.999)
      continue;
    const vec3 delta = textureLod(reference, uv_in, pc.image.z).rgb - textureLod(reference, uv_out, pc.image.z).rgb;
    sum += vec2(weight * EdgeLogRatio(delta), weight);
  }
  return sum;
}

void main() {
  const uint index = gl_GlobalInvocationID.x;
  const vec2 mine = index < pc.edge_count ? ScoreEdge(index) : vec2(0.0);
  if (pc.dump_camera != 0u && index < pc.edge_count) per_edge[(pc.dump_camera - 1u) * pc.edge_count + index] = mine;
  const vec2 total = subgroupAdd(mine);
  if (subgroupElect()) partials[pc.partial_offset + gl_WorkGroupID.x] = total;
}
