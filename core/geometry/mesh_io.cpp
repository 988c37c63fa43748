#include "core/geometry/mesh_io.h"

#include "core/geometry/text_mesh_readers.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <istream>
#include <memory>
#include <mutex>
#include <sstream>
#include <streambuf>
#include <string>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

namespace cagewrap {

bool has_extension(const std::string& path, const char* ext) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e == ext;
}

namespace {

using namespace OpenMesh;

// Receives the raw vertex and face stream of OpenMesh's readers; keeps faces OpenMesh's own mesh
// kernels would reject (non-manifold, duplicate), because the cage report must name them.
class RawImporter final : public IO::BaseImporter {
 public:
  explicit RawImporter(PolyMesh& mesh) : mesh_(mesh) {}
  VertexHandle add_vertex(const Vec3f& p) override {
    mesh_.positions.emplace_back(p[0], p[1], p[2]);
    return VertexHandle(static_cast<int>(mesh_.positions.size() - 1));
  }
  VertexHandle add_vertex(const Vec3d& p) override {
    mesh_.positions.emplace_back(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    return VertexHandle(static_cast<int>(mesh_.positions.size() - 1));
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3f(0, 0, 0)); }
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(const VHandles& corners) override {
    std::vector<uint32_t> idx;
    idx.reserve(corners.size());
    for (auto vh : corners) {
      // Negative or huge handles are recorded as out-of-range so validation names them.
      idx.push_back(vh.idx() < 0 ? UINT32_MAX : static_cast<uint32_t>(vh.idx()));
    }
    mesh_.add_face(idx);
    return FaceHandle(static_cast<int>(mesh_.num_faces() - 1));
  }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_point(VertexHandle vh, const Vec3f& p) override {
    if (vh.idx() >= 0 && static_cast<size_t>(vh.idx()) < mesh_.positions.size())
      mesh_.positions[static_cast<size_t>(vh.idx())] = {p[0], p[1], p[2]};
  }
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  size_t n_vertices() const override { return mesh_.positions.size(); }
  size_t n_faces() const override { return mesh_.num_faces(); }
  size_t n_edges() const override { return 0; }

 private:
  PolyMesh& mesh_;
};

// A stream buffer that keeps the first kKeep characters written to it and counts the rest: a reader
// that reports one problem per word of a hostile file cannot grow it without bound (OpenMesh's PLY
// header reader printed errors until memory ran out on a 141-byte file: found by fuzzing).
class BoundedTextBuffer final : public std::streambuf {
 public:
  static constexpr size_t kKeep = 4096;
  std::string str() const { return dropped_ ? text_ + " ..." : text_; }

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    if (text_.size() < kKeep)
      text_.push_back(traits_type::to_char_type(c));
    else
      dropped_ = true;
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    const size_t room = kKeep - std::min(kKeep, text_.size());
    const size_t take = std::min(room, static_cast<size_t>(n));
    text_.append(s, take);
    if (take < static_cast<size_t>(n)) dropped_ = true;
    return n;
  }

 private:
  std::string text_;
  bool dropped_ = false;
};

// OpenMesh reports problems on its global omerr() stream (and chatter on omlog()); while it reads, both
// write into a buffer of ours instead. The streams' buffers are swapped rather than their targets
// connected and disconnected: OpenMesh 9's multiplex_streambuf::disconnect never deletes the target
// that connect allocated (48 bytes lost per load), and std::cerr stays connected for any other
// OpenMesh message. Callers hold the mutex: the streams are global.
class CaptureOpenMeshErrors {
 public:
  CaptureOpenMeshErrors() : err_(omerr().rdbuf(&buffer_)), log_(omlog().rdbuf(&discard_)) {}
  ~CaptureOpenMeshErrors() {
    omerr().rdbuf(err_);
    omlog().rdbuf(log_);
  }
  CaptureOpenMeshErrors(const CaptureOpenMeshErrors&) = delete;
  CaptureOpenMeshErrors& operator=(const CaptureOpenMeshErrors&) = delete;
  std::string text() const {
    std::string s = buffer_.str();
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (auto& c : s)
      if (c == '\n') c = ' ';
    return s;
  }

 private:
  BoundedTextBuffer buffer_, discard_;
  std::streambuf* err_;
  std::streambuf* log_;
};

std::mutex& openmesh_mutex() {
  static std::mutex m;
  return m;
}

// An input stream over bytes in memory (no copy), seekable: OpenMesh's readers seek.
class MemoryInput final : public std::streambuf {
 public:
  explicit MemoryInput(std::string& bytes) { setg(bytes.data(), bytes.data(), bytes.data() + bytes.size()); }

 protected:
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override {
    if (!(which & std::ios_base::in)) return pos_type(off_type(-1));
    const off_type base = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? gptr() - eback() : egptr() - eback();
    const off_type at = base + off;
    if (at < 0 || at > egptr() - eback()) return pos_type(off_type(-1));
    setg(eback(), eback() + at, egptr());
    return pos_type(at);
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
    return seekoff(off_type(pos), std::ios_base::beg, which);
  }
};

// PLY, STL and binary OFF through OpenMesh's readers, every vertex and face kept by RawImporter:
// from the file, or from `bytes` (a PLY file with its header rewritten, check_ascii_ply).
Result<PolyMesh> read_with_openmesh(const std::string& path, std::string* bytes = nullptr) {
  PolyMesh mesh;
  RawImporter importer(mesh);
  IO::Options options;
  bool read_ok;
  std::string om_errors;
  {
    std::lock_guard lock(openmesh_mutex());
    CaptureOpenMeshErrors capture;
    if (bytes) {
      MemoryInput buffer(*bytes);
      std::istream in(&buffer);
      read_ok = IO::IOManager().read(in, ".ply", importer, options);
    } else {
      read_ok = IO::IOManager().read(path, importer, options);
    }
    om_errors = capture.text();
  }
  if (!read_ok)
    return make_error(ErrorCode::kParse, path + ": could not be parsed" +
                                             (om_errors.empty() ? std::string() : " (" + om_errors + ")"));
  return mesh;
}

// The whole file in memory. The buffer is anonymous memory mapped with MAP_POPULATE, then read() into:
// on a 100 MB OBJ the page faults of reading into a fresh malloc'd buffer cost more than the parse.
// (Mapping the file itself is cheaper still, but a file truncated while we read it would then end the
// program with SIGBUS.)
class FileBuffer {
 public:
  FileBuffer() = default;
  FileBuffer(const FileBuffer&) = delete;
  FileBuffer& operator=(const FileBuffer&) = delete;
  ~FileBuffer() { reset(); }
  // false when the file cannot be opened or read
  bool read(const std::string& path) {
    reset();
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    struct stat st {};
    bool ok = ::fstat(fd, &st) == 0;
    if (ok && st.st_size > 0) {
      capacity_ = static_cast<size_t>(st.st_size);
      void* p = ::mmap(nullptr, capacity_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_POPULATE, -1, 0);
      if (p == MAP_FAILED) {
        capacity_ = 0;
        ok = false;
      } else {
        data_ = static_cast<char*>(p);
        while (size_ < capacity_) {
          const ssize_t n = ::read(fd, data_ + size_, capacity_ - size_);
          if (n < 0 && errno == EINTR) continue;
          if (n < 0) ok = false;
          if (n <= 0) break;  // error, or the file shrank meanwhile: keep what was read
          size_ += static_cast<size_t>(n);
        }
      }
    }
    ::close(fd);
    return ok;
  }
  void reset() {
    if (data_) ::munmap(data_, capacity_);
    data_ = nullptr;
    size_ = capacity_ = 0;
  }
  std::string_view view() const { return {data_, size_}; }

 private:
  char* data_ = nullptr;
  size_t size_ = 0, capacity_ = 0;
};

}  // namespace

Result<PolyMesh> load_mesh(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) return make_error(ErrorCode::kFileNotFound, path + ": no such file");
  if (fs::is_directory(path, ec)) return make_error(ErrorCode::kFileUnreadable, path + ": is a directory");
  if (fs::file_size(path, ec) == 0) return make_error(ErrorCode::kEmpty, path + ": file is empty");
  const bool obj = has_extension(path, ".obj"), ply = has_extension(path, ".ply"), off = has_extension(path, ".off"),
             stl = has_extension(path, ".stl");
  if (!(obj || ply || off || stl))
    return make_error(ErrorCode::kUnsupportedFormat,
                      path + ": unsupported mesh format (use .obj, .ply, .off or .stl)");
  FileBuffer file;
  if (!file.read(path)) return make_error(ErrorCode::kFileUnreadable, path + ": cannot be opened for reading");
  const std::string_view data = file.view();
  if (data.empty()) return make_error(ErrorCode::kEmpty, path + ": file is empty");
  Result<PolyMesh> mesh = PolyMesh{};
  if (obj) {
    mesh = read_obj(data, path);
  } else if (off && !off_is_binary(data)) {
    mesh = read_off(data, path);
  } else {
    // OpenMesh must never see a bad number in a text file: its readers go on from a failed stream
    // and its PLY header reader is not robust to junk: it reads the header as we checked it
    std::string canonical_ply;
    if (ply) {
      if (auto s = check_ascii_ply(data, path, &canonical_ply); !s) return s.error();
    } else if (stl) {
      if (auto s = check_ascii_stl(data, path); !s) return s.error();
    } else if (off) {
      if (auto s = check_binary_off(data, path); !s) return s.error();
    }
    file.reset();
    mesh = read_with_openmesh(path, ply ? &canonical_ply : nullptr);
  }
  if (!mesh) return mesh.error();
  if (mesh->positions.empty()) return make_error(ErrorCode::kEmpty, path + ": has no vertices");
  if (auto valid = validate_mesh(*mesh, path); !valid) return valid.error();
  return mesh;
}

Status save_obj(const std::string& path, std::span<const glm::vec3> positions, const PolyMesh& topology) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f) return make_error(ErrorCode::kWrite, path + ": cannot be opened for writing");
  std::vector<char> buffer(1 << 20);
  std::setvbuf(f.get(), buffer.data(), _IOFBF, buffer.size());
  std::fprintf(f.get(), "# written by cagewrap\n");
  for (const auto& p : positions) std::fprintf(f.get(), "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
  for (size_t i = 0; i < topology.num_faces(); ++i) {
    std::fputc('f', f.get());
    for (uint32_t c : topology.face(i)) std::fprintf(f.get(), " %u", c + 1);
    std::fputc('\n', f.get());
  }
  if (std::fflush(f.get()) != 0 || std::ferror(f.get()))
    return make_error(ErrorCode::kWrite, path + ": write failed (disk full?)");
  return Ok{};
}

Status save_bin(const std::string& path, std::span<const glm::vec3> positions) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return make_error(ErrorCode::kWrite, path + ": cannot be opened for writing");
  static_assert(sizeof(glm::vec3) == 12);
  out.write(reinterpret_cast<const char*>(positions.data()),
            static_cast<std::streamsize>(positions.size() * sizeof(glm::vec3)));
  if (!out) return make_error(ErrorCode::kWrite, path + ": write failed (disk full?)");
  return Ok{};
}

Result<std::vector<glm::vec3>> load_bin(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return make_error(ErrorCode::kFileNotFound, path + ": cannot be opened");
  auto size = static_cast<size_t>(in.tellg());
  if (size % 12 != 0)
    return make_error(ErrorCode::kParse, path + ": size " + std::to_string(size) +
                                             " bytes is not a multiple of 12 (float32 x 3 per vertex)");
  std::vector<glm::vec3> out(size / 12);
  in.seekg(0);
  in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(size));
  if (!in) return make_error(ErrorCode::kFileUnreadable, path + ": read failed");
  return out;
}

Status save_positions(const std::string& path, std::span<const glm::vec3> positions, const PolyMesh& topology) {
  if (has_extension(path, ".bin")) return save_bin(path, positions);
  if (has_extension(path, ".obj")) return save_obj(path, positions, topology);
  return make_error(ErrorCode::kUnsupportedFormat, path + ": output must end in .obj or .bin");
}

}  // namespace cagewrap
