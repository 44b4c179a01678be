// tinyobjloader's parser compiled with the fuzzing flags, so that libFuzzer follows its branches and
// the sanitizers check its memory accesses. Its definitions in the fuzzer take precedence over the
// shared library's, which drape::mesh_io links.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
