// tinygltf's implementation, compiled here only for the fuzz build (PENUMBRA_FUZZ=ON) so that
// it carries the same sanitizer and coverage instrumentation as the loader around it; the
// normal build links Debian's libtinygltf.so instead. This is the route Debian's README for
// libtinygltf-dev describes (one translation unit defining TINYGLTF_IMPLEMENTATION); stb_image
// itself still comes from Debian's libstb.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
