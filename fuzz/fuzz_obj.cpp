// libFuzzer target: drape::mesh_io's OBJ reader (tinyobjloader and the checks around it) on
// arbitrary bytes, read from a file in double and from memory in float with the rest shape taken
// from the uv. It must either return a mesh that passes ClothMesh::validate() or throw
// InvalidParameter; any other exception escapes and is reported as a crash, as are crashes, leaks
// and undefined behaviour.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "drape/mesh_io/read_obj.hpp"

namespace {

template <class Scalar>
void check(const drape::mesh_io::MeshRead<Scalar>& read) {
  const drape::ClothMesh<Scalar>& mesh = read.mesh;
  (void)mesh.validate();  // throws on a mesh the reader should have rejected: reported as a crash
  for (const auto& [name, vertices] : mesh.groups)
    for (int v : vertices)
      if (v < 0 || v >= mesh.vertex_count()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string path = "/tmp/drape_fuzz_obj_" + std::to_string(::getpid()) + ".obj";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    check(drape::mesh_io::read_obj<double>(path));
  } catch (const drape::InvalidParameter&) {
  }
  std::remove(path.c_str());
  drape::mesh_io::ObjOptions options;
  options.rest_from_uv = true;
  options.uv_scale = 0.5;
  try {
    check(drape::mesh_io::parse_obj<float>(text, "fuzz.obj", options));
  } catch (const drape::InvalidParameter&) {
  }
  return 0;
}
