// Shared by the passes that rasterise faces in atlas space: a vertex lands at its atlas UV
// (the viewport picks the level's atlas size), whatever the camera.
vec4 AtlasPosition(vec2 atlas_uv) { return vec4(atlas_uv * 2.0 - 1.0, 0.0, 1.0); }
