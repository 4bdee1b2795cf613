#version 460
// View-specific texture pass (thesis §5.2–5.5), vertex stage. The camera projection is
// done here, per vertex: within a triangle the world position is affine in atlas space, so
// the homogeneous clip position interpolates exactly, and the fragment stage only divides
// (LAVAPIPE.md: a 4×4 per fragment halves the rate). Because nothing is clipped in atlas
// space, triangles crossing the camera's near plane keep every texel in front of it
// (§5.5.1): the fragment stage rejects exactly the texels behind the near plane.
#extension GL_GOOGLE_include_directive : require
#include "atlas_space.glsl"
#include "view_texture_push.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_atlas_uv;
layout(location = 3) in uint in_node;
layout(location = 5) in float in_texel_area;  // its chart's (Atlas.h: charts may differ in scale)

layout(std430, set = 0, binding = 0) readonly buffer NodeMatrices { mat4 world_from_node[]; };

layout(location = 0) out vec4 clip;
layout(location = 1) out vec3 world;
layout(location = 2) out vec3 normal;
layout(location = 3) flat out float texel_area;

void main() {
  const mat4 m = world_from_node[pc.node_offset + in_node];
  const vec4 w = m * vec4(in_position, 1.0);
  world = w.xyz;
  clip = pc.clip_from_world * w;
  normal = transpose(inverse(mat3(m))) * in_normal;
  texel_area = in_texel_area;
  gl_Position = AtlasPosition(in_atlas_uv);
}
