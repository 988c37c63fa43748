// Tests for app/workspace/autosave.h: the recovery file is written only while there are unsaved changes, at
// most once per interval (a fake clock), atomically, into its own folder and never over the
// project or the character; it loads as the document with a record of its project; it is removed
// when the work is clean again; and the start-up scan offers what editors that no longer run left
// behind, newest first, removing recovery files older than their (since saved) project. The
// autosave interval in the preferences is read, written and checked.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "app/workspace/autosave.h"
#include "app/workspace/preferences.h"
#include "core/document/project_io.h"
#include "tests/document_fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using test::read_text;
using test::write_text;

class AutosaveTest : public test::TempDirTest {
 protected:
  Document doc() {
    test::write_tiny_character(path("hero.gltf"));
    test::write_box_cage(path("cage.obj"));
    auto d = document_from_files(path("hero.gltf"), path("cage.obj"));
    EXPECT_TRUE(d.ok());
    return *d;
  }
  std::string recovery_dir() const { return recovery_directory(path("config")); }
};

TEST_F(AutosaveTest, WritesOnlyUnsavedChangesAtMostOncePerInterval) {
  const auto t0 = Autosave::Clock::time_point{} + 1000s;
  Autosave a(recovery_dir(), 60.0, t0, "r.cagewrap");
  ASSERT_TRUE(a.enabled());
  EXPECT_EQ(a.path(), path("config/recovery/r.cagewrap"));
  Document d = doc();
  EXPECT_FALSE(a.tick(d, /*dirty=*/false, t0 + 120s)) << "nothing unsaved: nothing written";
  EXPECT_FALSE(fs::exists(a.path()));
  Document edited = with_cage_offsets(d, std::vector<glm::vec3>(d.cage->num_vertices(), glm::vec3(0, 0.1f, 0)));
  auto m = a.tick(edited, true, t0 + 120s);
  ASSERT_TRUE(m);
  EXPECT_NE(m->find("autosaved the unsaved work to " + a.path()), std::string::npos) << *m;
  auto back = load_project(a.path());
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(same_content(back->document, edited));
  EXPECT_FALSE(a.tick(edited, true, t0 + 500s)) << "the same revision is not written again";
  Document more = with_cage_offsets(edited, std::vector<glm::vec3>(d.cage->num_vertices(), glm::vec3(0, 0.2f, 0)));
  EXPECT_FALSE(a.tick(more, true, t0 + 150s)) << "within the interval of the last write";
  EXPECT_TRUE(same_content(load_project(a.path())->document, edited));
  EXPECT_TRUE(a.tick(more, true, t0 + 180s));
  EXPECT_TRUE(same_content(load_project(a.path())->document, more));
  EXPECT_FALSE(fs::exists(a.path() + ".tmp"));
  // the work is saved (or undone back to the saved state): the file goes
  auto gone = a.tick(more, false, t0 + 181s);
  ASSERT_TRUE(gone);
  EXPECT_NE(gone->find("removed the recovery file"), std::string::npos);
  EXPECT_FALSE(fs::exists(a.path()));
  // off: never writes
  Autosave off(recovery_dir(), 0.0, t0, "off.cagewrap");
  EXPECT_FALSE(off.enabled());
  EXPECT_FALSE(off.tick(more, true, t0 + 10000s));
  EXPECT_FALSE(fs::exists(off.path()));
}

TEST_F(AutosaveTest, RecoveryFileNamesItsProjectAndLeavesTheProjectAlone) {
  Document d = doc();
  ASSERT_TRUE(save_project(path("p.cagewrap"), d).ok());
  d.project_path = path("p.cagewrap");
  const std::string saved = read_text(path("p.cagewrap"));
  Document edited = with_set_edits(d, {SetEdit{1, {3}, {}}});
  Autosave a(recovery_dir(), 1.0);
  ASSERT_TRUE(a.write(edited).ok());
  EXPECT_EQ(read_text(path("p.cagewrap")), saved) << "the project is the artist's: never written by autosave";
  EXPECT_EQ(fs::path(a.path()).parent_path(), fs::path(recovery_dir()));
  EXPECT_EQ(fs::path(a.path()).filename().string().rfind("recovery-", 0), 0u);
  auto back = load_project(a.path());
  ASSERT_TRUE(back.ok()) << back.error().message;
  ASSERT_TRUE(back->recovery);
  EXPECT_EQ(back->recovery->project, path("p.cagewrap"));
  EXPECT_EQ(back->recovery->pid, ::getpid());
  EXPECT_TRUE(same_content(back->document, edited));
  // a normal project has no recovery record, and saving a recovered document writes none
  EXPECT_FALSE(load_project(path("p.cagewrap"))->recovery);
  ASSERT_TRUE(save_project(path("q.cagewrap"), back->document).ok());
  EXPECT_EQ(read_text(path("q.cagewrap")).find("\"recovery\""), std::string::npos);
  // a recovery path that is the project or the character is refused, leaving them as they were
  Autosave over_project(dir_.string(), 1.0, Autosave::Clock::now(), "p.cagewrap");
  EXPECT_FALSE(over_project.write(edited).ok());
  EXPECT_EQ(read_text(path("p.cagewrap")), saved);
  Autosave over_character(dir_.string(), 1.0, Autosave::Clock::now(), "hero.gltf");
  EXPECT_FALSE(over_character.write(edited).ok());
  EXPECT_TRUE(load_project(path("p.cagewrap")).ok());
}

TEST_F(AutosaveTest, StartupScanOffersOnlyWorkNotSavedSince) {
  Document d = doc();
  ASSERT_TRUE(save_project(path("old.cagewrap"), d).ok());
  ASSERT_TRUE(save_project(path("new.cagewrap"), d).ok());
  // recovery of "old": written after its project; of "new": before it (saved since); untitled
  Document old_work = d, new_work = d, untitled = d;
  old_work.project_path = path("old.cagewrap");
  new_work.project_path = path("new.cagewrap");
  Autosave a(recovery_dir(), 1.0, Autosave::Clock::now(), "a.cagewrap");
  Autosave b(recovery_dir(), 1.0, Autosave::Clock::now(), "b.cagewrap");
  Autosave c(recovery_dir(), 1.0, Autosave::Clock::now(), "c.cagewrap");
  ASSERT_TRUE(b.write(new_work).ok());
  std::this_thread::sleep_for(20ms);
  ASSERT_TRUE(save_project(path("new.cagewrap"), d).ok());  // saved after its autosave
  ASSERT_TRUE(a.write(old_work).ok());
  ASSERT_TRUE(c.write(untitled).ok());
  // a: older than c, newer than its project
  fs::last_write_time(path("old.cagewrap"), fs::last_write_time(a.path()) - 20s);
  fs::last_write_time(a.path(), fs::last_write_time(a.path()) - 10s);
  write_text(path("config/recovery/junk.cagewrap"), "{ not json");
  write_text(path("config/recovery/x.cagewrap.tmp"), "half a file");  // a killed write: ignored
  RecoveryScan scan = list_recovery_files(recovery_dir());
  ASSERT_EQ(scan.offer.size(), 2u);
  EXPECT_EQ(scan.offer[0].path, c.path()) << "newest first";
  EXPECT_EQ(scan.offer[0].info.project, "");
  EXPECT_EQ(scan.offer[1].path, a.path());
  EXPECT_EQ(scan.offer[1].info.project, path("old.cagewrap"));
  EXPECT_GT(scan.offer[0].modified, scan.offer[1].modified);
  EXPECT_FALSE(fs::exists(b.path())) << "older than its project: removed";
  ASSERT_EQ(scan.notes.size(), 2u);
  bool named_stale = false, named_junk = false;
  for (const auto& n : scan.notes) {
    named_stale = named_stale || (n.find(b.path()) != std::string::npos && n.find("older than its project") != std::string::npos);
    named_junk = named_junk || n.find("junk.cagewrap") != std::string::npos;
  }
  EXPECT_TRUE(named_stale && named_junk);
  EXPECT_TRUE(fs::exists(path("config/recovery/junk.cagewrap"))) << "left alone";
  EXPECT_TRUE(list_recovery_files(path("nowhere")).offer.empty());
}

TEST_F(AutosaveTest, WorkOfARunningEditorIsNotOffered) {
  // a child process named like the editor, still running, wrote a recovery file
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::prctl(PR_SET_NAME, "cagewrap");
    char c = 1;
    (void)!::write(ready[1], &c, 1);
    ::pause();
    ::_exit(0);
  }
  char c;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  Document d = doc();
  Autosave mine(recovery_dir(), 1.0, Autosave::Clock::now(), "running.cagewrap");
  ASSERT_TRUE(mine.write(d).ok());
  std::string text = read_text(mine.path());
  const std::string own = "\"pid\": " + std::to_string(::getpid());
  ASSERT_NE(text.find(own), std::string::npos);
  text.replace(text.find(own), own.size(), "\"pid\": " + std::to_string(child));
  write_text(mine.path(), text);
  EXPECT_TRUE(list_recovery_files(recovery_dir()).offer.empty()) << "its editor still runs";
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  ASSERT_EQ(list_recovery_files(recovery_dir()).offer.size(), 1u) << "its editor is gone";
  ::close(ready[0]);
  ::close(ready[1]);
}

TEST_F(AutosaveTest, IntervalIsAPreference) {
  EXPECT_EQ(Preferences{}.autosave_seconds, kDefaultAutosaveSeconds);
  Preferences p;
  p.autosave_seconds = 45;
  ASSERT_TRUE(save_preferences(path("prefs.json"), p).ok());
  auto back = load_preferences(path("prefs.json"));
  EXPECT_TRUE(back.warnings.empty());
  EXPECT_EQ(back.prefs.autosave_seconds, 45);
  EXPECT_TRUE(back.prefs == p);
  write_text(path("bad.json"), R"({"format": "cagewrap-preferences", "autosave": {"interval_seconds": -5}})");
  auto bad = load_preferences(path("bad.json"));
  ASSERT_EQ(bad.warnings.size(), 1u);
  EXPECT_NE(bad.warnings[0].find("autosave.interval_seconds"), std::string::npos) << bad.warnings[0];
  EXPECT_EQ(bad.prefs.autosave_seconds, kDefaultAutosaveSeconds);
  write_text(path("off.json"), R"({"format": "cagewrap-preferences", "autosave": {"interval_seconds": 0}})");
  EXPECT_EQ(load_preferences(path("off.json")).prefs.autosave_seconds, 0);
}

}  // namespace
}  // namespace cagewrap
