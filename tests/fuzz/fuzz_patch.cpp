// libFuzzer harness for patch driver files (core/io/patch_io.h): the input read as a .cwpatch and as a
// .gltf (extras.cagewrap_patch); when a driver loads, a few skin points are bound to its samples
// and deformed by it at rest (sampling, frames, the sample binding and the kernel).
#include <cmath>
#include <cstdlib>

#include "core/deform/patch_binding.h"
#include "core/io/patch_io.h"
#include "tests/fuzz/fuzz_file.h"

namespace {

void exercise(const cagewrap::Result<cagewrap::PatchSurface>& p, const std::string& path) {
  if (!p.ok()) {
    if (p.error().message.find(path) == std::string::npos) std::abort();  // errors name the file
    return;
  }
  if (p->num_control_points() > 4096) return;      // keep each input fast
  for (const glm::dvec3& q : p->control_points())  // the maps are floats: scene-sized coordinates only
    if (std::abs(q.x) > 1e6 || std::abs(q.y) > 1e6 || std::abs(q.z) > 1e6) return;
  static const std::vector<glm::vec3> skin = {{0.1f, 0, 0}, {-0.1f, 0.5f, 0}, {0, 0.2f, 1}, {2, 0, 0.3f}};
  auto b = cagewrap::bind_skin_to_patches(skin, p.value(), 1, {});
  if (!b.ok()) return;  // a zero-size net, all samples degenerate: refused with a message
  auto d = cagewrap::PatchDeformer::create(*b, skin, p.value(), 1);
  if (!d.ok()) std::abort();  // a binding of this driver must make a deformer
  std::vector<glm::vec3> out(skin.size());
  if (!d->deform(p.value(), out).ok()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string cw = cagewrap::fuzz::write_input("in.cwpatch", data, size);
  exercise(cagewrap::load_patch(cw), cw);
  const std::string gl = cagewrap::fuzz::write_input("in.gltf", data, size);
  exercise(cagewrap::load_patch_gltf(gl), gl);
  return 0;
}
