// Test helper for the kill tests (tests/robustness_test.cpp): `cagewrap_save_loop DIR` loads
// DIR/hero.gltf with DIR/cage_a.obj and DIR/cage_b.obj and saves DIR/big.cagewrap over and over
// until it is killed, with the cage of the same vertex count each time (a and b differ in size).
// `cagewrap_save_loop DIR --recovery` does the same through the editor's autosave (app/workspace/autosave.h):
// the recovery file DIR/config/recovery/loop.cagewrap, the two documents edited in turn.
#include <cstdio>
#include <string>

#include "app/workspace/autosave.h"
#include "core/document/document.h"
#include "core/document/project_io.h"

int main(int argc, char** argv) {
  const bool recovery = argc == 3 && std::string(argv[2]) == "--recovery";
  if (argc != 2 && !recovery) {
    std::fprintf(stderr, "usage: cagewrap_save_loop DIR [--recovery]\n");
    return 2;
  }
  const std::string dir = argv[1];
  auto a = cagewrap::document_from_files(dir + "/hero.gltf", dir + "/cage_a.obj");
  auto b = cagewrap::document_from_files(dir + "/hero.gltf", dir + "/cage_b.obj");
  if (!a.ok() || !b.ok()) {
    std::fprintf(stderr, "error: %s\n", (!a.ok() ? a.error() : b.error()).message.c_str());
    return 1;
  }
  // the autosave writes whenever it is asked (an interval of a nanosecond), as the editor would
  cagewrap::Autosave autosave(cagewrap::recovery_directory(dir + "/config"), 1e-9,
                              cagewrap::Autosave::Clock::now(), "loop.cagewrap");
  for (unsigned i = 0;; ++i) {
    // DIR/loop.ready once the first write is done: the test's random delay starts there, so a slow
    // start (a sanitizer build, a loaded machine) does not eat it
    if (i == 1) {
      if (std::FILE* f = std::fopen((dir + "/loop.ready").c_str(), "w")) std::fclose(f);
    }
    const cagewrap::Document& doc = i % 2 ? *b : *a;
    if (recovery) {
      cagewrap::Document edited = doc;
      edited.revision = cagewrap::next_revision();  // a new unsaved change each time
      if (auto m = autosave.tick(edited, /*dirty=*/true); m && m->rfind("error", 0) == 0) {
        std::fprintf(stderr, "%s\n", m->c_str());
        return 1;
      }
      continue;
    }
    auto s = cagewrap::save_project(dir + "/big.cagewrap", doc);
    if (!s.ok()) {
      std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
      return 1;
    }
  }
}
