#version 460
// Draws the scene from one camera (synth, render): node-frame vertices are placed by the
// hypothesis's node matrices and projected with the camera's clip_from_world, which
// carries K, [R|t] and a reversed, infinite-far depth (pipelines/passes/Projection.h).
#extension GL_GOOGLE_include_directive : require
#include "novel_view_push.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_atlas_uv;
layout(location = 3) in uint in_node;

layout(std430, set = 0, binding = 0) readonly buffer NodeMatrices { mat4 world_from_node[]; };

layout(location = 0) out vec2 atlas_uv;
layout(location = 1) out vec3 world_position;
layout(location = 2) out vec3 world_normal;

void main() {
  const mat4 m = world_from_node[pc.node_offset + in_node];
  const vec4 world = m * vec4(in_position, 1.0);
  world_position = world.xyz;
  world_normal = transpose(inverse(mat3(m))) * in_normal;
  atlas_uv = in_atlas_uv;
  gl_Position = pc.clip_from_world * world;
}
