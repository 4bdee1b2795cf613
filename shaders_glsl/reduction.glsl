#include "scalars.glsl"

// A fixed-order tree reduction over a 256-thread workgroup, so that the same inputs give
// bit-identical sums on the same device (seeded chains must repeat exactly).
shared float s_sum[256];
shared float s_dof[256];
shared float s_unverified[256];
shared uvec4 s_counts[256];
shared uvec4 s_views[256];

Scalars ReduceWorkgroup(uint tid, Scalars mine) {
  s_sum[tid] = mine.sum_squares;
  s_dof[tid] = mine.dof;
  s_unverified[tid] = mine.unverified;
  s_counts[tid] = uvec4(mine.seen_multi, mine.seen_once, mine.seen_none, mine.interior);
  s_views[tid] = uvec4(mine.views, mine.outlier_views, mine.masked, 0u);
  barrier();
  for (uint stride = 128u; stride > 0u; stride >>= 1u) {
    if (tid < stride) {
      s_sum[tid] += s_sum[tid + stride];
      s_dof[tid] += s_dof[tid + stride];
      s_unverified[tid] += s_unverified[tid + stride];
      s_counts[tid] += s_counts[tid + stride];
      s_views[tid] += s_views[tid + stride];
    }
    barrier();
  }
  Scalars total = ZeroScalars();
  total.sum_squares = s_sum[0];
  total.dof = s_dof[0];
  total.unverified = s_unverified[0];
  total.seen_multi = s_counts[0].x;
  total.seen_once = s_counts[0].y;
  total.seen_none = s_counts[0].z;
  total.interior = s_counts[0].w;
  total.views = s_views[0].x;
  total.outlier_views = s_views[0].y;
  total.masked = s_views[0].z;
  return total;
}
