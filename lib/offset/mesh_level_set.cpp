#include "offset/mesh_level_set.h"

#include <sys/mman.h>

#include <cstddef>
#include <memory>
#include <new>

// Reproducible meshes: CGAL's surface mesher orders cells by handle, i.e. by memory address, so its
// output depended on malloc's history (it differed between runs when levels meshed in parallel).
// Every CGAL container of this translation unit therefore allocates from a monotone bump arena in
// one reserved address range per mesher call: address order is allocation order, which is
// deterministic. (CGAL_ALLOCATOR only sets template defaults, so these are distinct types.)
namespace cdbench::detail {

struct MesherArena {
  char* base = nullptr;
  std::size_t size = 0, used = 0;
};
inline thread_local MesherArena* current_mesher_arena = nullptr;

template <class T>
struct MesherAllocator {
  using value_type = T;
  MesherAllocator() noexcept = default;
  template <class U>
  MesherAllocator(const MesherAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    MesherArena* a = current_mesher_arena;
    if (a == nullptr) return std::allocator<T>().allocate(n);
    constexpr std::size_t align = alignof(std::max_align_t) > alignof(T) ? alignof(std::max_align_t) : alignof(T);
    const std::size_t start = (a->used + align - 1) / align * align;
    if (n > (a->size - start) / sizeof(T)) throw std::bad_alloc();
    a->used = start + n * sizeof(T);
    return reinterpret_cast<T*>(a->base + start);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    MesherArena* a = current_mesher_arena;
    const char* c = reinterpret_cast<const char*>(p);
    if (a != nullptr && c >= a->base && c < a->base + a->size) return;  // released with the arena
    std::allocator<T>().deallocate(p, n);
  }
  template <class U>
  bool operator==(const MesherAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const MesherAllocator<U>&) const noexcept { return false; }
};

// Reserves address space (not memory) for one mesher call and makes it current on this thread.
class ArenaScope {
 public:
  ArenaScope() {
    arena_.size = std::size_t{1} << 37;  // 128 GiB of addresses; only touched pages cost memory
    void* p = mmap(nullptr, arena_.size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    arena_.base = static_cast<char*>(p);
    previous_ = current_mesher_arena;
    current_mesher_arena = &arena_;
  }
  ~ArenaScope() {
    current_mesher_arena = previous_;
    munmap(arena_.base, arena_.size);
  }
  ArenaScope(const ArenaScope&) = delete;
  ArenaScope& operator=(const ArenaScope&) = delete;

 private:
  MesherArena arena_;
  MesherArena* previous_ = nullptr;
};

}  // namespace cdbench::detail

#define CGAL_ALLOCATOR(T) cdbench::detail::MesherAllocator<T>

#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>

#include <algorithm>
#include <cmath>

#include "mesh/cgal_surface_mesh.h"
#include "offset/level_set_evaluator.h"

namespace cdbench {
namespace {

using detail::Evaluator;

using Tr = CGAL::Surface_mesh_default_triangulation_3;
using C2t3 = CGAL::Complex_2_in_triangulation_3<Tr>;
using GT = Tr::Geom_traits;
using Point = GT::Point_3;
using FT = GT::FT;

struct Function {
  Evaluator* evaluator;
  FT operator()(const Point& p) const { return (*evaluator)(Vec3(p.x(), p.y(), p.z())); }
};

}  // namespace

std::vector<Vec3> level_set_seeds(const std::function<double(const Vec3&)>& f, const Vec3& center, double radius,
                                  int count) {
  std::vector<Vec3> seeds;
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / count, phi = k * golden_angle;
    const Vec3 dir(std::sqrt(1.0 - z * z) * std::cos(phi), std::sqrt(1.0 - z * z) * std::sin(phi), z);
    double lo = 0.0, hi = radius;
    if (!(f(center + hi * dir) > 0.0)) continue;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;  // adjacent doubles: as close as doubles get
      (f(center + mid * dir) < 0.0 ? lo : hi) = mid;
    }
    seeds.push_back(center + hi * dir);
  }
  return seeds;
}

TriangleMesh mesh_level_set(const std::function<double(const Vec3&)>& f, const Vec3& center, double radius,
                            const std::vector<Vec3>& seeds, const LevelSetMeshOptions& options,
                            LevelSetMeshStats* stats) {
  detail::ArenaScope arena;  // declared first: every CGAL object below is gone before it is unmapped
  Tr tr;
  C2t3 c2t3(tr);
  const std::vector<Vec3> kept = detail::distinct_seeds(seeds, options.distance_bound);
  for (const Vec3& s : kept) tr.insert(Point(s.x(), s.y(), s.z()));
  Evaluator evaluator(f, options.lipschitz, 1e-9 * radius);
  CGAL::Implicit_surface_3<GT, Function> surface(Function{&evaluator}, GT::Sphere_3(Point(center.x(), center.y(), center.z()),
                                                                             radius * radius),
                                                 options.bisection_relative_error);
  CGAL::Surface_mesh_default_criteria_3<Tr> criteria(options.angle_bound, options.radius_bound,
                                                     options.distance_bound);
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag(), 0);
  CGAL::Surface_mesh<Point> sm;
  if (c2t3.number_of_facets() > 0) CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, sm);
  if (stats != nullptr) *stats = evaluator.stats;
  return triangle_mesh_from(sm);
}

}  // namespace cdbench
