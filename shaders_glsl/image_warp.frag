#version 460
// Image-space warp pass, fragment stage: the sums of the pixel pairs' χ² and counts (image_warp.glsl).
#extension GL_GOOGLE_include_directive : require
#include "image_warp.glsl"
