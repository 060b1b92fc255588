#include "harness/build_info.hpp"

namespace pcrt {

const BuildInfo& build_info() {
  static const BuildInfo info{std::string(PCRT_COMPILER_ID) + " " + PCRT_COMPILER_VERSION,
                              PCRT_CXX_FLAGS, PCRT_BUILD_TYPE, PCRT_DEPENDENCY_VERSIONS,
                              PCRT_SOURCE_DIR};
  return info;
}

}  // namespace pcrt
