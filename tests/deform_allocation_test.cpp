// deform() validates its inputs once and then must not allocate: counted with a replaced global
// operator new (every thread) around the call.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "core/deform/deformer.h"
#include "core/deform/registration.h"
#include "tests/fixtures.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
// the nothrow forms too (std::stable_sort's buffer uses them): every new must pair with our delete
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace cagewrap {
namespace {

TEST(DeformAllocation, DeformDoesNotAllocatePerCall) {
  PolyMesh skin = fixtures::cylinder_skin(0.5, 4.0, 64, 200);  // enough points for several parallel chunks
  Cage cage = fixtures::cylinder_cage();
  auto posed = fixtures::bent(cage.polygons.positions, 2.0, 30);
  for (Variant v : {Variant::kBasic, Variant::kClamped, Variant::kExtended}) {
    BindParams p;
    p.variant = v;
    p.max_distance = 0.25;
    // some points fall back to the rigid path too
    const auto edits = fixtures::empty_set_edits(skin.num_vertices(), 13);
    Binding b = std::move(bind_skin(skin.positions, cage, cage.polygons.positions, p, edits)).value();
    ASSERT_FALSE(b.rigid_points.empty());
    Deformer d = std::move(Deformer::create(b, skin.positions)).value();
    std::vector<glm::vec3> out(skin.num_vertices());
    ASSERT_TRUE(d.deform(posed, out).ok());  // warm-up: thread pool and first touch
    g_allocations = 0;
    g_counting = true;
    for (int i = 0; i < 5; ++i) (void)d.deform(posed, out);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << variant_name(v);
  }
  // the counter works: a vector allocation inside the window is seen
  g_allocations = 0;
  g_counting = true;
  std::vector<int>* probe = new std::vector<int>(10);
  g_counting = false;
  delete probe;
  EXPECT_GE(g_allocations.load(), 2);
}

}  // namespace
}  // namespace cagewrap
