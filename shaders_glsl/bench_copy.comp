#version 460
// `vkrecon bench` ceiling: the device's own rate for a compute shader that only moves
// memory (one 16-byte load and one 16-byte store per invocation). The composite pass is
// compared with it (LAVAPIPE.md: compute is lavapipe's weak spot).

layout(local_size_x = 256) in;

layout(std430, set = 0, binding = 0) readonly buffer Source { uvec4 source[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Destination { uvec4 destination[]; };

layout(push_constant) uniform Push {
  uint count;  // uvec4 elements to copy
} pc;

void main() {
  // Grid-stride, so a buffer larger than one dispatch's invocations is still copied whole.
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) destination[i] = source[i];
}
