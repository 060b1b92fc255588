#include "structures/wide_node.hpp"

#include <cstdlib>
#include <string_view>

#include "core/error.hpp"

namespace pcrt {

// PCRT_NODE_LANES=sse forces the SSE node tests on an AVX2 CPU: the walks CPUs without AVX2 run,
// which the op-count gate checks give the same counts (scripts/test.sh). Any other value is
// refused: a misspelt one would run the AVX2 walks while claiming to check the SSE ones.
bool wide_nodes_use_avx2() {
  static const bool avx2 = [] {
    const char* env = std::getenv("PCRT_NODE_LANES");
    if (env && std::string_view(env) == "sse") return false;
    if (env && *env)
      input_error(
          "PCRT_NODE_LANES={}: unknown; 'sse' forces the SSE node tests, unset lets the "
          "CPU choose",
          env);
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return avx2;
}

}  // namespace pcrt
