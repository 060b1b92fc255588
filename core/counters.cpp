#include "core/counters.hpp"

#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace pcrt {
namespace {

struct Registry {
  std::mutex mutex;
  std::array<CounterInfo, kMaxCounters> infos;
  size_t count = 0;
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

Counter::Counter(const char* name, const char* description) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  for (size_t i = 0; i < r.count; ++i) {
    if (r.infos[i].name == name) {  // the same inline counter seen from two translation units
      id_ = static_cast<uint32_t>(i);
      return;
    }
  }
  if (r.count == kMaxCounters) {
    std::fprintf(stderr, "pcrt: more than %zu counters registered; raise kMaxCounters\n",
                 kMaxCounters);
    std::abort();
  }
  id_ = static_cast<uint32_t>(r.count);
  r.infos[r.count++] = CounterInfo{name, description};
}

const std::array<CounterInfo, kMaxCounters>& registered_counters() { return registry().infos; }
size_t registered_counter_count() { return registry().count; }

std::map<std::string, uint64_t> OpCounters::to_map() const {
  std::map<std::string, uint64_t> m;
  const auto& infos = registered_counters();
  for (size_t i = 0; i < registered_counter_count(); ++i)
    if (values_[i] != 0) m[infos[i].name] = values_[i];
  return m;
}

}  // namespace pcrt
