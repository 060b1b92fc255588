#include "harness/build_info.hpp"

#include <filesystem>

#include "core/error.hpp"

namespace pcrt {

const BuildInfo& build_info() {
  static const BuildInfo info{std::string(PCRT_COMPILER_ID) + " " + PCRT_COMPILER_VERSION,
                              PCRT_CXX_FLAGS, PCRT_BUILD_TYPE, PCRT_DEPENDENCY_VERSIONS,
                              PCRT_SOURCE_DIR};
  return info;
}

std::string installed_script(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path in_source = fs::path(build_info().source_dir) / "scripts" / name;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path installed = exe.parent_path().parent_path() / "share" / "pcrt" / name;
  if (fs::exists(in_source, ec)) return in_source.string();
  if (!exe.empty() && fs::exists(installed, ec)) return installed.string();
  input_error("{} not found in {} or {}", name, in_source.parent_path().string(),
              installed.parent_path().string());
}

}  // namespace pcrt
