// Push constants of the novel-view pass (pipelines/passes/NovelViewPass.cpp mirrors them).
layout(push_constant) uniform Push {
  mat4 clip_from_world;
  uint node_offset;  // first matrix of this hypothesis in world_from_node
  uint mode;         // 0: atlas colour, 1: world position, 2: atlas colour lit by the sun
} pc;
