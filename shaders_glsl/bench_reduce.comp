#version 460
// `vkrecon bench` probe: the composite pass's workgroup reduction (reduction.glsl) alone, on
// made-up per-texel scalars, with no image reads. Timed against the composite, it shows
// how much of that pass the reduction is.
#extension GL_GOOGLE_include_directive : require
#include "reduction.glsl"

layout(local_size_x = 16, local_size_y = 16) in;  // as composite.comp

layout(std430, set = 0, binding = 0) writeonly buffer Partials { Scalars partials[]; };

void main() {
  const uvec2 texel = gl_GlobalInvocationID.xy;
  const Scalars mine = Scalars(float(texel.x & 7u), float(texel.y & 3u), texel.x & 1u, texel.y & 1u, 0u, 0u, 0u, 0u);
  const Scalars total = ReduceWorkgroup(gl_LocalInvocationIndex, mine);
  if (gl_LocalInvocationIndex == 0u) partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = total;
}
