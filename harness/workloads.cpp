#include "harness/workloads.hpp"

#include <algorithm>
#include <atomic>
#include <ctime>
#include <unordered_set>

#include "core/error.hpp"
#include "core/rng.hpp"

namespace pcrt {
namespace {

constexpr size_t kLookups =
    1 << 16;  // fixed number of queries per run for the per-lookup workloads

std::vector<uint64_t> random_keys(size_t n, uint64_t seed) {
  Rng rng(seed, 77);
  std::vector<uint64_t> v(n);
  for (auto& x : v) x = (uint64_t(rng.next_u32()) << 32) | rng.next_u32();
  return v;
}

}  // namespace

const std::vector<WorkloadInfo>& workloads() {
  static const std::vector<WorkloadInfo> list = {
      {"sort",
       Growth::kLinearLog,
       "O(N log N)",
       {1 << 8, 1 << 9, 1 << 10, 1 << 11, 1 << 12, 1 << 13, 1 << 14, 1 << 15, 1 << 16, 1 << 17}},
      {"nth_element",
       Growth::kLinear,
       "O(N)",
       {1 << 8, 1 << 9, 1 << 10, 1 << 11, 1 << 12, 1 << 13, 1 << 14, 1 << 15, 1 << 16, 1 << 17}},
      // Up to 2^16 keys (512 KB): cache resident, so time counts comparisons and not the memory
      // hierarchy (at 2^20 keys the misses make time grow like N^0.2, which the fitter rightly
      // calls x^0.5 rather than log x).
      {"binary_search",
       Growth::kLog,
       "O(log N)",
       {1 << 4, 1 << 6, 1 << 8, 1 << 10, 1 << 12, 1 << 14, 1 << 16}},
      {"triple_loop", Growth::kCubic, "O(N^3)", {24, 32, 48, 64, 96, 128, 160}},
      {"hash_lookup",
       Growth::kConstant,
       "O(1)",
       {1 << 4, 1 << 5, 1 << 6, 1 << 7, 1 << 8, 1 << 9, 1 << 10}},
  };
  return list;
}

namespace {

// The calibrating thread's CPU time, not wall time: the workloads run on one thread, and on a
// loaded machine the time the scheduler gives others lands in wall time, at random sizes, which
// bent the time fits (a pause in a 2 ms run doubles it; the model penalty then decides).
struct Clock {
  using time_point = double;
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  }
};

double seconds_since(Clock::time_point start) { return Clock::now() - start; }

// One timed run of a workload: its counted operations and seconds over `batch` instances.
struct WorkloadRun {
  uint64_t ops = 0;
  double seconds = 0;
  size_t batch = 1;  // independent instances per run; time and operations are per instance
};

// sort and nth_element: enough instances for about 2^18 elements in all, generated before the
// clock starts, so a run lasts milliseconds whatever N and every instance comes from the same
// cache level.
WorkloadRun run_selection(bool full_sort, size_t n, uint64_t seed) {
  WorkloadRun r;
  r.batch = std::max<size_t>(1, (size_t(1) << 18) / n);
  std::vector<std::vector<uint64_t>> inputs;
  for (size_t b = 0; b < r.batch; ++b) inputs.push_back(random_keys(n, seed + b));
  auto less = [&r](uint64_t a, uint64_t b) { return ++r.ops, a < b; };
  const auto start = Clock::now();
  for (auto& v : inputs) {
    if (full_sort)
      std::sort(v.begin(), v.end(), less);
    else
      std::nth_element(v.begin(), v.begin() + long(n / 2), v.end(), less);
  }
  r.seconds = seconds_since(start);
  return r;
}

WorkloadRun run_binary_search(size_t n, uint64_t seed) {
  WorkloadRun r;
  std::vector<uint64_t> v = random_keys(n, seed);
  std::sort(v.begin(), v.end());
  const std::vector<uint64_t> q = random_keys(kLookups, seed + 1);
  auto less = [&r](uint64_t a, uint64_t b) { return ++r.ops, a < b; };
  uint64_t found = 0;
  const auto start = Clock::now();
  for (uint64_t k : q) found += uint64_t(std::lower_bound(v.begin(), v.end(), k, less) - v.begin());
  r.seconds = seconds_since(start);
  static std::atomic<uint64_t> sink;  // keeps the lookups from being optimised away
  sink.store(found, std::memory_order_relaxed);
  return r;
}

WorkloadRun run_triple_loop(size_t n) {
  WorkloadRun r;
  std::vector<double> a(n * n, 1.0), b(n * n, 0.5), c(n * n, 0.0);
  const auto start = Clock::now();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      double s = 0;
      for (size_t k = 0; k < n; ++k) s += a[i * n + k] * b[k * n + j];
      c[i * n + j] = s;
    }
  r.seconds = seconds_since(start);
  r.ops = uint64_t(n) * n * n;
  if (c[0] != 0.5 * double(n)) input_error("triple_loop: wrong product");
  return r;
}

WorkloadRun run_hash_lookup(size_t n, uint64_t seed) {
  WorkloadRun r;
  const std::vector<uint64_t> v = random_keys(n, seed);
  struct Eq {
    uint64_t* ops;
    bool operator()(uint64_t a, uint64_t b) const { return ++*ops, a == b; }
  };
  std::unordered_set<uint64_t, std::hash<uint64_t>, Eq> set(v.begin(), v.end(), n,
                                                            std::hash<uint64_t>(), Eq{&r.ops});
  r.ops = 0;  // only the lookups count
  size_t hits = 0;
  const auto start = Clock::now();
  for (size_t i = 0; i < kLookups; ++i) hits += set.count(v[(i * 7919) % n]);
  r.seconds = seconds_since(start);
  if (hits != kLookups) input_error("hash_lookup: lost keys");
  return r;
}

WorkloadRun run_named(const std::string& id, size_t n, uint64_t seed) {
  if (id == "sort" || id == "nth_element") return run_selection(id == "sort", n, seed);
  if (id == "binary_search") return run_binary_search(n, seed);
  if (id == "triple_loop") return run_triple_loop(n);
  if (id == "hash_lookup") return run_hash_lookup(n, seed);
  std::string known;
  for (const auto& w : workloads()) known += (known.empty() ? "" : ", ") + w.id;
  input_error("unknown workload '{}' (known: {})", id, known);
}

}  // namespace

double run_workload(const std::string& id, size_t n, uint64_t seed, OpCounters& counters) {
  const WorkloadRun r = run_named(id, n, seed);
  counters.add(kWorkloadOperations, r.ops / r.batch);
  return r.seconds / double(r.batch);
}

}  // namespace pcrt
