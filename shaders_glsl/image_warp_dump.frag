#version 460
// Image-space warp pass, fragment stage for `vkrecon likelihood --dump`: the pixel pair's χ²
// and the synthetic image s_{s,t} (image_warp.glsl).
#extension GL_GOOGLE_include_directive : require
#define WRITE_SYNTHETIC
#include "image_warp.glsl"
