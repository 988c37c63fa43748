#include "core/document/character_embedding.h"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/base/atomic_write.h"
#include "core/base/file_hash.h"
#include "core/io/gltf_loader.h"

namespace cagewrap {

namespace fs = std::filesystem;

namespace {

Result<std::string> read_bytes(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return make_error(ErrorCode::kFileNotFound, path + ": no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kFileUnreadable, path + ": cannot be opened for reading");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return make_error(ErrorCode::kFileUnreadable, path + ": read failed");
  return bytes;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal() || fs::equivalent(a, b, ec);
}

}  // namespace

Result<Document> embed_character(const Document& doc) {
  if (doc.embedded_character) return doc;
  const std::string& path = doc.character_path;
  auto bytes = read_bytes(path);
  if (!bytes) return make_error(bytes.error().code, "cannot embed the character: " + bytes.error().message);
  if (const std::string h = format_hash(fnv1a64(*bytes)); h != doc.character_hash)
    return make_error(ErrorCode::kInvalidArgument,
                      path + ": cannot embed the character: the file changed since it was loaded (hash " + h +
                          ", loaded " + doc.character_hash + "); open the project again first");
  if (auto loaded = load_character_bytes(*bytes, path, {doc.character_keep_units}, path); !loaded)
    return make_error(loaded.error().code, "cannot embed the character: " + loaded.error().message);
  return with_embedded_character(doc, std::make_shared<const std::string>(std::move(bytes).value()));
}

Result<Document> unembed_character(const Document& doc, const std::string& path, bool replace) {
  if (!doc.embedded_character)
    return make_error(ErrorCode::kInvalidArgument, (doc.project_path.empty() ? std::string("the document") : doc.project_path) +
                                                       ": the character is not embedded; it is the file " + doc.character_path);
  if (path.empty()) return make_error(ErrorCode::kInvalidArgument, "give a file to write the character to");
  if (!doc.project_path.empty() && same_file(path, doc.project_path))
    return make_error(ErrorCode::kInvalidArgument, path + ": is the project file; choose another name for the character");
  std::error_code ec;
  bool write = true;
  if (fs::exists(path, ec)) {
    auto existing = read_bytes(path);
    write = !existing || *existing != *doc.embedded_character;
    if (write && !replace)
      return make_error(ErrorCode::kInvalidArgument,
                        path + ": already exists (another file); choose another name, or remove it first");
  }
  if (write)
    if (auto s = write_file_atomic(path, *doc.embedded_character); !s) return s.error();
  Document out = with_embedded_character(doc, nullptr);
  out.character_path = fs::absolute(path).lexically_normal().string();
  return out;
}

}  // namespace cagewrap
