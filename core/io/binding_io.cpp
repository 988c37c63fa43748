#include "core/io/binding_io.h"

#include "core/base/atomic_write.h"
#include "core/base/digits.h"

#include <cstring>
#include <fstream>
#include <iterator>

namespace cagewrap {

namespace {

constexpr char kMagic[8] = {'C', 'W', 'B', 'I', 'N', 'D', '0', '1'};
constexpr uint32_t kVersion = 3;  // reads 1 (no sets, no separation), 2 and 3 (a parametric driver's samples)
// A cage's binding is written as version 2 (older builds still read it); a sample binding as version 3.
constexpr uint32_t kCageVersion = 2;

class Writer {
 public:
  template <class T>
  void pod(const T& v) {
    const char* p = reinterpret_cast<const char*>(&v);
    buf_.insert(buf_.end(), p, p + sizeof(T));
  }
  template <class T>
  void array(const std::vector<T>& v) {
    pod<uint64_t>(v.size());
    if (v.empty()) return;  // data() may be null
    const char* p = reinterpret_cast<const char*>(v.data());
    buf_.insert(buf_.end(), p, p + v.size() * sizeof(T));
  }
  const std::vector<char>& data() const { return buf_; }

 private:
  std::vector<char> buf_;
};

class Reader {
 public:
  explicit Reader(std::vector<char> data) : buf_(std::move(data)) {}
  template <class T>
  bool pod(T& v) {
    if (buf_.size() - pos_ < sizeof(T)) return false;
    std::memcpy(&v, buf_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  // A table: its u64 count, checked against the bytes left before anything is allocated (a small file
  // may claim 2^63 entries), then its entries. `table` names it in problem().
  template <class T>
  bool array(std::vector<T>& v, const char* table) {
    uint64_t n;
    if (!pod(n)) return false;
    if (n > (buf_.size() - pos_) / sizeof(T)) {
      problem_ = std::string("table ") + table + " claims " + group_digits(n) + " entries of " +
                 std::to_string(sizeof(T)) + (sizeof(T) == 1 ? " byte (" : " bytes (") +
                 group_digits(static_cast<unsigned __int128>(n) * sizeof(T)) +
                 " bytes) but " + group_digits(buf_.size() - pos_) + " bytes are left in the file";
      return false;
    }
    v.resize(n);
    if (n) std::memcpy(v.data(), buf_.data() + pos_, n * sizeof(T));  // memcpy(nullptr, ..., 0) is undefined
    pos_ += n * sizeof(T);
    return true;
  }
  bool at_end() const { return pos_ == buf_.size(); }
  // Why the last read failed: a table larger than the file; empty when the file simply ended.
  const std::string& problem() const { return problem_; }

 private:
  std::vector<char> buf_;
  size_t pos_ = 0;
  std::string problem_;
};

}  // namespace

std::string binding_bytes(const Binding& b) {
  Writer w;
  for (char c : kMagic) w.pod(c);
  const bool samples = b.num_samples > 0;
  w.pod(samples ? kVersion : kCageVersion);
  w.pod(b.params.local);
  w.pod(b.params.epsilon);
  w.pod(b.params.max_elements);
  w.pod(b.params.scale);
  w.pod(b.params.max_distance);
  w.pod(b.params.close_distance);
  w.pod(static_cast<uint8_t>(b.params.variant));
  w.pod(b.h);
  w.pod(b.origin.x);
  w.pod(b.origin.y);
  w.pod(b.origin.z);
  w.pod(b.num_points);
  w.pod(b.num_cage_vertices);
  w.array(b.rest_cage);
  w.array(b.elements);
  w.array(b.element_status);
  w.array(b.offsets);
  w.array(b.ids);
  w.array(b.weights);
  w.array(b.bary);
  w.array(b.rigid_points);
  w.array(b.rigid_element);
  w.array(b.rigid_bary);
  w.pod(b.quality_inside);
  w.pod(b.max_set_size);
  w.pod(b.total_set_size);
  // version 2
  w.pod(static_cast<uint8_t>(b.params.separate));
  w.pod(b.params.separation_steps);
  w.pod(static_cast<uint8_t>(b.separation_applied));
  w.array(b.set_offsets);
  w.array(b.set_ids);
  w.array(b.set_weights);
  w.array(b.separated);
  if (samples) {  // version 3
    w.pod(b.num_samples);
    w.array(b.invalid_elements);
  }
  return std::string(w.data().begin(), w.data().end());
}

Status save_binding(const std::string& path, const Binding& binding) {
  if (binding.num_samples > 0)
    return make_error(ErrorCode::kInvalidArgument, path + ": a binding to a parametric driver's samples is not saved as a "
                                                          ".cwb file; it is rebuilt from the driver (docs/parametric-drivers.md)");
  // write beside, fsync, rename: a failed or killed write never leaves half a file under the real name
  return write_file_atomic(path, binding_bytes(binding));
}

Result<Binding> load_binding(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kFileNotFound, path + ": cannot be opened");
  std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.empty()) return make_error(ErrorCode::kEmpty, path + ": file is empty");
  Reader r(std::move(data));
  char magic[8];
  for (char& c : magic)
    if (!r.pod(c)) return make_error(ErrorCode::kParse, path + ": not a cagewrap binding (too short)");
  if (std::memcmp(magic, kMagic, 8) != 0) return make_error(ErrorCode::kParse, path + ": not a cagewrap binding (wrong magic)");
  uint32_t version;
  if (!r.pod(version)) return make_error(ErrorCode::kParse, path + ": truncated header");
  if (version < 1 || version > kVersion)
    return make_error(ErrorCode::kVersion, path + ": binding format version " + std::to_string(version) +
                                               " is not supported (this build reads version " +
                                               "1 to " + std::to_string(kVersion) + "); bind again");
  Binding b;
  uint8_t variant = 0;
  bool ok = r.pod(b.params.local) && r.pod(b.params.epsilon) && r.pod(b.params.max_elements) &&
            r.pod(b.params.scale) && r.pod(b.params.max_distance) && r.pod(b.params.close_distance) &&
            r.pod(variant) && r.pod(b.h) && r.pod(b.origin.x) && r.pod(b.origin.y) && r.pod(b.origin.z) &&
            r.pod(b.num_points) && r.pod(b.num_cage_vertices) && r.array(b.rest_cage, "rest_cage") &&
            r.array(b.elements, "elements") && r.array(b.element_status, "element_status") &&
            r.array(b.offsets, "offsets") && r.array(b.ids, "ids") && r.array(b.weights, "weights") &&
            r.array(b.bary, "bary") && r.array(b.rigid_points, "rigid_points") &&
            r.array(b.rigid_element, "rigid_element") && r.array(b.rigid_bary, "rigid_bary") &&
            r.pod(b.quality_inside) && r.pod(b.max_set_size) && r.pod(b.total_set_size);
  uint8_t separate = 0, applied = 0;
  if (version == 1) b.params.separate = false;  // made before automatic separation
  else
    ok = ok && r.pod(separate) && r.pod(b.params.separation_steps) && r.pod(applied) &&
         r.array(b.set_offsets, "set_offsets") && r.array(b.set_ids, "set_ids") &&
         r.array(b.set_weights, "set_weights") && r.array(b.separated, "separated");
  std::vector<uint32_t> invalid_samples;
  if (version >= 3) ok = ok && r.pod(b.num_samples) && r.array(invalid_samples, "invalid_samples");
  if (!ok)
    return make_error(ErrorCode::kParse, path + ": " + (r.problem().empty() ? "the file is cut short" : r.problem()));
  if (!r.at_end()) return make_error(ErrorCode::kParse, path + ": unexpected data after the last table");
  if (variant > 2) return make_error(ErrorCode::kParse, path + ": unknown variant " + std::to_string(variant));
  if (separate > 1 || applied > 1) return make_error(ErrorCode::kParse, path + ": the separation flags are not 0 or 1");
  if (version > 1) b.params.separate = separate;
  b.separation_applied = applied;
  for (uint32_t s : b.separated) {
    b.total_separated += s;
    b.separated_points += s > 0;
  }
  b.params.variant = static_cast<Variant>(variant);
  for (size_t e = 0; e < b.element_status.size(); ++e)
    if (static_cast<uint8_t>(b.element_status[e]) > 3)
      return make_error(ErrorCode::kParse, path + ": element " + std::to_string(e) + " has an unknown status " +
                                               std::to_string(static_cast<unsigned>(b.element_status[e])));
  if (auto v = validate(b.params); !v) return make_error(ErrorCode::kParse, path + ": " + v.error().message);
  if (auto v = validate_binding(b); !v) return make_error(v.error().code, path + ": " + v.error().message);
  for (size_t e = 0; e < b.element_status.size(); ++e)
    if (b.element_status[e] != ElementStatus::kValid) b.invalid_elements.push_back(static_cast<uint32_t>(e));
  for (size_t i = 0; i < invalid_samples.size(); ++i)
    if (invalid_samples[i] >= b.num_samples || (i > 0 && invalid_samples[i] <= invalid_samples[i - 1]))
      return make_error(ErrorCode::kParse, path + ": degenerate sample entry " + std::to_string(i) + " (" +
                                               std::to_string(invalid_samples[i]) + ") is out of order or past the " +
                                               std::to_string(b.num_samples) + " samples");
  if (b.num_samples > 0) b.invalid_elements = std::move(invalid_samples);
  return b;
}

}  // namespace cagewrap
