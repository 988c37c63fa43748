// cagewrap_alloc_cap: no small input may make a loader ask for a huge block of memory (issue 19).
//
// This program replaces the global allocation functions (malloc, calloc, realloc, memalign,
// posix_memalign, aligned_alloc, valloc, pvalloc, forwarding to glibc's own __libc_* functions, and
// every form of operator new and delete on top of them): each records the largest single request and
// refuses one above 64 MB (malloc returns null, operator new throws std::bad_alloc), counting it. Then
// it writes every file of the hostile corpus (tests/tools/hostile_corpus.h) to a temporary folder,
// loads it with its loader and checks that the load fails, that the message names the file, that no
// request above the cap was made (a refused one counts even when the loader recovered from it: without
// the cap it would have been granted, or the machine lost to swapping) and that it took under a second.
// One line per file; exit status 1 when any check fails.
//
// Not built with the sanitizers (CAGEWRAP_SANITIZE, CAGEWRAP_FUZZ): they replace malloc themselves.
#include <errno.h>
#include <malloc.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include "core/io/binding_io.h"
#include "core/base/digits.h"
#include "core/io/gltf_loader.h"
#include "core/geometry/mesh_io.h"
#include "core/io/patch_io.h"
#include "core/document/project_io.h"
#include "core/io/set_edits_io.h"
#include "tests/tools/hostile_corpus.h"

extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* p, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void* __libc_valloc(size_t size);
void* __libc_pvalloc(size_t size);
void __libc_free(void* p);
}

namespace {

constexpr size_t kCap = size_t(64) << 20;  // the most one request may ask for
constexpr double kSecondsPerFile = 1.0;     // a refusal is quick: it reads a few kilobytes
constexpr unsigned kWatchdogSeconds = 20;   // a load still running then has hung: the run stops

std::atomic<size_t> g_largest{0};  // the largest request since the last reset
std::atomic<size_t> g_refused{0};  // requests above kCap since the last reset

// Records a request of `size` bytes; false when it is above the cap.
bool admit(size_t size) {
  size_t seen = g_largest.load(std::memory_order_relaxed);
  while (size > seen && !g_largest.compare_exchange_weak(seen, size, std::memory_order_relaxed)) {
  }
  if (size <= kCap) return true;
  g_refused.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool valid_alignment(size_t alignment) {
  return alignment >= sizeof(void*) && (alignment & (alignment - 1)) == 0;
}

void* aligned(size_t alignment, size_t size) {
  if (!admit(size)) {
    errno = ENOMEM;
    return nullptr;
  }
  return __libc_memalign(alignment, size);
}

}  // namespace

// ------------------------------------------------------------------ the C allocation functions

extern "C" {

void* malloc(size_t size) {
  if (!admit(size)) {
    errno = ENOMEM;
    return nullptr;
  }
  return __libc_malloc(size);
}

void free(void* p) { __libc_free(p); }

void* calloc(size_t count, size_t size) {
  // a product that does not fit is a request for more than any cap
  const size_t bytes = size != 0 && count > SIZE_MAX / size ? SIZE_MAX : count * size;
  if (!admit(bytes)) {
    errno = ENOMEM;
    return nullptr;
  }
  return __libc_calloc(count, size);
}

void* realloc(void* p, size_t size) {
  if (!admit(size)) {
    errno = ENOMEM;
    return nullptr;  // p stays valid, as after any failed realloc
  }
  return __libc_realloc(p, size);
}

void* memalign(size_t alignment, size_t size) { return aligned(alignment, size); }

void* aligned_alloc(size_t alignment, size_t size) { return aligned(alignment, size); }

int posix_memalign(void** out, size_t alignment, size_t size) {
  if (!valid_alignment(alignment)) return EINVAL;
  void* p = aligned(alignment, size);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}

void* valloc(size_t size) {
  if (!admit(size)) {
    errno = ENOMEM;
    return nullptr;
  }
  return __libc_valloc(size);
}

void* pvalloc(size_t size) {
  if (!admit(size)) {
    errno = ENOMEM;
    return nullptr;
  }
  return __libc_pvalloc(size);
}

}  // extern "C"

// ------------------------------------------------------------------ operator new and delete

void* operator new(size_t size) {
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](size_t size) { return ::operator new(size); }
void* operator new(size_t size, const std::nothrow_t&) noexcept { return std::malloc(size ? size : 1); }
void* operator new[](size_t size, const std::nothrow_t&) noexcept { return std::malloc(size ? size : 1); }
void* operator new(size_t size, std::align_val_t alignment) {
  if (void* p = aligned(std::max(size_t(alignment), sizeof(void*)), size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](size_t size, std::align_val_t alignment) { return ::operator new(size, alignment); }
void* operator new(size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return aligned(std::max(size_t(alignment), sizeof(void*)), size ? size : 1);
}
void* operator new[](size_t size, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return aligned(std::max(size_t(alignment), sizeof(void*)), size ? size : 1);
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

// ------------------------------------------------------------------ the check

namespace {

using namespace cagewrap;
using hostile::Loader;
namespace fs = std::filesystem;

// The file being loaded, for the watchdog (a signal handler may only read it).
char g_current[256] = "";

void watchdog(int) {
  const char prefix[] = "alloc_cap: FAIL: still loading after 20 s (hung?): ";
  [[maybe_unused]] ssize_t n = ::write(2, prefix, sizeof prefix - 1);
  n = ::write(2, g_current, std::strlen(g_current));
  n = ::write(2, "\n", 1);
  ::_exit(1);
}

// The loader's error message, or "" when the file loaded.
template <class T>
std::string error_of(const Result<T>& r) {
  return r.ok() ? std::string() : r.error().message;
}

std::string load(const hostile::HostileFile& file, const std::string& path, bool& loaded) {
  std::string message;
  switch (file.loader) {
    case Loader::kCharacter:
      message = error_of(load_character(path));
      break;
    case Loader::kMesh:
      message = error_of(load_mesh(path));
      break;
    case Loader::kProject:
      message = error_of(load_project(path));
      break;
    case Loader::kSetEdits: {
      auto edits = load_set_edits(path);
      if (!edits) {
        message = edits.error().message;
        break;
      }
      static const std::vector<glm::vec3> skin = hostile::set_edits_skin();
      static const Cage cage = hostile::set_edits_cage();
      message = error_of(resolve_set_edits(*edits, path, skin, cage));
      break;
    }
    case Loader::kPatch:
      message = error_of(load_patch(path));
      break;
    case Loader::kPatchGltf:
      message = error_of(load_patch_gltf(path));
      break;
    case Loader::kBinding:
      message = error_of(load_binding(path));
      break;
  }
  loaded = message.empty();
  return message;
}

// Loads `file` from `dir` under the cap and prints its line; false when a check fails. A hostile file
// must fail naming itself; an original must load. Neither may ask for more than the cap.
bool check(const hostile::HostileFile& file, const fs::path& dir, bool hostile, size_t& worst) {
  const std::string path = (dir / file.name).string();
  hostile::write_all(path, file.bytes);
  std::snprintf(g_current, sizeof g_current, "%s", file.name.c_str());
  bool loaded = false, threw = false;
  std::string message;
  g_largest = 0;
  g_refused = 0;
  alarm(kWatchdogSeconds);
  const auto start = std::chrono::steady_clock::now();
  try {
    message = load(file, path, loaded);
  } catch (const std::exception& e) {
    threw = true;  // a loader must return an error, not throw
    message = std::string("threw ") + e.what();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  alarm(0);
  const size_t largest = g_largest, refused = g_refused;
  worst = std::max(worst, largest);
  std::string problems;
  if (threw) problems += " threw;";
  if (hostile && loaded) problems += " loaded;";
  if (hostile && !loaded && !threw && message.find(path) == std::string::npos)
    problems += " the message does not name the file;";
  if (!hostile && !loaded) problems += " the original does not load;";
  if (refused) problems += " " + std::to_string(refused) + " request(s) above the cap;";
  if (seconds > kSecondsPerFile) problems += " took " + std::to_string(seconds) + " s;";
  // the message as read, with the folder left out
  for (size_t at; (at = message.find(dir.string() + "/")) != std::string::npos;)
    message.erase(at, dir.string().size() + 1);
  if (!hostile && message.empty()) message = "loads";
  std::printf("%-4s %-50s %-10s largest %11s B  %s\n", problems.empty() ? "ok" : "FAIL", file.name.c_str(),
              hostile::loader_name(file.loader), group_digits(largest).c_str(),
              problems.empty() ? message.c_str() : ("FAILED:" + problems + " [" + file.field + "] " + message).c_str());
  std::error_code ec;
  fs::remove(path, ec);
  return problems.empty();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2) {
    std::fprintf(stderr, "usage: cagewrap_alloc_cap [FOLDER (a fresh temporary one)]\n");
    return 2;
  }
  const fs::path dir = argc == 2 ? fs::path(argv[1])
                                 : fs::temp_directory_path() / ("cagewrap_alloc_cap_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "scratch");
  hostile::Corpus corpus;
  try {
    corpus = hostile::hostile_corpus((dir / "scratch").string());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "alloc_cap: cannot make the corpus: %s\n", e.what());
    return 1;
  }
  // the hooks are live: a request above the cap, through malloc and through operator new, is refused and
  // counted (were the replacement not linked in, this would allocate and the run would prove nothing)
  {
    g_refused = 0;
    void* volatile p = std::malloc(kCap + 1);
    bool threw = false;
    try {
      char* volatile q = new char[kCap + 1];
      delete[] q;
    } catch (const std::bad_alloc&) {
      threw = true;
    }
    if (p != nullptr || !threw || g_refused != 2) {
      std::fprintf(stderr, "alloc_cap: the allocation hooks are not in effect (malloc %s, new %s)\n",
                   p ? "granted" : "refused", threw ? "refused" : "granted");
      std::free(p);
      return 1;
    }
    g_refused = 0;
    g_largest = 0;
  }
  std::signal(SIGALRM, watchdog);
  size_t failed = 0, worst = 0;
  const auto start = std::chrono::steady_clock::now();
  for (const hostile::HostileFile& file : corpus.originals) failed += !check(file, dir, false, worst);
  for (const hostile::HostileFile& file : corpus.hostile) failed += !check(file, dir, true, worst);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::error_code ec;
  fs::remove_all(dir, ec);
  std::printf("alloc_cap: %zu hostile files and %zu originals, %zu failed; largest single request %s bytes (cap %s); "
              "%.3f s\n",
              corpus.hostile.size(), corpus.originals.size(), failed, group_digits(worst).c_str(),
              group_digits(kCap).c_str(), seconds);
  return failed ? 1 : 0;
}
