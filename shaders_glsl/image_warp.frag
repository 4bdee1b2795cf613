#version 460
// Image-space warp pass, fragment stage: the pixel pair's χ² only (image_warp.glsl).
#extension GL_GOOGLE_include_directive : require
#include "image_warp.glsl"
