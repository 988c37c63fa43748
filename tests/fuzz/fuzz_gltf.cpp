// libFuzzer harness for the glTF 2.0 loader (core/io/gltf_loader.h): input starting with "glTF" is
// read as .glb, anything else as .gltf JSON. Any outcome but a crash, a sanitizer report or a hang
// is fine: bad files must fail with a message naming the file.
#include <cstdlib>
#include <cstring>

#include "core/io/gltf_loader.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = cagewrap::fuzz::write_input(glb ? "in.glb" : "in.gltf", data, size);
  auto c = cagewrap::load_character(path);
  if (!c.ok() && c.error().message.find(path) == std::string::npos) std::abort();  // errors name the file
  return 0;
}
