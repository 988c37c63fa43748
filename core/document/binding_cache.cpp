#include "core/document/binding_cache.h"

#include <cstring>
#include <functional>
#include <filesystem>
#include <type_traits>

#include "core/io/binding_io.h"
#include "core/base/check.h"
#include "core/base/file_hash.h"
#include "core/deform/patch_binding.h"
#include "core/deform/registration.h"

namespace cagewrap {

namespace fs = std::filesystem;

namespace {

// FNV-1a over values in a fixed order (never over struct memory: padding is not content).
class Hasher {
 public:
  template <class T>
  Hasher& pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    h_ = fnv1a64(std::string_view(reinterpret_cast<const char*>(&v), sizeof v), h_);
    return *this;
  }
  template <class T>
  Hasher& list(const std::vector<T>& v) {
    pod<uint64_t>(v.size());
    if (!v.empty()) h_ = fnv1a64(std::string_view(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)), h_);
    return *this;
  }
  std::string text() const { return format_hash(h_); }

 private:
  uint64_t h_ = kFnv1a64Offset;
};

bool same_floats(const std::vector<glm::vec3>& a, std::span<const glm::vec3> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0);
}

// The weight rule is part of the program: a binding cached before the tie band (issue 18) is stale.
std::string program_input() {
  return std::string("cagewrap ") + CAGEWRAP_VERSION + " (weights: tie band " + std::to_string(kTieBand) + ")";
}

std::string params_input(const BindParams& p) {
  return Hasher()
      .pod(p.local)
      .pod(p.epsilon)
      .pod(p.max_elements)
      .pod(p.scale)
      .pod(p.max_distance)
      .pod(p.close_distance)
      .pod(static_cast<uint8_t>(p.variant))
      .pod(static_cast<uint8_t>(p.separate))
      .pod(p.separation_steps)
      .text();
}

std::string set_edits_input(std::span<const SetEdit> set_edits) {
  Hasher edits;
  edits.pod<uint64_t>(set_edits.size());
  for (const SetEdit& e : set_edits) edits.pod(e.point).pod(static_cast<uint8_t>(e.only)).list(e.exclude).list(e.include);
  return edits.text();
}

// The cached binding `r` names, when it is still valid: the inputs `now`, the file's hash, and `fits`.
Result<Binding> load_recorded(const BindingCacheRecord& r, const BindingInputs& now,
                              const std::function<Status(const Binding&)>& fits) {
  const std::string changed = changed_inputs(r.inputs, now);
  if (!changed.empty())
    return make_error(ErrorCode::kInvalidArgument,
                      r.file + " is out of date: " + changed + " changed since it was written");
  auto hash = hash_file(r.file);
  if (!hash) return make_error(hash.error().code, r.file + ": the cached binding is gone (" + hash.error().message + ")");
  if (*hash != r.file_hash)
    return make_error(ErrorCode::kInvalidArgument, r.file + " was changed or replaced since the project was saved (hash " +
                                                       *hash + ", the project says " + r.file_hash + ")");
  auto binding = load_binding(r.file);
  if (!binding) return binding.error();
  if (auto f = fits(*binding); !f)
    return make_error(f.error().code, r.file + " does not fit the project: " + f.error().message);
  return binding;
}

// The cache file of `binding` at `path` with the inputs `inputs` (`fits` checked first).
Result<BindingCacheFile> make_cache_file(std::string path, const Binding& binding, BindingInputs inputs, const Status& fits) {
  BindingCacheFile out;
  out.path = std::move(path);
  if (!fits) return make_error(fits.error().code, out.path + ": the binding was not cached: " + fits.error().message);
  out.bytes = binding_bytes(binding);
  out.record.file = fs::absolute(out.path).lexically_normal().string();
  out.record.file_hash = format_hash(fnv1a64(out.bytes));
  out.record.inputs = std::move(inputs);
  return out;
}

}  // namespace

std::string binding_cache_path(const std::string& project_path, size_t deformer) {
  return deformer == 0 ? project_path + ".cwb" : project_path + "." + std::to_string(deformer) + ".cwb";
}

BindingInputs binding_inputs(const Document& doc) {
  CAGEWRAP_CHECK(doc.cage, "a binding's inputs need a cage");
  BindingInputs in;
  in.program = program_input();
  in.character = doc.character_hash + (doc.character_keep_units ? " keep-units" : "");
  const PolyMesh& cage = doc.cage->polygons;
  in.cage = Hasher().list(cage.face_start).list(cage.face_vertices).list(cage.positions).text();
  in.params = params_input(doc.params);
  in.set_edits = set_edits_input(doc.set_edits);
  const BindParams& p = doc.params;
  // the attachment reaches the bind only through automatic separation's part labels
  Hasher attachment;
  if (p.separate) {
    attachment.pod(static_cast<uint8_t>(doc.attachment.mode)).pod(doc.attachment.smooth_width);
    attachment.pod<uint64_t>(doc.attachment.overrides.size());
    for (const AttachmentOverride& o : doc.attachment.overrides) attachment.pod(o.vertex).pod(o.node);
  }
  in.attachment = attachment.text();
  return in;
}

std::string changed_inputs(const BindingInputs& recorded, const BindingInputs& now) {
  const std::pair<std::string BindingInputs::*, std::string> parts[] = {
      {&BindingInputs::character, "the character file"},
      {&BindingInputs::cage, "the cage"},
      {&BindingInputs::params, "the binding parameters"},
      {&BindingInputs::set_edits, "the set edits"},
      {&BindingInputs::attachment, "the attachment settings"},
      {&BindingInputs::program, "the program (" + recorded.program + " made it)"},
  };
  std::vector<std::string> names;
  for (const auto& [member, name] : parts)
    if (recorded.*member != now.*member) names.push_back(name);
  std::string s;
  for (size_t i = 0; i < names.size(); ++i)
    s += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return s;
}

Status binding_fits(const Binding& binding, const Document& doc) {
  if (!doc.cage || !doc.character)
    return make_error(ErrorCode::kInvalidArgument, "the document has no cage or no character");
  if (!(binding.params == doc.params))
    return make_error(ErrorCode::kInvalidArgument, "it was made with other binding parameters");
  if (!same_floats(binding.rest_cage, doc.cage_positions()))
    return make_error(ErrorCode::kTopologyMismatch, "it was made from another rest cage (" +
                                                        std::to_string(binding.rest_cage.size()) + " vertices, the project's has " +
                                                        std::to_string(doc.cage->num_vertices()) + ")");
  if (binding.elements != doc.cage->elements)
    return make_error(ErrorCode::kTopologyMismatch, "it was made from a cage with other faces");
  if (binding.num_points != doc.character->num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "it binds " + std::to_string(binding.num_points) +
                                                        " skin points, the character has " +
                                                        std::to_string(doc.character->num_vertices()));
  return Ok{};
}

Result<BindingCacheFile> make_binding_cache(const std::string& project_path, const Document& doc,
                                            const Binding& binding, size_t deformer) {
  const Status fits = binding_fits(binding, doc);
  return make_cache_file(binding_cache_path(project_path, deformer), binding, fits ? binding_inputs(doc) : BindingInputs{}, fits);
}

Result<Binding> load_binding_cache(const Document& doc) {
  const BindingCacheRecord& r = doc.binding_cache;
  if (r.file.empty())
    return make_error(ErrorCode::kFileNotFound, (doc.project_path.empty() ? std::string("the document") : doc.project_path) +
                                                    ": no binding is cached");
  if (!doc.cage) return make_error(ErrorCode::kInvalidArgument, r.file + ": the project has no cage to use it with");
  return load_recorded(r, binding_inputs(doc), [&doc](const Binding& b) { return binding_fits(b, doc); });
}

std::string driver_binding_cache_path(const std::string& project_path, size_t driver) {
  return project_path + ".D" + std::to_string(driver + 1) + ".cwb";
}

BindingInputs driver_binding_inputs(const Document& doc, size_t driver) {
  const DriverRef r = driver_at(doc, driver);
  BindingInputs in;
  in.program = program_input();
  in.character = doc.character_hash + (doc.character_keep_units ? " keep-units" : "");
  Hasher surface;
  surface.pod(r.driver->density).pod<uint64_t>(r.driver->rest.grids.size());
  for (const PatchGrid& g : r.driver->rest.grids) surface.pod(static_cast<uint8_t>(g.basis)).pod(g.rows).pod(g.cols).list(g.points);
  in.cage = surface.text();
  in.params = params_input(patch_bind_params(driver_params(doc, *r.place)));
  in.set_edits = set_edits_input(r.place->set_edits);
  in.attachment = Hasher().text();  // a driver's attachment does not reach its bind
  return in;
}

Status driver_binding_fits(const Binding& binding, const Document& doc, size_t driver) {
  if (!doc.character) return make_error(ErrorCode::kInvalidArgument, "the document has no character");
  const DriverRef r = driver_at(doc, driver);
  if (!(binding.params == patch_bind_params(driver_params(doc, *r.place))))
    return make_error(ErrorCode::kInvalidArgument, "it was made with other binding parameters");
  const size_t samples = patch_sample_count(r.driver->rest, r.driver->density);
  if (binding.num_samples == 0 || binding.num_samples != samples || !binding.rest_cage.empty())
    return make_error(ErrorCode::kTopologyMismatch, "it binds to " + std::to_string(binding.num_samples) +
                                                        " driver samples, the driver has " + std::to_string(samples));
  if (binding.num_points != doc.character->num_vertices())
    return make_error(ErrorCode::kTopologyMismatch, "it binds " + std::to_string(binding.num_points) +
                                                        " skin points, the character has " +
                                                        std::to_string(doc.character->num_vertices()));
  return Ok{};
}

Result<BindingCacheFile> make_driver_binding_cache(const std::string& project_path, const Document& doc, size_t driver,
                                                   const Binding& binding) {
  const Status fits = driver_binding_fits(binding, doc, driver);
  return make_cache_file(driver_binding_cache_path(project_path, driver), binding,
                         fits ? driver_binding_inputs(doc, driver) : BindingInputs{}, fits);
}

Result<Binding> load_driver_binding_cache(const Document& doc, size_t driver) {
  const BindingCacheRecord& r = driver_at(doc, driver).place->binding_cache;
  if (r.file.empty())
    return make_error(ErrorCode::kFileNotFound, (doc.project_path.empty() ? std::string("the document") : doc.project_path) +
                                                    ": no binding of parametric driver '" + driver_name(doc, driver) + "' is cached");
  return load_recorded(r, driver_binding_inputs(doc, driver),
                       [&doc, driver](const Binding& b) { return driver_binding_fits(b, doc, driver); });
}

StackBindingCache load_stack_binding_caches(const Document& doc) {
  StackBindingCache out;
  out.bindings.resize(deformer_count(doc));
  for (size_t d = 0; d < out.bindings.size(); ++d) {
    if (deformer_muted(doc, d)) continue;
    const BindingCacheRecord& r = d == 0 ? doc.binding_cache : doc.layers[d - 1].binding_cache;
    if (r.file.empty() || (d == 0 && !doc.cage)) continue;
    auto b = load_binding_cache(deformer_document(doc, d));
    if (b) {
      out.bindings[d] = std::move(b).value();
      ++out.used;
    } else {
      out.not_used.push_back(b.error().message);
    }
  }
  out.drivers.resize(driver_count(doc));
  for (size_t i = 0; i < out.drivers.size(); ++i) {
    if (!driver_moves_skin(doc, i) || driver_at(doc, i).place->binding_cache.file.empty()) continue;
    auto b = load_driver_binding_cache(doc, i);
    if (b) {
      out.drivers[i] = std::move(b).value();
      ++out.drivers_used;
    } else {
      out.not_used.push_back(b.error().message);
    }
  }
  return out;
}

}  // namespace cagewrap
