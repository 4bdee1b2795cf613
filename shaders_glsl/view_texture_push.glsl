// Push constants of the view-specific texture pass (pipelines/passes/ViewTexturePass.cpp mirrors it).
layout(push_constant) uniform Push {
  mat4 clip_from_world;   // camera i (full-resolution K: NDC does not depend on the level)
  vec4 centre;            // camera centre (xyz); w unused
  vec4 params;            // fx·fy at full resolution (x), relative depth tolerance (y), weights: 0 uniform 1 angle (z), near (w)
  uint node_offset;
  float level;            // pyramid level: the least LOD the reference is sampled at
} pc;
