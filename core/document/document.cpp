#include "core/document/document.h"

#include <atomic>
#include <cstring>

#include "core/base/check.h"
#include "core/base/file_hash.h"
#include "core/io/gltf_loader.h"
#include "core/io/cage_import.h"
#include "core/geometry/mesh_io.h"

namespace cagewrap {

std::span<const glm::vec3> Document::cage_positions() const {
  if (!cage) return {};
  return cage->polygons.positions;
}

uint64_t next_revision() {
  static std::atomic<uint64_t> counter{0};
  return ++counter;
}

Result<Document> document_from_files(const std::string& character_path, const std::string& cage_path,
                                     const CharacterLoadOptions& load) {
  auto character = load_character(character_path, load);
  if (!character) return character.error();
  // a file with no vertex at all (animation only, or every primitive empty) has nothing to skin
  if (character->num_vertices() == 0)
    return make_error(ErrorCode::kEmpty,
                      character_path + ": has no vertices (no mesh primitive of the default scene holds any): nothing to skin");
  auto hash = hash_file(character_path);
  if (!hash) return hash.error();
  Document doc;
  doc.character = std::make_shared<const Character>(std::move(character).value());
  doc.character_path = character_path;
  doc.character_hash = std::move(hash).value();
  doc.character_keep_units = load.keep_units;
  if (!cage_path.empty()) {
    auto mesh = load_cage_mesh(cage_path);
    if (!mesh) return mesh.error();
    auto cage = make_cage(std::move(mesh).value(), cage_path);
    if (!cage) return cage.error();
    doc.cage = std::make_shared<const Cage>(std::move(cage).value());
  }
  doc.revision = next_revision();
  return doc;
}

Document with_cage_positions(const Document& doc, std::span<const glm::vec3> positions) {
  CAGEWRAP_CHECK(doc.cage, "with_cage_positions needs a document with a cage");
  CAGEWRAP_CHECK(positions.size() == doc.cage->num_vertices(), "one position per cage vertex");
  auto cage = std::make_shared<Cage>(*doc.cage);
  cage->polygons.positions.assign(positions.begin(), positions.end());
  return with_cage(doc, std::move(cage));
}

Document with_cage(const Document& doc, std::shared_ptr<const Cage> cage) {
  Document out = doc;
  out.cage = std::move(cage);
  const size_t before = doc.cage ? doc.cage->num_vertices() : 0;
  const size_t after = out.cage ? out.cage->num_vertices() : 0;
  if (!out.cage || out.cage_offsets.size() != after) out.cage_offsets.clear();
  if (before != after) {
    out.attachment.overrides.clear();
    clear_vertex_data(out.keyposes);
    out.sim.vertices.clear();
  }
  out.revision = next_revision();
  return out;
}

Document with_cage_offsets(const Document& doc, std::vector<glm::vec3> offsets) {
  Document out = doc;
  out.cage_offsets = std::move(offsets);
  out.revision = next_revision();
  return out;
}

Document with_params(const Document& doc, const BindParams& params) {
  Document out = doc;
  out.params = params;
  out.revision = next_revision();
  return out;
}

Document with_set_edits(const Document& doc, std::vector<SetEdit> edits) {
  Document out = doc;
  out.set_edits = std::move(edits);
  out.revision = next_revision();
  return out;
}

Document with_attachment(const Document& doc, AttachmentSettings attachment) {
  Document out = doc;
  out.attachment = std::move(attachment);
  out.revision = next_revision();
  return out;
}

Document with_keyposes(const Document& doc, std::vector<KeyposeSet> keyposes) {
  Document out = doc;
  out.keyposes = std::move(keyposes);
  out.revision = next_revision();
  return out;
}

Document with_sim(const Document& doc, SimSettings sim) {
  Document out = doc;
  out.sim = std::move(sim);
  out.revision = next_revision();
  return out;
}

Document with_patch_driver(const Document& doc, std::shared_ptr<const PatchDriver> driver) {
  Document out = doc;
  out.patch_driver = std::move(driver);
  out.revision = next_revision();
  return out;
}

Document with_driver_place(const Document& doc, DriverPlacement place) {
  Document out = doc;
  out.driver_place = std::move(place);
  out.revision = next_revision();
  return out;
}

size_t driver_position(const Document& doc, const DriverPlacement& place) {
  const int32_t a = place.after;
  return a < 0 ? doc.layers.size() : std::min(static_cast<size_t>(a), doc.layers.size());
}
size_t driver_position(const Document& doc) { return driver_position(doc, doc.driver_place); }

const BindParams& driver_params(const Document& doc, const DriverPlacement& place) {
  return place.params ? *place.params : doc.params;
}
const BindParams& driver_params(const Document& doc) { return driver_params(doc, doc.driver_place); }

bool driver_moves_skin(const Document& doc, size_t i) {
  if (i >= driver_count(doc)) return false;
  const bool solo = doc.stack.solo >= 0 && static_cast<size_t>(doc.stack.solo) < deformer_count(doc);
  if (solo) return false;
  if (const auto s = soloed_driver(doc)) return *s == i && driver_at(doc, i).driver->drive_skin;
  return driver_at(doc, i).driver->drive_skin;
}

std::optional<size_t> soloed_driver(const Document& doc) {
  if (doc.stack.solo_driver.empty()) return std::nullopt;
  for (size_t i = 0; i < driver_count(doc); ++i)
    if (driver_name(doc, i) == doc.stack.solo_driver) return i;
  return std::nullopt;
}

Document with_driver_solo(const Document& doc, std::optional<size_t> i) {
  Document out = doc;
  out.stack.solo_driver.clear();
  if (i) {
    CAGEWRAP_CHECK(*i < driver_count(doc), "with_driver_solo: no such parametric driver");
    DriverPlacement place = *driver_at(doc, *i).place;
    place.name = driver_name(doc, *i);  // baked: the solo follows the driver wherever it moves in the list
    out = with_driver_place(out, *i, std::move(place));
    out.stack.solo = -1;
    out.stack.solo_driver = driver_name(out, *i);
  }
  out.revision = next_revision();
  return out;
}
bool driver_moves_skin(const Document& doc) { return driver_moves_skin(doc, 0); }

DriverRef driver_at(const Document& doc, size_t i) {
  CAGEWRAP_CHECK(i < driver_count(doc), "driver_at: no such parametric driver");
  if (i == 0) return {doc.patch_driver.get(), &doc.driver_place};
  const DriverDeformer& d = doc.more_drivers[i - 1];
  return {d.driver.get(), &d.place};
}

std::string driver_name(const Document& doc, size_t i) {
  if (i < driver_count(doc) && !driver_at(doc, i).place->name.empty()) return driver_at(doc, i).place->name;
  return i == 0 ? "driver" : "driver " + std::to_string(i + 1);
}

Document with_more_drivers(const Document& doc, std::vector<DriverDeformer> drivers) {
  for (const DriverDeformer& d : drivers) CAGEWRAP_CHECK(d.driver != nullptr, "a parametric driver needs its surface");
  CAGEWRAP_CHECK(drivers.empty() || doc.patch_driver, "more parametric drivers need a first one");
  Document out = doc;
  out.more_drivers = std::move(drivers);
  out.revision = next_revision();
  return out;
}

Document with_first_driver(const Document& doc, size_t i) {
  CAGEWRAP_CHECK(i < driver_count(doc), "with_first_driver: no such parametric driver");
  Document out = doc;
  if (i > 0) {
    // each keeps the name it is shown by ("driver", "driver 3"), whatever its place
    if (out.driver_place.name.empty()) out.driver_place.name = driver_name(doc, 0);
    if (out.more_drivers[i - 1].place.name.empty()) out.more_drivers[i - 1].place.name = driver_name(doc, i);
    DriverDeformer& d = out.more_drivers[i - 1];
    std::swap(out.patch_driver, d.driver);
    std::swap(out.driver_place, d.place);
    out.revision = next_revision();
  }
  return out;
}

Document with_driver(const Document& doc, size_t i, std::shared_ptr<const PatchDriver> driver, DriverPlacement place) {
  CAGEWRAP_CHECK(i < driver_count(doc) && driver, "with_driver: no such parametric driver");
  Document out = doc;
  if (i == 0) {
    out.patch_driver = std::move(driver);
    out.driver_place = std::move(place);
  } else {
    out.more_drivers[i - 1] = {std::move(driver), std::move(place)};
  }
  out.revision = next_revision();
  return out;
}

Document with_driver_place(const Document& doc, size_t i, DriverPlacement place) {
  CAGEWRAP_CHECK(i < driver_count(doc), "with_driver_place: no such parametric driver");
  return with_driver(doc, i, i == 0 ? doc.patch_driver : doc.more_drivers[i - 1].driver, std::move(place));
}

Document without_first_driver(const Document& doc) {
  Document out = doc;
  out.revision = next_revision();
  if (out.more_drivers.empty()) {
    out.patch_driver = nullptr;
    out.driver_place = {};
    return out;
  }
  out.patch_driver = out.more_drivers.front().driver;
  out.driver_place = out.more_drivers.front().place;
  out.more_drivers.erase(out.more_drivers.begin());
  return out;
}

Document with_layers(const Document& doc, std::vector<DeformerLayer> layers) {
  for (const DeformerLayer& l : layers) CAGEWRAP_CHECK(l.cage != nullptr, "a deformer layer needs a cage");
  Document out = doc;
  out.layers = std::move(layers);
  out.revision = next_revision();
  return out;
}

Document with_stack(const Document& doc, DeformerStack stack) {
  Document out = doc;
  out.stack = stack;
  out.revision = next_revision();
  return out;
}

Document layer_document(const Document& doc, size_t i) {
  CAGEWRAP_CHECK(i < doc.layers.size(), "layer_document: no such layer");
  const DeformerLayer& l = doc.layers[i];
  // field by field: a copy of the whole document would copy every layer, driver and edit only to drop
  // them (Rig poses each layer through this at every frame)
  Document out;
  out.character = doc.character;
  out.character_path = doc.character_path;
  out.character_hash = doc.character_hash;
  out.character_keep_units = doc.character_keep_units;
  out.embedded_character = doc.embedded_character;
  out.cage = l.cage;
  out.params = l.params;
  out.set_edits = l.set_edits;
  out.cage_offsets = l.cage_offsets;
  out.attachment = l.attachment;
  out.keyposes = l.keyposes;
  out.sim = l.sim;
  out.project_path = doc.project_path;
  out.cache_binding = doc.cache_binding;
  out.binding_cache = l.binding_cache;
  out.revision = doc.revision;
  return out;  // the same revision: the same document, seen through one layer
}

bool deformer_muted(const Document& doc, size_t d) {
  if (soloed_driver(doc)) return true;  // a driver alone moves the skin
  if (doc.stack.solo >= 0 && static_cast<size_t>(doc.stack.solo) < deformer_count(doc)) return d != static_cast<size_t>(doc.stack.solo);
  if (d == 0) return doc.stack.base_muted;
  return d - 1 < doc.layers.size() ? doc.layers[d - 1].muted : true;
}

size_t moving_deformers(const Document& doc) {
  size_t n = 0;
  for (size_t d = 0; d < deformer_count(doc); ++d) n += !deformer_muted(doc, d);
  return n;
}

size_t moving_drivers(const Document& doc) {
  size_t n = 0;
  for (size_t i = 0; i < driver_count(doc); ++i) n += driver_moves_skin(doc, i);
  return n;
}

bool deformer_hidden(const Document& doc, size_t d) {
  if (d == 0) return doc.stack.base_hidden;
  return d - 1 < doc.layers.size() ? doc.layers[d - 1].hidden : true;
}

std::string deformer_name(const Document& doc, size_t d) {
  if (d == 0) return "cage";
  return d - 1 < doc.layers.size() ? doc.layers[d - 1].name : std::string();
}

Document deformer_document(const Document& doc, size_t d) {
  CAGEWRAP_CHECK(d < deformer_count(doc), "deformer_document: no such deformer");
  if (d > 0) return layer_document(doc, d - 1);
  Document out = doc;
  out.patch_driver = nullptr;
  out.driver_place = {};
  out.more_drivers.clear();
  out.layers.clear();
  out.stack = {};
  return out;  // the same revision, like layer_document
}

const char* stack_mode_name(StackMode mode) {
  switch (mode) {
    case StackMode::kInOrder: return "in_order";
    case StackMode::kSum: return "sum";
    case StackMode::kBlend: return "blend";
  }
  return "in_order";
}

bool parse_stack_mode(std::string_view name, StackMode& out) {
  for (StackMode m : {StackMode::kInOrder, StackMode::kSum, StackMode::kBlend})
    if (name == stack_mode_name(m)) {
      out = m;
      return true;
    }
  return false;
}

Document with_character(const Document& doc, std::shared_ptr<const Character> character, std::string path,
                        std::string hash) {
  Document out = doc;
  out.character = std::move(character);
  out.character_path = std::move(path);
  out.character_hash = std::move(hash);
  out.revision = next_revision();
  return out;
}

Document with_embedded_character(const Document& doc, std::shared_ptr<const std::string> bytes) {
  CAGEWRAP_CHECK(!bytes || format_hash(fnv1a64(*bytes)) == doc.character_hash,
                 "the embedded bytes must be the document's character file");
  Document out = doc;
  out.embedded_character = std::move(bytes);
  out.revision = next_revision();
  return out;
}

Document with_cache_binding(const Document& doc, bool cache) {
  Document out = doc;
  out.cache_binding = cache;
  out.revision = next_revision();
  return out;
}

bool same_params(const BindParams& a, const BindParams& b) {
  return a == b;
}

namespace {
bool same_patch_driver(const PatchDriver* a, const PatchDriver* b) {
  return a == b || (a && b && *a == *b);
}
}  // namespace

bool same_set_edits(std::span<const SetEdit> a, std::span<const SetEdit> b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) return false;
  return true;
}

namespace {
bool same_cage(const Cage* a, const Cage* b) {
  if (a == b) return true;
  if (!a || !b) return false;
  const PolyMesh &pa = a->polygons, &pb = b->polygons;
  return pa.face_start == pb.face_start && pa.face_vertices == pb.face_vertices &&
         pa.positions.size() == pb.positions.size() &&
         std::memcmp(pa.positions.data(), pb.positions.data(), pa.positions.size() * sizeof(glm::vec3)) == 0;
}

// bit for bit, like the cage positions
bool same_offsets(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0);
}

// Sizes, not capacities: the estimate is then the same for a snapshot and its copies.
template <class T>
size_t vector_bytes(const std::vector<T>& v) {
  return v.size() * sizeof(T);
}
}  // namespace

bool same_layer(const DeformerLayer& a, const DeformerLayer& b) {
  const bool same_mask = a.mask == b.mask || (a.mask && b.mask && *a.mask == *b.mask);
  return a.name == b.name && a.muted == b.muted && a.hidden == b.hidden && same_cage(a.cage.get(), b.cage.get()) && same_params(a.params, b.params) &&
         same_set_edits(a.set_edits, b.set_edits) && same_offsets(a.cage_offsets, b.cage_offsets) &&
         a.attachment == b.attachment && a.keyposes == b.keyposes && a.sim == b.sim && same_mask &&
         a.mask_source == b.mask_source;
}

namespace {
bool same_layers(std::span<const DeformerLayer> a, std::span<const DeformerLayer> b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!same_layer(a[i], b[i])) return false;
  return true;
}
}  // namespace

bool same_content(const Document& a, const Document& b) {
  return a.character_hash == b.character_hash && a.character_keep_units == b.character_keep_units &&
         !a.embedded_character == !b.embedded_character &&
         a.cache_binding == b.cache_binding && same_cage(a.cage.get(), b.cage.get()) &&
         same_offsets(a.cage_offsets, b.cage_offsets) && same_params(a.params, b.params) &&
         same_set_edits(a.set_edits, b.set_edits) && a.attachment == b.attachment &&
         a.keyposes == b.keyposes && a.sim == b.sim &&
         same_patch_driver(a.patch_driver.get(), b.patch_driver.get()) && a.driver_place == b.driver_place &&
         a.more_drivers == b.more_drivers &&
         a.preserved_fields == b.preserved_fields &&
         same_layers(a.layers, b.layers) && a.stack == b.stack;
}

bool same_cage_motion(const Document& a, const Document& b) {
  const bool same_character =
      a.character == b.character || (!a.character_hash.empty() && a.character_hash == b.character_hash);
  return same_character && same_cage(a.cage.get(), b.cage.get()) && same_offsets(a.cage_offsets, b.cage_offsets) && a.attachment == b.attachment && a.keyposes == b.keyposes &&
         a.sim == b.sim;
}

size_t estimated_bytes(const Character& c) {
  size_t n = sizeof(Character) + c.source.size();
  n += c.skeleton.size() * sizeof(SkeletonNode) + c.skeleton.order().size() * sizeof(uint32_t);
  for (const Skin& s : c.skins) n += sizeof(Skin) + vector_bytes(s.joints) + vector_bytes(s.inverse_bind);
  for (const Primitive& p : c.primitives) {
    n += sizeof(Primitive) + vector_bytes(p.positions) + vector_bytes(p.triangles) + vector_bytes(p.influence_start) +
         vector_bytes(p.influence_joint) + vector_bytes(p.influence_weight) + vector_bytes(p.morph_weights);
    for (const auto& m : p.morph_targets) n += vector_bytes(m);
  }
  for (const Clip& clip : c.clips) {
    n += sizeof(Clip) + vector_bytes(clip.channels);
    for (const auto& s : clip.samplers) n += sizeof(s) + vector_bytes(s.times) + vector_bytes(s.values);
  }
  for (const auto& w : c.warnings) n += sizeof(w) + w.size();
  return n;
}

size_t estimated_bytes(const Cage& cage) {
  return sizeof(Cage) + vector_bytes(cage.polygons.positions) + vector_bytes(cage.polygons.face_start) +
         vector_bytes(cage.polygons.face_vertices) + vector_bytes(cage.elements) + vector_bytes(cage.element_face);
}

size_t estimated_own_bytes(const Document& doc) {
  size_t n = sizeof(Document) + doc.character_path.size() + doc.character_hash.size() +
             doc.preserved_fields.size() + doc.project_path.size() + vector_bytes(doc.set_edits);
  for (const SetEdit& e : doc.set_edits) n += vector_bytes(e.exclude) + vector_bytes(e.include);
  n += vector_bytes(doc.cage_offsets) + vector_bytes(doc.attachment.overrides) + vector_bytes(doc.keyposes);
  n += vector_bytes(doc.sim.vertices) + vector_bytes(doc.sim.colliders);
  for (const Collider& c : doc.sim.colliders) n += c.name.size();
  for (size_t i = 0; i < driver_count(doc); ++i)
    for (const PatchSurface* s : {&driver_at(doc, i).driver->rest, &driver_at(doc, i).driver->posed})
      for (const PatchGrid& g : s->grids) n += sizeof(PatchGrid) + vector_bytes(g.points);
  auto keyposes = [](const std::vector<KeyposeSet>& sets) {
    size_t n = vector_bytes(sets);
    for (const KeyposeSet& s : sets) {
      n += s.name.size() + vector_bytes(s.drivers) + vector_bytes(s.keys);
      for (const KeyposeKey& k : s.keys) n += vector_bytes(k.values) + vector_bytes(k.vertices) + vector_bytes(k.offsets);
    }
    return n;
  };
  n += keyposes(doc.keyposes) - vector_bytes(doc.keyposes) + keyposes(doc.driver_place.keyposes) + doc.driver_place.mask_source.size();
  n += vector_bytes(doc.more_drivers);
  for (const DriverDeformer& d : doc.more_drivers) n += keyposes(d.place.keyposes) + d.place.mask_source.size() + d.place.name.size();
  n += vector_bytes(doc.layers);
  for (const DeformerLayer& l : doc.layers) {
    n += l.name.size() + l.mask_source.size() + vector_bytes(l.set_edits) + vector_bytes(l.cage_offsets) +
         vector_bytes(l.attachment.overrides) + keyposes(l.keyposes) + vector_bytes(l.sim.vertices) + vector_bytes(l.sim.colliders);
    for (const SetEdit& e : l.set_edits) n += vector_bytes(e.exclude) + vector_bytes(e.include);
  }
  return n;
}

}  // namespace cagewrap
