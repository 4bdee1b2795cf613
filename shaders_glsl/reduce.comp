#version 460
// Second level of the reduction: one workgroup per hypothesis sums its partials in a fixed
// order and writes one Scalars into host-visible memory.
#extension GL_GOOGLE_include_directive : require
#include "reduction.glsl"

layout(local_size_x = 256) in;

layout(std430, set = 0, binding = 0) readonly buffer Partials { Scalars partials[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Results { Scalars results[]; };

layout(push_constant) uniform Push {
  uint partial_stride;  // partials reserved per hypothesis
  uint partial_count;   // partials used per hypothesis at this level
} pc;

void main() {
  const uint tid = gl_LocalInvocationIndex;
  const uint base = gl_WorkGroupID.x * pc.partial_stride;
  Scalars mine = ZeroScalars();
  for (uint i = tid; i < pc.partial_count; i += 256u) {
    mine = AddScalars(mine, partials[base + i]);
  }
  const Scalars total = ReduceWorkgroup(tid, mine);
  if (tid == 0u) results[gl_WorkGroupID.x] = total;
}
