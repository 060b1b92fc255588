// How this pcrt was built, recorded in every sweep's context.json. The values are compiled into
// one translation unit only (build_info.cpp), so that the rest of the code does not depend on
// where the source tree lies (and a compiler cache can share it between checkouts).
#pragma once

#include <optional>
#include <string>

namespace pcrt {

struct BuildInfo {
  std::string compiler;      // "GNU 12.2.0"
  std::string flags;         // CMAKE_CXX_FLAGS plus the build type's flags
  std::string build_type;    // "Release", ...
  std::string dependencies;  // the versions CMake found
  std::string source_dir;    // the source tree (scripts/, git revision)
};

const BuildInfo& build_info();

// The commit this binary was built from and whether tracked files differed from it (nullopt when
// git could not tell; commit "unknown" without git), generated at every build
// (cmake/build_revision.cmake). Results record it beside the source tree's revision at run time.
struct BuildRevision {
  std::string commit;
  std::optional<bool> dirty;
};
const BuildRevision& build_revision();

// A script pcrt runs (report.py): in the source tree it was built from, else where
// `cmake --install` put it (<prefix>/share/pcrt, beside <prefix>/bin/pcrt). Throws InputError
// naming both places when neither has it.
std::string installed_script(const std::string& name);

}  // namespace pcrt
