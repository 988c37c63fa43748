// Tests for core/io/binding_io.h (the .cwb file) and for the checks Deformer::create and deform() make on a
// binding and a posed cage: a saved binding reloads identically and deforms bit for bit as the original;
// a damaged file fails cleanly with an error naming the file, never a crash or a huge allocation.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "core/io/binding_io.h"
#include "core/deform/deformer.h"
#include "core/base/digits.h"
#include "core/deform/registration.h"
#include "tests/expect_error.h"
#include "tests/fixtures.h"

namespace cagewrap {
namespace {

namespace fs = std::filesystem;


// A damaged index table caught by load_binding: a parse or range error naming the file.
::testing::AssertionResult RejectedAtLoad(const Result<Binding>& r, std::initializer_list<std::string> parts) {
  if (r.ok()) return ::testing::AssertionFailure() << "loaded";
  const ErrorCode c = r.error().code;
  if (c != ErrorCode::kParse && c != ErrorCode::kIndexOutOfRange)
    return ::testing::AssertionFailure() << "code " << error_code_name(c) << ": " << r.error().message;
  return Fails(r, c, parts);
}

constexpr Variant kVariants[] = {Variant::kBasic, Variant::kClamped, Variant::kExtended};

// The skin: a UV sphere of radius 0.5; the cage: the cube [-1, 1]^3 with each side split into 2 x 2 quads.
struct Scene {
  PolyMesh skin = fixtures::sphere_skin(0.5, 8, 12);
  Cage cage = fixtures::box_cage(1.0, 2);
};

// The same cube plus a zero-area triangle (on a new vertex at the middle of an edge) and a second copy
// of face 0, so the binding lists skipped elements.
Cage cage_with_bad_elements() {
  PolyMesh m = fixtures::box_cage(1.0, 2).polygons;
  auto face0 = m.face(0);
  std::vector<uint32_t> copy(face0.begin(), face0.end());
  const uint32_t a = copy[0], b = copy[1];
  m.positions.push_back(0.5f * (m.positions[a] + m.positions[b]));
  const uint32_t mid = static_cast<uint32_t>(m.positions.size() - 1);
  m.add_face({a, mid, b});
  m.add_face(copy);
  return std::move(make_cage(std::move(m), "cage with bad elements")).value();
}

Binding bind_or_die(const PolyMesh& skin, const Cage& cage, const BindParams& p, std::span<const SetEdit> edits = {}) {
  auto b = bind_skin(skin.positions, cage, cage.polygons.positions, p, edits);
  EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error().message);
  return std::move(b).value();
}

// A non-rigid pose: the half x > 0 bent 40 degrees about z, then everything sheared a little.
std::vector<glm::vec3> posed_cage(const Cage& cage) {
  auto p = fixtures::bent(cage.polygons.positions, 0.0, 40.0);
  for (auto& v : p) v.y += 0.2f * v.x;
  return p;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expect_same_binding(const Binding& a, const Binding& b) {
  EXPECT_EQ(a.params.local, b.params.local);
  EXPECT_EQ(a.params.epsilon, b.params.epsilon);
  EXPECT_EQ(a.params.max_elements, b.params.max_elements);
  EXPECT_EQ(a.params.scale, b.params.scale);
  EXPECT_EQ(a.params.max_distance, b.params.max_distance);
  EXPECT_EQ(a.params.close_distance, b.params.close_distance);
  EXPECT_EQ(a.params.variant, b.params.variant);
  EXPECT_EQ(a.h, b.h);
  EXPECT_EQ(a.origin, b.origin);
  EXPECT_EQ(a.num_points, b.num_points);
  EXPECT_EQ(a.num_cage_vertices, b.num_cage_vertices);
  EXPECT_TRUE(same_bytes(a.rest_cage, b.rest_cage));
  EXPECT_EQ(a.elements, b.elements);
  EXPECT_EQ(a.element_status, b.element_status);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.ids, b.ids);
  EXPECT_TRUE(same_bytes(a.weights, b.weights));
  EXPECT_TRUE(same_bytes(a.bary, b.bary));
  EXPECT_EQ(a.rigid_points, b.rigid_points);
  EXPECT_EQ(a.rigid_element, b.rigid_element);
  EXPECT_TRUE(same_bytes(a.rigid_bary, b.rigid_bary));
  EXPECT_EQ(a.invalid_elements, b.invalid_elements);
  EXPECT_EQ(a.quality_inside, b.quality_inside);
  EXPECT_EQ(a.max_set_size, b.max_set_size);
  EXPECT_EQ(a.total_set_size, b.total_set_size);
}

std::vector<glm::vec3> deform_or_die(const Binding& b, std::span<const glm::vec3> skin, std::span<const glm::vec3> posed) {
  auto d = Deformer::create(b, skin);
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
  std::vector<glm::vec3> out(skin.size(), glm::vec3(NAN));
  if (!d.ok()) return out;
  auto s = d->deform(posed, out);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return out;
}

// Byte offsets of the fields, from the layout documented in binding_io.h.
struct Layout {
  static constexpr size_t kVersion = 8, kVariant = 56, kEpsilon = 20, kNumPoints = 89, kFirstArray = 97;
  // per table, in file order: offset of its u64 count (the data follows)
  size_t rest_cage, elements, element_status, offsets, ids, weights, bary, rigid_points, rigid_element, rigid_bary;
  size_t separate, set_offsets, set_ids, set_weights, separated;  // version 2
  size_t end;
  explicit Layout(const Binding& b) {
    size_t at = kFirstArray;
    auto table = [&](size_t count, size_t elem) {
      size_t here = at;
      at += 8 + count * elem;
      return here;
    };
    rest_cage = table(b.rest_cage.size(), 12);
    elements = table(b.elements.size(), 12);
    element_status = table(b.element_status.size(), 1);
    offsets = table(b.offsets.size(), 4);
    ids = table(b.ids.size(), 4);
    weights = table(b.weights.size(), 4);
    bary = table(b.bary.size(), 4);
    rigid_points = table(b.rigid_points.size(), 4);
    rigid_element = table(b.rigid_element.size(), 4);
    rigid_bary = table(b.rigid_bary.size(), 4);
    at += 4 + 4 + 8;  // the report
    separate = at;
    at += 1 + 4 + 1;  // separate, separation_steps, separation_applied
    set_offsets = table(b.set_offsets.size(), 4);
    set_ids = table(b.set_ids.size(), 4);
    set_weights = table(b.set_weights.size(), 4);
    separated = table(b.separated.size(), 4);
    end = at;
  }
};

class BindingIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("cagewrap-binding_io-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<char> read(const std::string& p) const {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  std::string write(const std::string& name, const std::vector<char>& bytes, size_t size) const {
    std::string p = path(name);
    std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(size));
    return p;
  }
  std::string write(const std::string& name, const std::vector<char>& bytes) const {
    return write(name, bytes, bytes.size());
  }
  template <class T>
  static void poke(std::vector<char>& bytes, size_t at, T value) {
    ASSERT_LE(at + sizeof(T), bytes.size());
    std::memcpy(bytes.data() + at, &value, sizeof(T));
  }
  template <class T>
  static T peek(const std::vector<char>& bytes, size_t at) {
    T v{};
    std::memcpy(&v, bytes.data() + at, sizeof(T));
    return v;
  }
  // Binds `scene` with `variant`, saves it, and returns the file's bytes.
  std::vector<char> saved(const Binding& b, const std::string& name = "b.cwb") {
    auto s = save_binding(path(name), b);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    return read(path(name));
  }
  fs::path dir_;
};

// ------------------------------------------------------------------------------------------ round trips

TEST_F(BindingIoTest, RoundTripIsIdenticalAndDeformsBitForBitForEveryVariant) {
  Scene s;
  const auto posed = posed_cage(s.cage);
  for (Variant v : kVariants) {
    SCOPED_TRACE(variant_name(v));
    BindParams p;
    p.variant = v;
    p.local = 3.0;
    p.epsilon = 0.05;
    p.max_elements = 6;
    p.close_distance = 0.75;
    Binding b = bind_or_die(s.skin, s.cage, p);
    ASSERT_TRUE(save_binding(path("b.cwb"), b).ok());
    auto loaded = load_binding(path("b.cwb"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    expect_same_binding(b, *loaded);
    EXPECT_FALSE(fs::exists(path("b.cwb.tmp"))) << "the temporary file was left behind";

    auto want = deform_or_die(b, s.skin.positions, posed);
    auto got = deform_or_die(*loaded, s.skin.positions, posed);
    EXPECT_TRUE(same_bytes(want, got)) << "deforming with the reloaded binding differs";
    EXPECT_GT(fixtures::max_distance(want, s.skin.positions), 0.1) << "the pose should move the skin";
  }
}

// Fallback points (empty sets, from edits that leave a point no element) and
// skipped elements travel through the file too.
TEST_F(BindingIoTest, RoundTripKeepsFallbackPointsAndSkippedElements) {
  Scene s;
  Cage cage = cage_with_bad_elements();
  auto posed = posed_cage(cage);
  for (Variant v : kVariants) {
    SCOPED_TRACE(variant_name(v));
    BindParams p;
    p.variant = v;
    const auto edits = fixtures::empty_set_edits(s.skin.num_vertices(), 5);
    auto bound = bind_skin(s.skin.positions, cage, cage.polygons.positions, p, edits);
    ASSERT_TRUE(bound.ok()) << bound.error().message;
    Binding b = std::move(bound).value();
    ASSERT_FALSE(b.rigid_points.empty()) << "fixture should give some points an empty set";
    ASSERT_LT(b.rigid_points.size(), b.num_points) << "fixture should give some points a set";
    ASSERT_EQ(b.invalid_elements.size(), 3u) << "the zero-area triangle and the two halves of the copied quad";
    ASSERT_TRUE(save_binding(path("b.cwb"), b).ok());
    auto loaded = load_binding(path("b.cwb"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    expect_same_binding(b, *loaded);
    EXPECT_TRUE(same_bytes(deform_or_die(b, s.skin.positions, posed), deform_or_die(*loaded, s.skin.positions, posed)));
  }
}

TEST_F(BindingIoTest, FileFollowsTheDocumentedLayout) {
  Scene s;
  BindParams p;
  p.variant = Variant::kClamped;
  p.epsilon = 0.125;
  Binding b = bind_or_die(s.skin, s.cage, p);
  auto bytes = saved(b);
  Layout at(b);
  ASSERT_EQ(bytes.size(), at.end);
  EXPECT_EQ(std::string(bytes.data(), 8), "CWBIND01");
  EXPECT_EQ(peek<uint32_t>(bytes, Layout::kVersion), 2u);
  EXPECT_EQ(peek<double>(bytes, Layout::kEpsilon), 0.125);
  EXPECT_EQ(peek<uint8_t>(bytes, Layout::kVariant), static_cast<uint8_t>(Variant::kClamped));
  EXPECT_EQ(peek<uint32_t>(bytes, Layout::kNumPoints), s.skin.num_vertices());
  EXPECT_EQ(peek<uint64_t>(bytes, at.offsets), s.skin.num_vertices() + 1);
  EXPECT_EQ(peek<uint64_t>(bytes, at.bary), 2 * b.ids.size());
}

TEST_F(BindingIoTest, SavingOverAnExistingFileReplacesIt) {
  Scene s;
  BindParams p;
  p.variant = Variant::kBasic;
  Binding basic = bind_or_die(s.skin, s.cage, p);
  p.variant = Variant::kExtended;
  Binding extended = bind_or_die(s.skin, s.cage, p);
  ASSERT_TRUE(save_binding(path("b.cwb"), extended).ok());
  ASSERT_TRUE(save_binding(path("b.cwb"), basic).ok());
  auto loaded = load_binding(path("b.cwb"));
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  expect_same_binding(basic, *loaded);
}

// ------------------------------------------------------------------------------------------ bad files

TEST_F(BindingIoTest, MissingFileIsNamed) {
  const std::string p = path("nope.cwb");
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kFileNotFound, {p}));
}

TEST_F(BindingIoTest, EmptyFileIsNamed) {
  const std::string p = write("empty.cwb", {});
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kEmpty, {p}));
}

TEST_F(BindingIoTest, SaveIntoMissingFolderIsAWriteErrorNamingThePath) {
  Scene s;
  Binding b = bind_or_die(s.skin, s.cage, BindParams{});
  const std::string p = path("no/such/folder/b.cwb");
  EXPECT_TRUE(Fails(save_binding(p, b), ErrorCode::kWrite, {p}));
}

TEST_F(BindingIoTest, WrongMagicIsNamed) {
  Scene s;
  auto bytes = saved(bind_or_die(s.skin, s.cage, BindParams{}));
  for (size_t i : {0u, 5u, 7u}) {
    auto bad = bytes;
    bad[i] ^= 0x20;
    const std::string p = write("magic.cwb", bad);
    EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kParse, {p, "magic"})) << "byte " << i;
  }
  // a mesh is not a binding
  std::vector<char> obj_text;
  for (char c : std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")) obj_text.push_back(c);
  const std::string p = write("mesh.cwb", obj_text);
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kParse, {p}));
}

// Version 1 (no set table, no separation fields) still loads: the same stencil, separation off, and
// an extended binding without its sets says so (has_sets() is false). The separate table of an
// extended binding and the separation report round-trip in version 2.
TEST_F(BindingIoTest, VersionOneStillLoadsAndVersionTwoKeepsTheSets) {
  Scene s;
  BindParams p;
  p.variant = Variant::kExtended;
  Binding b = bind_or_die(s.skin, s.cage, p);
  ASSERT_TRUE(b.has_sets());
  auto bytes = saved(b);
  Layout at(b);
  ASSERT_EQ(bytes.size(), at.end);
  EXPECT_EQ(peek<uint64_t>(bytes, at.set_offsets), s.skin.num_vertices() + 1);
  const std::string p2 = write("v2.cwb", bytes);
  auto back = load_binding(p2);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->set_offsets, b.set_offsets);
  EXPECT_EQ(back->set_ids, b.set_ids);
  EXPECT_EQ(back->set_weights, b.set_weights);
  EXPECT_EQ(back->params, b.params);
  std::vector<char> v1(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(at.separate));
  poke<uint32_t>(v1, Layout::kVersion, 1);
  const std::string p1 = write("v1.cwb", v1);
  auto old = load_binding(p1);
  ASSERT_TRUE(old.ok()) << old.error().message;
  EXPECT_EQ(old->ids, b.ids);
  EXPECT_EQ(old->weights, b.weights);
  EXPECT_FALSE(old->params.separate);
  EXPECT_FALSE(old->has_sets());
  // a set table that does not fit the points is named
  Binding bad = b;
  bad.set_offsets.pop_back();
  const std::string pb = write("badsets.cwb", saved(bad));
  EXPECT_TRUE(Fails(load_binding(pb), ErrorCode::kParse, {pb, "set table"}));
}

TEST_F(BindingIoTest, OtherVersionIsNamed) {
  Scene s;
  auto bytes = saved(bind_or_die(s.skin, s.cage, BindParams{}));
  for (uint32_t version : {0u, 4u, 0x01000000u}) {
    auto bad = bytes;
    poke(bad, Layout::kVersion, version);
    const std::string p = write("version.cwb", bad);
    EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kVersion, {p, "version " + std::to_string(version)}));
  }
}

// Prefixes of a file that has all ten tables non-empty: every length through the header and the first
// table counts, every table boundary and the bytes either side of it, and a stride through the data.
// Each must fail cleanly with kEmpty/kParse naming the file, never crash.
TEST_F(BindingIoTest, EveryTruncationFailsCleanly) {
  Scene s;
  BindParams p;
  p.variant = Variant::kClamped;
  p.max_distance = 0.6;
  Binding b = bind_or_die(s.skin, cage_with_bad_elements(), p, fixtures::empty_set_edits(s.skin.num_vertices(), 5));
  ASSERT_FALSE(b.rigid_points.empty());
  ASSERT_FALSE(b.bary.empty());
  auto bytes = saved(b);
  ASSERT_GT(bytes.size(), 1000u);
  Layout at(b);
  std::set<size_t> lengths;
  for (size_t len = 0; len < 160; ++len) lengths.insert(len);
  for (size_t len = 160; len < bytes.size(); len += 37) lengths.insert(len);
  for (size_t table : {at.rest_cage, at.elements, at.element_status, at.offsets, at.ids, at.weights, at.bary,
                       at.rigid_points, at.rigid_element, at.rigid_bary, at.end - 16})
    for (size_t len : {table - 1, table, table + 1, table + 7, table + 8, table + 9}) lengths.insert(len);
  for (size_t back = 1; back <= 17; ++back) lengths.insert(bytes.size() - back);
  const std::string name = path("cut.cwb");
  size_t failures = 0;
  for (size_t len : lengths) {
    if (len >= bytes.size()) continue;
    write("cut.cwb", bytes, len);
    auto r = load_binding(name);
    const ErrorCode want = len == 0 ? ErrorCode::kEmpty : ErrorCode::kParse;
    auto check = Fails(r, want, {name});
    if (!check && ++failures <= 5) ADD_FAILURE() << "cut at " << len << " of " << bytes.size() << ": " << check.message();
  }
  EXPECT_EQ(failures, 0u);
  // and one byte too many
  auto longer = bytes;
  longer.push_back('\0');
  const std::string p2 = write("long.cwb", longer);
  EXPECT_TRUE(Fails(load_binding(p2), ErrorCode::kParse, {p2}));
}

// A count larger than the file must be rejected before anything is allocated (2^62 entries would
// throw or exhaust memory).
TEST_F(BindingIoTest, InflatedTableCountsFailWithoutAllocating) {
  Scene s;
  BindParams p;
  p.variant = Variant::kClamped;
  p.max_distance = 0.6;
  Binding b = bind_or_die(s.skin, cage_with_bad_elements(), p, fixtures::empty_set_edits(s.skin.num_vertices(), 5));
  auto bytes = saved(b);
  Layout at(b);
  const std::pair<const char*, size_t> tables[] = {
      {"rest_cage", at.rest_cage}, {"elements", at.elements}, {"element_status", at.element_status},
      {"offsets", at.offsets},     {"ids", at.ids},           {"weights", at.weights},
      {"bary", at.bary},           {"rigid_points", at.rigid_points}, {"rigid_element", at.rigid_element},
      {"rigid_bary", at.rigid_bary}};
  for (const auto& [table, offset] : tables) {
    const uint64_t count = peek<uint64_t>(bytes, offset);
    for (uint64_t inflated : {count + 1, uint64_t(1) << 32, uint64_t(1) << 62, std::numeric_limits<uint64_t>::max(),
                              std::numeric_limits<uint64_t>::max() / 4 + 1}) {
      auto bad = bytes;
      poke(bad, offset, inflated);
      const std::string f = write("count.cwb", bad);
      EXPECT_TRUE(Fails(load_binding(f), ErrorCode::kParse, {f})) << table << " count " << inflated;
    }
  }
}

// The message names the table and both sizes, grouped by thousands; a huge header count is named the
// same way, against the table it must match (issue 19).
TEST_F(BindingIoTest, HugeCountsNameTheTableAndBothNumbers) {
  Scene s;
  Binding b = bind_or_die(s.skin, s.cage, BindParams{});
  auto bytes = saved(b);
  Layout at(b);
  const size_t left = bytes.size() - at.ids - 8;  // after the ids count
  auto bad = bytes;
  poke<uint64_t>(bad, at.ids, 1000000000);
  const std::string ids = write("ids.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(ids), ErrorCode::kParse,
                    {ids, "table ids claims 1,000,000,000 entries of 4 bytes (4,000,000,000 bytes) but " +
                              group_digits(left) + " bytes are left in the file"}));
  bad = bytes;
  poke<uint64_t>(bad, at.set_weights, uint64_t(1) << 63);
  const std::string weights = write("set_weights.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(weights), ErrorCode::kParse,
                    {weights, "table set_weights claims 9,223,372,036,854,775,808 entries of 4 bytes "
                              "(36,893,488,147,419,103,232 bytes)"}));
  bad = bytes;
  poke<uint32_t>(bad, Layout::kNumPoints, 4000000000u);
  const std::string points = write("points.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(points), ErrorCode::kParse,
                    {points, "(" + std::to_string(b.offsets.size()) + " offsets for 4,000,000,000 points)"}));
}

TEST_F(BindingIoTest, NonMonotoneOffsetsAreRejected) {
  Scene s;
  Binding b = bind_or_die(s.skin, s.cage, BindParams{});
  auto bytes = saved(b);
  Layout at(b);
  const size_t data = at.offsets + 8;
  ASSERT_GT(b.offsets[2], 0u);
  auto bad = bytes;
  poke<uint32_t>(bad, data + 4 * 1, b.offsets[2] + 1);  // offsets[1] > offsets[2]
  const std::string p = write("offsets.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kParse, {p, "monotone"}));

  bad = bytes;
  poke<uint32_t>(bad, data, 1);  // must start at 0
  const std::string q = write("offsets0.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(q), ErrorCode::kParse, {q, "offset"}));
}

TEST_F(BindingIoTest, OffsetTableOfTheWrongLengthIsRejected) {
  Scene s;
  Binding b = bind_or_die(s.skin, s.cage, BindParams{});
  auto bytes = saved(b);
  auto bad = bytes;
  poke<uint32_t>(bad, Layout::kNumPoints, b.num_points + 1);
  const std::string p = write("points.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kParse, {p, "point count"}));
}

TEST_F(BindingIoTest, UnknownVariantStatusOrBadParameterIsRejected) {
  Scene s;
  Binding b = bind_or_die(s.skin, s.cage, BindParams{});
  auto bytes = saved(b);
  Layout at(b);

  auto bad = bytes;
  poke<uint8_t>(bad, Layout::kVariant, 7);
  std::string p = write("variant.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kParse, {p, "variant 7"}));

  bad = bytes;
  poke<uint8_t>(bad, at.element_status + 8 + 3, 9);
  p = write("status.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kParse, {p, "status"}));

  bad = bytes;
  poke<double>(bad, Layout::kEpsilon, 0.0);
  p = write("epsilon.cwb", bad);
  EXPECT_TRUE(Fails(load_binding(p), ErrorCode::kParse, {p, "epsilon"}));
}

// load_binding may accept an id beyond its table (it checks structure), but the deformer must not; the
// message names the offending id.
TEST_F(BindingIoTest, OutOfRangeIdsAreRejectedByTheDeformer) {
  Scene s;
  for (Variant v : kVariants) {
    SCOPED_TRACE(variant_name(v));
    BindParams p;
    p.variant = v;
    Binding b = bind_or_die(s.skin, s.cage, p);
    auto bytes = saved(b);
    Layout at(b);
    // extended stores cage vertex ids, the others element ids
    const uint32_t limit = v == Variant::kExtended ? b.num_cage_vertices : static_cast<uint32_t>(b.elements.size());
    const size_t entry = b.offsets[40] + 1;  // some entry of point 40
    auto bad = bytes;
    poke<uint32_t>(bad, at.ids + 8 + 4 * entry, limit);
    const std::string f = write("ids.cwb", bad);
    auto loaded = load_binding(f);
    if (!loaded.ok()) {  // rejecting it already at load is fine too
      EXPECT_TRUE(RejectedAtLoad(loaded, {f, std::to_string(limit)}));
      continue;
    }
    auto d = Deformer::create(*loaded, s.skin.positions);
    EXPECT_TRUE(Fails(d, ErrorCode::kIndexOutOfRange, {std::to_string(limit)}));
  }
}

// A corner of an element beyond the cage, a fallback element beyond the elements, a fallback point beyond
// the skin: rejected (at load or by the deformer) with the offending index in the message.
TEST_F(BindingIoTest, OutOfRangeCageVertexOrFallbackIsRejectedByTheDeformer) {
  Scene s;
  BindParams p;
  p.variant = Variant::kBasic;
  p.max_distance = 0.6;
  Binding b = bind_or_die(s.skin, s.cage, p, fixtures::empty_set_edits(s.skin.num_vertices(), 5));
  ASSERT_FALSE(b.rigid_points.empty());
  auto bytes = saved(b);
  Layout at(b);
  struct Damage {
    const char* what;
    size_t offset;
    uint32_t value;
  };
  const Damage damages[] = {
      {"element 2 corner 1", at.elements + 8 + 4 * 7, b.num_cage_vertices + 5},
      {"fallback element", at.rigid_element + 8, static_cast<uint32_t>(b.elements.size())},
      {"fallback point", at.rigid_points + 8, b.num_points},
  };
  for (const Damage& d : damages) {
    SCOPED_TRACE(d.what);
    auto bad = bytes;
    poke<uint32_t>(bad, d.offset, d.value);
    const std::string f = write("damaged.cwb", bad);
    auto loaded = load_binding(f);
    if (loaded.ok()) {
      EXPECT_TRUE(Fails(Deformer::create(*loaded, s.skin.positions), ErrorCode::kIndexOutOfRange,
                        {std::to_string(d.value)}));
    } else {
      EXPECT_TRUE(RejectedAtLoad(loaded, {f, std::to_string(d.value)}));
    }
  }
}

// ------------------------------------------------------------------------------------------ deformer checks

TEST(BindingDeformerChecks, SkinOfTheWrongSizeNamesBothCounts) {
  Scene s;
  Binding b = bind_or_die(s.skin, s.cage, BindParams{});
  const size_t n = s.skin.num_vertices();
  std::vector<glm::vec3> fewer(s.skin.positions.begin(), s.skin.positions.end() - 1);
  EXPECT_TRUE(Fails(Deformer::create(b, fewer), ErrorCode::kTopologyMismatch,
                    {std::to_string(n), std::to_string(n - 1)}));
  std::vector<glm::vec3> more = s.skin.positions;
  more.resize(n + 13, glm::vec3(0.f));
  EXPECT_TRUE(Fails(Deformer::create(b, more), ErrorCode::kTopologyMismatch,
                    {std::to_string(n), std::to_string(n + 13)}));
}

TEST(BindingDeformerChecks, PosedCageWithOtherVertexCountNamesBothCounts) {
  Scene s;
  for (Variant v : kVariants) {
    BindParams p;
    p.variant = v;
    Binding b = bind_or_die(s.skin, s.cage, p);
    auto d = Deformer::create(b, s.skin.positions);
    ASSERT_TRUE(d.ok()) << d.error().message;
    std::vector<glm::vec3> out(s.skin.num_vertices());
    auto cage = s.cage.polygons.positions;  // 26 vertices
    auto shorter = std::vector<glm::vec3>(cage.begin(), cage.end() - 2);
    EXPECT_TRUE(Fails(d->deform(shorter, out), ErrorCode::kTopologyMismatch, {"24", "26"})) << variant_name(v);
    auto longer = cage;
    longer.push_back(glm::vec3(0.f));
    EXPECT_TRUE(Fails(d->deform(longer, out), ErrorCode::kTopologyMismatch, {"27", "26"})) << variant_name(v);
  }
}

TEST(BindingDeformerChecks, NonFinitePosedVertexIsNamed) {
  Scene s;
  for (Variant v : kVariants) {
    BindParams p;
    p.variant = v;
    Binding b = bind_or_die(s.skin, s.cage, p);
    auto d = Deformer::create(b, s.skin.positions);
    ASSERT_TRUE(d.ok()) << d.error().message;
    std::vector<glm::vec3> out(s.skin.num_vertices());
    for (float bad : {NAN, INFINITY, -INFINITY}) {
      auto posed = s.cage.polygons.positions;
      posed[17].z = bad;
      EXPECT_TRUE(Fails(d->deform(posed, out), ErrorCode::kNonFinite, {"vertex 17"})) << variant_name(v);
      EXPECT_TRUE(Fails(d->check_cage(posed), ErrorCode::kNonFinite, {"vertex 17"})) << variant_name(v);
    }
    // the deformer still works after rejecting a cage
    EXPECT_TRUE(d->deform(s.cage.polygons.positions, out).ok());
    EXPECT_LE(fixtures::max_distance(out, s.skin.positions), 1e-5);
  }
}

TEST(BindingDeformerChecks, OutputOfTheWrongSizeIsAnInvalidArgument) {
  Scene s;
  Binding b = bind_or_die(s.skin, s.cage, BindParams{});
  auto d = Deformer::create(b, s.skin.positions);
  ASSERT_TRUE(d.ok()) << d.error().message;
  const size_t n = s.skin.num_vertices();
  for (size_t size : {size_t(0), n - 1, n + 1}) {
    std::vector<glm::vec3> out(size, glm::vec3(-7.f));
    EXPECT_TRUE(Fails(d->deform(s.cage.polygons.positions, out), ErrorCode::kInvalidArgument,
                      {std::to_string(size), std::to_string(n)}));
    for (const auto& q : out) EXPECT_EQ(q, glm::vec3(-7.f)) << "a rejected call wrote to the output";
  }
}

}  // namespace
}  // namespace cagewrap
