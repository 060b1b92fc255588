#include "structures/wide_node.hpp"

namespace pcrt {

bool wide_nodes_use_avx2() {
  static const bool avx2 = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return avx2;
}

}  // namespace pcrt
