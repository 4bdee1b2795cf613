#version 460
// View-specific texture pass for texels the host knows camera i cannot see
// (pipelines/passes/ViewCulling.h): weight 0, exactly what view_texture.frag writes there,
// at the cost of a fill rather than of its samples.
layout(location = 0) in vec4 clip;  // view_texture.vert's outputs, unused: declared so the
layout(location = 1) in vec3 world; // interface between the stages matches
layout(location = 2) in vec3 normal;
layout(location = 3) flat in float texel_area;
layout(location = 0) out uvec2 view;

void main() { view = uvec2(0u); }
