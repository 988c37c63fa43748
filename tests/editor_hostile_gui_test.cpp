// Issue 19: every small hostile file (tests/tools/hostile_corpus.h: one count or size field of each
// format claiming billions) opened from the File menu through the file browser, one after another in
// one editor run: each is refused with a message naming the file, the editor keeps the document it had
// (the demo character, still drawn at the end) and exits normally. Under make test-sanitize-editor the
// same run is checked by AddressSanitizer and UBSan.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/gui_harness.h"
#include "tests/tools/hostile_corpus.h"

namespace {

namespace fs = std::filesystem;
using namespace cagewrap;

TEST(EditorHostileFilesGui, EachIsRefusedByNameAndTheDocumentStays) {
  std::string why;
  if (!test::gui_available(why)) GTEST_SKIP() << why;
  const fs::path dir = test::gui_test_dir() / "hostile";
  fs::remove_all(dir);
  fs::create_directories(dir / "files");
  fs::create_directories(dir / "scratch");
  const hostile::Corpus corpus = hostile::hostile_corpus((dir / "scratch").string());
  std::string script = "wait 2\n";
  std::vector<std::string> opened;
  for (const hostile::HostileFile& f : corpus.hostile) {
    const char* purpose = nullptr;
    if (f.loader == hostile::Loader::kCharacter || f.loader == hostile::Loader::kProject) purpose = "open";
    if (f.loader == hostile::Loader::kMesh) purpose = "import_cage";
    if (!purpose) continue;  // set edits, patch drivers and bindings are not opened from the File menu
    hostile::write_all((dir / "files" / f.name).string(), f.bytes);
    script += std::string("browse ") + purpose + " " + (dir / "files").string() + "\nwait 1\nbrowser_select " + f.name +
              "\nbrowser_confirm\nwait 2\nerror_ok\nwait 1\n";
    opened.push_back(f.name);
  }
  ASSERT_GE(opened.size(), 20u) << "the corpus holds characters, projects and meshes";
  script += "screenshot " + (dir / "after.png").string() + "\n";
  const auto run = test::run_editor_script(dir, "hostile", script, "--width 1280 --height 720", dir / "config");
  EXPECT_EQ(run.status, 0) << run.log;
  for (const std::string& name : opened)
    EXPECT_NE(run.log.find((dir / "files" / name).string()), std::string::npos) << name << " is not named in the log\n"
                                                                                   << run.log;
  // the demo character is still the document, and still drawn
  EXPECT_EQ(run.log.find("opened " + (dir / "files").string()), std::string::npos) << run.log;
  EXPECT_EQ(run.log.find("imported cage " + (dir / "files").string()), std::string::npos) << run.log;
  const test::Image after = test::load_png((dir / "after.png").string());
  ASSERT_EQ(after.w, 1280) << run.log;
  EXPECT_GT(test::skin_share(after), 0.02) << "the demo character should still be drawn";
}

}  // namespace
