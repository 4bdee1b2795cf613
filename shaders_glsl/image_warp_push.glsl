// Push constants and per-camera records of the image-space warp pass (thesis §4.2–4.3);
// pipelines/passes/TargetWarpPass.cpp mirrors both.

// One camera of one hypothesis (std430: 80 bytes).
struct WarpCamera {
  mat4 clip_from_world;  // full-resolution K: normalised image coordinates do not depend on the level
  vec4 centre_fx_fy;     // camera centre (xyz), fx·fy at full resolution (w)
};

layout(std430, set = 0, binding = 0) readonly buffer NodeMatrices { mat4 world_from_node[]; };
layout(std430, set = 0, binding = 1) readonly buffer Cameras { WarpCamera cameras[]; };

// The most sources one draw compares with its target (TargetWarpPass::kMaxSources): each
// carries a vec4 varying, and lavapipe interpolates 32 vec4s at most.
const uint kMaxSources = 8u;

layout(push_constant) uniform Push {
  uint node_offset;
  uint target;                   // cameras[] index of t (the hypothesis's slot included)
  uint source_count;             // sources of this draw, ≤ kMaxSources
  float level;                   // pyramid level
  float inv_sigma2;              // 1 / σ² on the [0,1] colour scale
  float cap;                     // per-dof cap of a pixel pair's χ² (3 dof per pair)
  float position_sd_over_sigma;  // δ/σ of the noise model (pipelines/model/Evaluation.h)
  float depth_tolerance;         // relative tolerance of the shadow-map test in s
  float near;                    // near plane (Projection.h)
  float depth_equal;             // relative slack of the depth-equal test against t's depth map
  uint sources[kMaxSources];     // cameras[] index of each source s
} pc;
