// stb_image's implementation, compiled into fuzz_image with coverage and sanitizers (see
// CMakeLists.txt): the same source as Debian's libstb, which the normal build links.
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
