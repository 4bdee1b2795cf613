// Shared by the passes that rasterise faces in atlas space: a vertex lands at its atlas UV
// (the viewport picks the level's atlas size), whatever the camera. The interior pass and
// every view-texture pass must cover exactly the same texels (the composite reads a view
// only where the interior pass marked surface, and the view layers are not cleared:
// ViewTexturePass.cpp). They do without `invariant`: uv·2 is exact, so a fused and an
// unfused uv·2 − 1 round alike, and the rest is fixed-function.
vec4 AtlasPosition(vec2 atlas_uv) { return vec4(atlas_uv * 2.0 - 1.0, 0.0, 1.0); }
