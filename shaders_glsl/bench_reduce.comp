#version 460
// `vkrecon bench` probe: the composite pass's reduction alone (columns of kRows texels per
// invocation, then a subgroup sum: subgroup_reduction.glsl), on made-up per-texel scalars,
// with no image reads. Timed against the composite, it shows how much of that pass the
// reduction is.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "subgroup_reduction.glsl"

layout(local_size_x_id = 0, local_size_y = 1) in;  // as composite.comp

layout(std430, set = 0, binding = 0) writeonly buffer Partials { Scalars partials[]; };

const uint kRows = 16u;  // as composite.comp

void main() {
  Scalars mine = ZeroScalars();
  const uint x = gl_GlobalInvocationID.x;
  for (uint r = 0u; r < kRows; ++r) {
    const uint y = gl_WorkGroupID.y * kRows + r;
    mine = AddScalars(mine, Scalars(float(x & 7u), float(y & 3u), 0.0, 0.0, x & 1u, y & 1u, 0u, 0u, 0u, 0u, 0u, 0u));
  }
  const Scalars total = ReduceSubgroup(mine);
  if (subgroupElect()) partials[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = total;
}
