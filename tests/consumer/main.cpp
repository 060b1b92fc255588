// A program of one's own on an installed pcrt: a generated sphere, two surveyed methods, rays from
// outside aimed at the centre. Fails (exit 1) unless every method is listed and every ray hits
// the unit sphere near radius 1.
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/dataset.hpp"
#include "methods/method.hpp"
#include "render/scene.hpp"

int main() {
  using namespace pcrt;
  if (MethodRegistry::instance().all().size() < 16) {
    std::fprintf(stderr, "consumer: only %zu methods registered\n",
                 MethodRegistry::instance().all().size());
    return 1;
  }
  const Dataset data = load_dataset("sphere:n=20000,seed=3");
  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i) {
    const float a = 0.1f * float(i), z = -0.9f + 1.8f * float(i) / 63.0f;
    Ray r;
    r.o =
        Vec3(3 * std::cos(a) * std::sqrt(1 - z * z), 3 * std::sin(a) * std::sqrt(1 - z * z), 3 * z);
    r.d = -r.o.normalized();
    rays.push_back(r);
  }
  for (const char* method : {"goradia_2010", "adamson_alexa_2003"}) {
    OpCounters counters;
    Timings timings;
    const PointScene scene(data.cloud, {method, "octree", {}}, counters, timings);
    std::vector<Hit> hits(rays.size());
    std::vector<char> found(rays.size());
    trace_rays(scene, rays, hits, found);
    for (size_t i = 0; i < rays.size(); ++i) {
      const float radius = rays[i].at(hits[i].t).norm();
      if (!found[i] || std::abs(radius - 1) > 0.02f) {
        std::fprintf(stderr, "consumer: %s ray %zu: hit %d at radius %g\n", method, i, found[i],
                     double(radius));
        return 1;
      }
    }
    std::printf("consumer: %s on octree: %zu of %zu rays hit the unit sphere\n", method,
                rays.size(), rays.size());
  }
  return 0;
}
