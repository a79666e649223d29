// Fuzz builds only (see CMakeLists.txt): the implementations of tinygltf and stb_image,
// compiled with the sanitizers instead of taken from the system's prebuilt libraries.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
