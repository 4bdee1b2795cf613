// tinygltf's implementation, compiled into fuzz_gltf with coverage and sanitizers (see
// CMakeLists.txt): the same source as Debian's libtinygltf, which the normal build links.
// GltfMesh.cpp never decodes or writes images, so stb is left out.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>
