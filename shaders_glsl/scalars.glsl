#ifndef SCALARS_GLSL
#define SCALARS_GLSL
// The per-hypothesis scalars (pipelines/model/Evaluation.h ReducedScalars), as partial sums per
// workgroup and as final results; mirrored by struct GpuScalars in pipelines/passes/ReducePass.cpp.
struct Scalars {
  float sum_squares;
  float dof;
  float unverified;    // Σ over texels one view sees of that view's saturated loss (Evaluation.h)
  float pad_float;
  uint seen_multi;
  uint seen_once;
  uint seen_none;
  uint interior;
  uint views;          // view samples of the texels seen by ≥ 2 views
  uint outlier_views;  // of those, the ones the robust composite treated as outliers
  uint masked;         // exterior texels fewer than two views compare only because of masks
  uint pad1;
};

Scalars ZeroScalars() { return Scalars(0.0, 0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u); }

Scalars AddScalars(Scalars a, Scalars b) {
  a.sum_squares += b.sum_squares;
  a.dof += b.dof;
  a.unverified += b.unverified;
  a.seen_multi += b.seen_multi;
  a.seen_once += b.seen_once;
  a.seen_none += b.seen_none;
  a.interior += b.interior;
  a.views += b.views;
  a.outlier_views += b.outlier_views;
  a.masked += b.masked;
  return a;
}
#endif
