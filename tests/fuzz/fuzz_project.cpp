// libFuzzer harness for the project file loader (core/document/project_io.h). The input is the .cagewrap
// file; its folder holds hero.gltf, a tiny character the seeds name, so that mutations reach the
// cage, binding, edits, attachment and keypose sections behind the character.
#include <cstdlib>

#include "core/document/project_io.h"
#include "tests/fuzz/fuzz_file.h"
#include "tests/fuzz/seed_fixtures.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  cagewrap::fuzz::write_tet_gltf(cagewrap::fuzz::work_dir() + "/hero.gltf");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cagewrap::fuzz::write_input("in.cagewrap", data, size);
  auto p = cagewrap::load_project(path);
  if (!p.ok() && p.error().message.find("in.cagewrap") == std::string::npos &&
      p.error().message.find("hero.gltf") == std::string::npos)
    std::abort();  // errors name the project (or the character it names)
  return 0;
}
