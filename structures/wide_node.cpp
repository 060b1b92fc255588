#include "structures/wide_node.hpp"

#include <cstdlib>
#include <string_view>

namespace pcrt {

// PCRT_NODE_LANES=sse forces the SSE node tests on an AVX2 CPU: the walks CPUs without AVX2 run,
// which the op-count gate checks give the same counts (scripts/test.sh).
bool wide_nodes_use_avx2() {
  static const bool avx2 = [] {
    const char* env = std::getenv("PCRT_NODE_LANES");
    if (env && std::string_view(env) == "sse") return false;
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return avx2;
}

}  // namespace pcrt
