// libFuzzer harness for the static mesh loaders (core/geometry/mesh_io.h, core/geometry/text_mesh_readers.h): the
// first byte picks the format (0 OBJ, 1 OFF, 2 PLY, 3 STL, modulo 4), the rest is the file.
// load_mesh runs the strict text readers and checks and OpenMesh behind them.
#include <cstdlib>

#include "core/geometry/mesh_io.h"
#include "core/geometry/text_mesh_readers.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* kNames[] = {"in.obj", "in.off", "in.ply", "in.stl"};
  const int format = data[0] % 4;
  const std::string path = cagewrap::fuzz::write_input(kNames[format], data + 1, size - 1);
  auto m = cagewrap::load_mesh(path);
  if (!m.ok() && m.error().message.find(path) == std::string::npos) std::abort();  // errors name the file
  return 0;
}
