// Operation counters in the spirit of pbrt's statistics: every hot path reports its work into a
// named 64-bit counter. Each thread (or tile task) owns an OpCounters and the totals are summed at
// the end; integer sums do not depend on how work was split, so totals are identical for any
// thread count. Counters are declared where the work happens:
//
//   inline const pcrt::Counter kLeavesVisited{"leaves_visited", "leaves handed to a method"};
//   ...
//   counters.add(kLeavesVisited);
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <string>

namespace pcrt {

inline constexpr size_t kMaxCounters = 128;

class Counter {
 public:
  Counter(const char* name, const char* description);
  [[nodiscard]] uint32_t id() const { return id_; }

 private:
  uint32_t id_;
};

struct CounterInfo {
  std::string name;
  std::string description;
};
// Every counter registered in this binary, indexed by id.
const std::array<CounterInfo, kMaxCounters>& registered_counters();
size_t registered_counter_count();

class OpCounters {
 public:
  void add(const Counter& c, uint64_t n = 1) {
#ifndef PCRT_NO_COUNTERS
    values_[c.id()] += n;
#else
    (void)c, (void)n;  // a build that measures what counting costs (PCRT_COUNTERS=OFF)
#endif
  }
  [[nodiscard]] uint64_t get(const Counter& c) const { return values_[c.id()]; }
  void merge(const OpCounters& other) {
    for (size_t i = 0; i < kMaxCounters; ++i) values_[i] += other.values_[i];
  }
  // Name -> value for every counter that is non-zero (sorted by name, for stable output).
  [[nodiscard]] std::map<std::string, uint64_t> to_map() const;

 private:
  std::array<uint64_t, kMaxCounters> values_{};
};

// Wall-clock seconds per named phase (prepare, build, render, ...).
using Timings = std::map<std::string, double>;

class ScopedTimer {
 public:
  ScopedTimer(Timings& t, std::string phase)
      : timings_(t), phase_(std::move(phase)), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    timings_[phase_] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  Timings& timings_;
  std::string phase_;
  std::chrono::steady_clock::time_point start_;
};

// Counters of the renderer and the generic tracing loop.
inline const Counter kRaysCast{"rays_cast", "rays traced (primary, bounce and shadow)"};
inline const Counter kPrimaryRays{"primary_rays", "camera rays"};
inline const Counter kBounceRays{"bounce_rays", "secondary rays sampled from the BRDF"};
inline const Counter kShadowRays{"shadow_rays", "rays towards the point light"};
inline const Counter kRayHits{"ray_hits", "rays that found a closest hit"};
inline const Counter kAnyHitRays{"any_hit_rays",
                                 "occlusion queries (shadow rays; also in rays_cast): any hit "
                                 "ends them"};
inline const Counter kRaysOccluded{"rays_occluded", "occlusion queries that found a blocker"};

}  // namespace pcrt
