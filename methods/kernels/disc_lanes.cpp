#include "methods/kernels/disc_lanes.hpp"

#include <cstdlib>

#include "methods/kernels/projection_lanes.hpp"

namespace pcrt {

#ifdef PCRT_AVX2
void disc_candidates_avx2(const DiscBlock* blocks, uint32_t first, uint32_t count,
                          const DiscQuery& q, uint64_t* word);
void projection_candidates_avx2(const float* records, const uint32_t* items, uint32_t count,
                                const ProjectionQuery& q, uint64_t* word);
#endif

namespace {

// One lane type for both kernels, so that the results' leaf_simd names what ran.
struct Choice {
  DiscKernel kernel;
  ProjectionKernel projection;
  const char* name;
};

// PCRT_DISC_LANES=scalar forces the scalar lanes (to measure what the wide ones gain).
Choice choose() {
#ifdef PCRT_AVX2
  const char* env = std::getenv("PCRT_DISC_LANES");
  const bool scalar = env && env[0] == 's';
  __builtin_cpu_init();
  if (!scalar && __builtin_cpu_supports("avx2"))
    return {disc_candidates_avx2, projection_candidates_avx2, "avx2x8"};
#endif
  return {disc_candidates<Lane1>, projection_candidates<Lane1>, "scalar"};
}

const Choice& choice() {
  static const Choice c = choose();
  return c;
}

}  // namespace

DiscKernel best_disc_kernel() { return choice().kernel; }

ProjectionKernel best_projection_kernel() { return choice().projection; }

const char* disc_lanes_name() { return choice().name; }

}  // namespace pcrt
