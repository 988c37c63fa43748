// libFuzzer harness for the binding file (core/io/binding_io.h): load_binding, and when a binding loads
// (validate_binding passed), a deformer made from it for a skin of its point count deforms its own
// rest cage, as `cagewrap deform` would with the cage it was bound to. Every error must name the file.
#include <cstdlib>
#include <vector>

#include "core/io/binding_io.h"
#include "core/deform/deformer.h"
#include "tests/fuzz/fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = cagewrap::fuzz::write_input("in.cwb", data, size);
  auto b = cagewrap::load_binding(path);
  if (!b.ok()) {
    if (b.error().message.find(path) == std::string::npos) std::abort();  // errors name the file
    return 0;
  }
  if (b->num_points > 4096 || b->rest_cage.size() > 4096) return 0;  // keep each input fast
  // the skin at rest: any finite points (the maps act on them; the file does not store them)
  std::vector<glm::vec3> skin(b->num_points);
  for (size_t p = 0; p < skin.size(); ++p) skin[p] = glm::vec3(0.01f * float(p), 0.5f, -0.25f);
  auto d = cagewrap::Deformer::create(*b, skin);
  if (!d.ok()) return 0;  // e.g. a degenerate rest cage: refused with a message
  std::vector<glm::vec3> out(skin.size());
  (void)d->deform(b->rest_cage, out);  // a non-finite rest cage is refused by check_cage
  return 0;
}
