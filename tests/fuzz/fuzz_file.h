// Shared by the libFuzzer harnesses (tests/fuzz/fuzz_*.cpp): the loaders read files, so each input
// is written to a file in a private folder (under /dev/shm when there is one: no disk traffic).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace cagewrap::fuzz {

// The harness's own folder, made once per process and removed at exit. The name is never
// destroyed: the exit handler that removes the folder runs after static destructors would have.
inline const std::string& work_dir() {
  static const std::string* dir = [] {
    std::filesystem::path base = std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    auto d = base / ("cagewrap-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    auto* name = new std::string(d.string());
    std::atexit([] { std::error_code ec; std::filesystem::remove_all(work_dir(), ec); });
    return name;
  }();
  return *dir;
}

// Writes `size` bytes to work_dir()/name and returns the path.
inline std::string write_input(const std::string& name, const uint8_t* data, size_t size) {
  std::string path = work_dir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

}  // namespace cagewrap::fuzz
