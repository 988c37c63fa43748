// libFuzzer harness for the characters read through assimp (core/io/assimp_loader.h): the input's first bytes
// pick the file's extension as a tool would have named it (FBX's "Kaydara", Collada's XML, DirectX's "xof ",
// Blitz3D's "BB3D", MilkShape's "MS3D", Doom 3's "MD5Version"; anything else is an SMD, a text format
// with no magic), and the loader reads that file. Any outcome but a crash, a sanitizer report or a hang is
// fine: bad files must fail with a message naming the file. The importer runs in a child process, as it does for
// users (its own crashes, frequent on malformed files, become errors naming the file); a file it read there is
// then read in this process too, so that this project's part of the import runs under the sanitizers.
// tests/fuzz/assimp_lsan.supp holds the leaks of libassimp's own.
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "core/io/gltf_loader.h"
#include "tests/fuzz/fuzz_file.h"

namespace {

const char* extension_of(std::string_view head) {
  auto has = [&](std::string_view magic) { return head.find(magic) != std::string_view::npos; };
  if (has("Kaydara") || has("FBXHeaderExtension")) return ".fbx";
  if (has("<?xml") || has("COLLADA")) return ".dae";
  if (head.substr(0, 4) == "xof ") return ".x";
  if (head.substr(0, 4) == "BB3D") return ".b3d";
  if (head.substr(0, 4) == "MS3D") return ".ms3d";
  if (has("MD5Version")) return ".md5mesh";
  return ".smd";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view head(reinterpret_cast<const char*>(data), std::min<size_t>(size, 256));
  const std::string path = cagewrap::fuzz::write_input(std::string("in") + extension_of(head), data, size);
  auto c = cagewrap::load_character(path);
  if (!c.ok() && c.error().message.find(path) == std::string::npos) std::abort();  // errors name the file
  if (c.ok()) {
    cagewrap::CharacterLoadOptions here;
    here.in_process = true;
    auto d = cagewrap::load_character(path, here);
    // (not necessarily the same character: assimp's MD5 reader, for one, reads uninitialised memory on some
    // malformed files and gives a face out of range in one run and not in another; either way is handled)
    if (!d.ok() && d.error().message.find(path) == std::string::npos) std::abort();
  }
  return 0;
}
