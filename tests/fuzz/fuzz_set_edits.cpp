// libFuzzer harness for the set edits file (core/io/set_edits_io.h): load_set_edits, then, when it
// parses, resolve_set_edits against a small skin and a box cage (the range checks and mirroring).
#include <cstdlib>

#include "core/io/set_edits_io.h"
#include "tests/fixtures.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const cagewrap::Cage cage = cagewrap::fixtures::box_cage(1.0, 2);
  static const std::vector<glm::vec3> skin = {{0.1f, 0, 0}, {-0.1f, 0, 0}, {0, 0.2f, 0}, {0, 0, 0.3f}};
  const std::string path = cagewrap::fuzz::write_input("in.edits", data, size);
  auto f = cagewrap::load_set_edits(path);
  if (!f.ok()) {
    if (f.error().message.find(path) == std::string::npos) std::abort();  // errors name the file
    return 0;
  }
  auto r = cagewrap::resolve_set_edits(*f, path, skin, cage);
  if (!r.ok() && r.error().message.find(path) == std::string::npos) std::abort();
  return 0;
}
