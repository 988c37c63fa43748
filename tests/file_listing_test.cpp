// Tests for app/workspace/file_listing.h on a temporary folder: order (folders first, natural order),
// extension filter, hidden files, sizes and times, navigation, typed paths and save names, and
// that every error names the folder or file.
#include "app/workspace/file_listing.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <filesystem>

#include "tests/document_fixtures.h"
#include "tests/expect_error.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;
using test::write_text;

std::vector<std::string> names(const std::vector<FileEntry>& entries) {
  std::vector<std::string> out;
  for (const auto& e : entries) out.push_back(e.name);
  return out;
}

const std::vector<std::string> kCharacters = {".cagewrap", ".glb", ".gltf"};

class FileListingTest : public test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    fs::create_directories(dir_ / "zeta");
    fs::create_directories(dir_ / "Alpha");
    fs::create_directories(dir_ / ".cache");
    write_text(path("take10.glb"), "0123456789");
    write_text(path("take2.glb"), "01");
    write_text(path("Hero.GLTF"), "{}");
    write_text(path("hero.cagewrap"), "{}");
    write_text(path("notes.txt"), "x");
    write_text(path(".hidden.glb"), "x");
    write_text(path("cage.obj"), "v 0 0 0\n");
  }
};

TEST(FileListing, ExtensionsMatchIgnoringCaseAndNeedAName) {
  EXPECT_TRUE(matches_extension("a.glb", {".glb"}));
  EXPECT_TRUE(matches_extension("A.GLB", {".glb"}));
  EXPECT_TRUE(matches_extension("x.tar.gltf", {".glb", ".gltf"}));
  EXPECT_FALSE(matches_extension("a.glb.bak", {".glb"}));
  EXPECT_FALSE(matches_extension(".glb", {".glb"}));  // a hidden file named ".glb", not a glTF
  EXPECT_FALSE(matches_extension("aglb", {".glb"}));
  EXPECT_TRUE(matches_extension("anything", {}));
}

TEST(FileListing, NaturalOrderComparesNumbersByValueAndIgnoresCase) {
  EXPECT_TRUE(natural_less("take2", "take10"));
  EXPECT_FALSE(natural_less("take10", "take2"));
  EXPECT_TRUE(natural_less("alpha", "Beta"));
  EXPECT_TRUE(natural_less("Beta", "gamma"));
  EXPECT_TRUE(natural_less("a", "ab"));
  EXPECT_TRUE(natural_less("file007", "file8"));
  // equal but for case: byte order, so the order stays strict and total
  EXPECT_TRUE(natural_less("Hero", "hero"));
  EXPECT_FALSE(natural_less("hero", "Hero"));
  EXPECT_FALSE(natural_less("same", "same"));
}

TEST_F(FileListingTest, FoldersFirstThenFilteredFilesInNaturalOrder) {
  auto l = list_directory(dir_.string(), FileFilter{kCharacters});
  ASSERT_TRUE(l.ok()) << l.error().message;
  EXPECT_EQ(names(l->entries), (std::vector<std::string>{"Alpha", "zeta", "hero.cagewrap", "Hero.GLTF",
                                                         "take2.glb", "take10.glb"}));
  EXPECT_TRUE(l->entries[0].is_directory);
  EXPECT_FALSE(l->entries[2].is_directory);
  EXPECT_EQ(l->hidden_count, 2u);    // .cache and .hidden.glb
  EXPECT_EQ(l->filtered_count, 2u);  // notes.txt and cage.obj
  EXPECT_EQ(l->directory, fs::absolute(dir_).lexically_normal().string());
}

TEST_F(FileListingTest, SizesAndTimesOfFiles) {
  auto l = list_directory(dir_.string(), FileFilter{{".glb"}});
  ASSERT_TRUE(l.ok());
  ASSERT_EQ(names(l->entries), (std::vector<std::string>{"Alpha", "zeta", "take2.glb", "take10.glb"}));
  EXPECT_FALSE(l->entries[0].size.has_value()) << "folders have no size";
  ASSERT_TRUE(l->entries[3].size.has_value());
  EXPECT_EQ(*l->entries[3].size, 10u);
  EXPECT_EQ(*l->entries[2].size, 2u);
  ASSERT_TRUE(l->entries[3].modified.has_value());
  EXPECT_LE(std::abs(*l->entries[3].modified - static_cast<int64_t>(std::time(nullptr))), 60);
}

TEST_F(FileListingTest, HiddenEntriesShownOnRequest) {
  FileFilter f{kCharacters};
  f.show_hidden = true;
  auto l = list_directory(dir_.string(), f);
  ASSERT_TRUE(l.ok());
  EXPECT_EQ(names(l->entries)[0], ".cache");
  EXPECT_TRUE(l->entries[0].is_hidden);
  const auto listed = names(l->entries);
  EXPECT_NE(std::find(listed.begin(), listed.end(), ".hidden.glb"), listed.end());
  EXPECT_EQ(l->hidden_count, 0u);
}

TEST_F(FileListingTest, NoFilterListsEveryFile) {
  auto l = list_directory(dir_.string(), FileFilter{});
  ASSERT_TRUE(l.ok());
  EXPECT_EQ(l->entries.size(), 2u + 6u);
  EXPECT_EQ(l->filtered_count, 0u);
}

TEST_F(FileListingTest, BrokenLinkIsListedWithoutDetails) {
  fs::create_symlink(dir_ / "gone.glb", dir_ / "link.glb");
  auto l = list_directory(dir_.string(), FileFilter{{".glb"}});
  ASSERT_TRUE(l.ok());
  auto it = std::find_if(l->entries.begin(), l->entries.end(),
                         [](const FileEntry& e) { return e.name == "link.glb"; });
  ASSERT_NE(it, l->entries.end());
  EXPECT_FALSE(it->is_directory);
  EXPECT_FALSE(it->size.has_value());
  EXPECT_FALSE(it->modified.has_value());
}

TEST_F(FileListingTest, LinkToFolderCountsAsFolder) {
  fs::create_directory_symlink(dir_ / "Alpha", dir_ / "beta_link");
  auto l = list_directory(dir_.string(), FileFilter{{".glb"}});
  ASSERT_TRUE(l.ok());
  EXPECT_EQ(names(l->entries)[1], "beta_link");
  EXPECT_TRUE(l->entries[1].is_directory);
}

TEST_F(FileListingTest, ErrorsNameTheFolder) {
  EXPECT_TRUE(Fails(list_directory(path("missing"), {}), ErrorCode::kFileNotFound,
                    {path("missing"), "does not exist"}));
  EXPECT_TRUE(Fails(list_directory(path("notes.txt"), {}), ErrorCode::kInvalidArgument,
                    {path("notes.txt"), "not a folder"}));
  if (::geteuid() != 0) {  // root reads any folder
    fs::create_directories(dir_ / "locked");
    ::chmod(path("locked").c_str(), 0);
    EXPECT_TRUE(Fails(list_directory(path("locked"), {}), ErrorCode::kFileUnreadable,
                      {path("locked"), "cannot read the folder"}));
    ::chmod(path("locked").c_str(), 0755);
  }
  // the message for an unreadable folder, whoever runs the test
  Error e = directory_error("/srv/x", std::make_error_code(std::errc::permission_denied));
  EXPECT_EQ(e.code, ErrorCode::kFileUnreadable);
  EXPECT_EQ(e.message, "cannot read the folder /srv/x (Permission denied)");
}

TEST(FileListing, AbsolutePathsAreNormalised) {
  EXPECT_EQ(absolute_path("/a/b/../c/./d/"), "/a/c/d");
  EXPECT_EQ(absolute_path("x/y", "/base"), "/base/x/y");
  EXPECT_EQ(absolute_path("../y", "/base/sub"), "/base/y");
  EXPECT_EQ(absolute_path("/"), "/");
  EXPECT_EQ(absolute_path("/.."), "/");
  EXPECT_EQ(absolute_path("x", ""), (fs::current_path() / "x").string());
  const char* home = std::getenv("HOME");
  if (home && *home) {
    EXPECT_EQ(absolute_path("~/models", "/elsewhere"), absolute_path(std::string(home) + "/models"));
    EXPECT_EQ(absolute_path("~", "/elsewhere"), absolute_path(home));
  }
  EXPECT_EQ(absolute_path("~user", "/b"), "/b/~user");  // only "~" and "~/" mean home
  EXPECT_EQ(parent_directory("/a/b"), "/a");
  EXPECT_EQ(parent_directory("/a"), "/");
  EXPECT_EQ(parent_directory("/"), "/");
}

TEST_F(FileListingTest, SaveNamesGetTheDefaultExtension) {
  const std::vector<std::string> ext = {".cagewrap"};
  auto t = resolve_save_name(dir_.string(), "new_hero", ext, ".cagewrap");
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_EQ(t->path, path("new_hero.cagewrap"));
  EXPECT_FALSE(t->exists);
  t = resolve_save_name(dir_.string(), "  hero.v2  ", ext, ".cagewrap");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->path, path("hero.v2.cagewrap"));
  t = resolve_save_name(dir_.string(), "HERO.CAGEWRAP", ext, ".cagewrap");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->path, path("HERO.CAGEWRAP"));
  t = resolve_save_name(dir_.string(), "Alpha/inner", ext, ".cagewrap");  // a relative sub-path
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->path, path("Alpha/inner.cagewrap"));
  t = resolve_save_name("/elsewhere", path("abs.cagewrap"), ext,
                        ".cagewrap");  // absolute: the folder is ignored
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->path, path("abs.cagewrap"));
}

TEST_F(FileListingTest, SaveOverAnExistingFileIsFlagged) {
  auto t = resolve_save_name(dir_.string(), "hero", {".cagewrap"}, ".cagewrap");
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->path, path("hero.cagewrap"));
  EXPECT_TRUE(t->exists);
}

TEST_F(FileListingTest, BadSaveNamesSayWhy) {
  const std::vector<std::string> ext = {".png"};
  EXPECT_TRUE(Fails(resolve_save_name(dir_.string(), "   ", ext, ".png"), ErrorCode::kInvalidArgument,
                    {"type a file name", dir_.string()}));
  EXPECT_TRUE(Fails(resolve_save_name(dir_.string(), "Alpha/", ext, ".png"), ErrorCode::kInvalidArgument,
                    {"Alpha/", "names a folder"}));
  for (const char* folder : {"..", ".", "Alpha/..", "~"})
    EXPECT_TRUE(Fails(resolve_save_name(dir_.string(), folder, ext, ".png"), ErrorCode::kInvalidArgument,
                      {"names a folder"}))
        << folder;
  EXPECT_TRUE(Fails(resolve_save_name(dir_.string(), "nowhere/shot", ext, ".png"), ErrorCode::kFileNotFound,
                    {path("nowhere/shot.png"), path("nowhere"), "does not exist"}));
  fs::create_directories(dir_ / "dir.png");
  EXPECT_TRUE(Fails(resolve_save_name(dir_.string(), "dir.png", ext, ".png"), ErrorCode::kInvalidArgument,
                    {path("dir.png"), "is a folder"}));
}

TEST(FileListing, SizesAndTimesReadWell) {
  EXPECT_EQ(format_size(0), "0 B");
  EXPECT_EQ(format_size(1023), "1023 B");
  EXPECT_EQ(format_size(1536), "1.5 KB");
  EXPECT_EQ(format_size(12u << 20), "12 MB");
  EXPECT_EQ(format_size(uint64_t(3) << 30), "3.0 GB");
  std::tm tm{};
  tm.tm_year = 2024 - 1900;
  tm.tm_mon = 2;
  tm.tm_mday = 5;
  tm.tm_hour = 14;
  tm.tm_min = 7;
  tm.tm_isdst = -1;
  EXPECT_EQ(format_time(static_cast<int64_t>(std::mktime(&tm))), "2024-03-05 14:07");
}

TEST_F(FileListingTest, BrowserNavigatesAndKeepsItsPlaceOnErrors) {
  FileBrowserModel m(FileFilter{kCharacters});
  m.open(dir_.string());
  EXPECT_TRUE(m.error().empty());
  EXPECT_EQ(m.directory(), dir_.string());
  ASSERT_TRUE(m.navigate("Alpha"));  // relative to the folder shown
  EXPECT_EQ(m.directory(), path("Alpha"));
  EXPECT_TRUE(m.entries().empty());
  EXPECT_TRUE(m.go_up());
  EXPECT_EQ(m.directory(), dir_.string());
  EXPECT_EQ(m.path_of(m.entries()[0]), path("Alpha"));
  // a failed move keeps the folder and its listing, and names what failed
  const size_t n = m.entries().size();
  EXPECT_FALSE(m.navigate("missing"));
  EXPECT_EQ(m.directory(), dir_.string());
  EXPECT_EQ(m.entries().size(), n);
  EXPECT_NE(m.error().find(path("missing")), std::string::npos) << m.error();
  ASSERT_TRUE(m.refresh());
  EXPECT_TRUE(m.error().empty()) << "a success clears the error";
  // the hidden toggle lists again
  m.set_show_hidden(true);
  EXPECT_EQ(m.entries()[0].name, ".cache");
  m.set_show_hidden(false);
  EXPECT_EQ(m.entries()[0].name, "Alpha");
}

TEST_F(FileListingTest, BrowserOpensTheNearestFolderThatExists) {
  FileBrowserModel m(FileFilter{kCharacters});
  m.open(path("Alpha/deleted/deeper"));
  EXPECT_EQ(m.directory(), path("Alpha"));
  EXPECT_NE(m.error().find(path("Alpha/deleted/deeper")), std::string::npos) << m.error();
  FileBrowserModel root;
  root.open("/");
  EXPECT_EQ(root.directory(), "/");
  EXPECT_TRUE(root.go_up());
  EXPECT_EQ(root.directory(), "/");
}

TEST_F(FileListingTest, TypedPathsEnterFoldersOrChooseFiles) {
  FileBrowserModel m(FileFilter{kCharacters});
  m.open(dir_.string());
  EXPECT_FALSE(m.enter_typed_path("zeta").has_value());
  EXPECT_EQ(m.directory(), path("zeta"));
  auto chosen = m.enter_typed_path(path("take2.glb"));
  ASSERT_TRUE(chosen.has_value()) << m.error();
  EXPECT_EQ(*chosen, path("take2.glb"));
  EXPECT_EQ(m.directory(), dir_.string()) << "choosing a file shows its folder";
  EXPECT_FALSE(m.enter_typed_path("notes.txt").has_value());
  EXPECT_NE(m.error().find("notes.txt is not a .cagewrap, .glb or .gltf file"), std::string::npos)
      << m.error();
  EXPECT_FALSE(m.enter_typed_path("ghost.glb").has_value());
  EXPECT_NE(m.error().find(path("ghost.glb") + " does not exist"), std::string::npos) << m.error();
  EXPECT_EQ(m.directory(), dir_.string());
}

}  // namespace
}  // namespace cagewrap
