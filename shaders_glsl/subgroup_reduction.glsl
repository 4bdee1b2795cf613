// The sum of every lane's Scalars within one subgroup, for passes whose workgroup is exactly
// one subgroup (PipelineBuilder.h CreateSubgroupComputePipeline). No shared memory and no
// barrier: on lavapipe a barrier turns every invocation into a coroutine, and the tree of
// reduction.glsl cost more than the composite it reduced. A subgroup of a fixed size sums in
// a fixed order, so results stay bit-identical on the same device.
// Needs GL_KHR_shader_subgroup_arithmetic, enabled by the including shader.
#include "scalars.glsl"

Scalars ReduceSubgroup(Scalars mine) {
  return Scalars(subgroupAdd(mine.sum_squares), subgroupAdd(mine.dof), subgroupAdd(mine.unverified), 0.0,
                 subgroupAdd(mine.seen_multi),
                 subgroupAdd(mine.seen_once), subgroupAdd(mine.seen_none), subgroupAdd(mine.interior), subgroupAdd(mine.views),
                 subgroupAdd(mine.outlier_views), subgroupAdd(mine.masked), 0u);
}
