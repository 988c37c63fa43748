// Test helper for the kill test (tests/robustness_test.cpp): `cagewrap_save_loop DIR` loads
// DIR/hero.gltf with DIR/cage_a.obj and DIR/cage_b.obj and saves DIR/big.cagewrap over and over
// until it is killed, with the cage of the same vertex count each time (a and b differ in size).
#include <cstdio>
#include <string>

#include "core/document.h"
#include "core/project_io.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: cagewrap_save_loop DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  auto a = cagewrap::document_from_files(dir + "/hero.gltf", dir + "/cage_a.obj");
  auto b = cagewrap::document_from_files(dir + "/hero.gltf", dir + "/cage_b.obj");
  if (!a.ok() || !b.ok()) {
    std::fprintf(stderr, "error: %s\n", (!a.ok() ? a.error() : b.error()).message.c_str());
    return 1;
  }
  for (unsigned i = 0;; ++i) {
    auto s = cagewrap::save_project(dir + "/big.cagewrap", i % 2 ? *b : *a);
    if (!s.ok()) {
      std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
      return 1;
    }
  }
}
