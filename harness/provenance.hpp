// What a sweep's numbers were made on (DIR/context.json): the machine, the build (build_info),
// the source tree's revision at run time (git_commit, git_dirty), the revision the binary was
// built from (build_commit, build_dirty: the same unless an older build ran in a newer tree) and
// the config.
#pragma once

#include <nlohmann/json.hpp>

namespace pcrt {

using nlohmann::json;

json machine_context(const json& config);
// The source tree's commit and whether tracked files differ from it, as {git_commit, git_dirty}:
// what `pcrt fit` records of the fitter that judged runs made earlier (DIR/fit_context.json).
json source_context();

}  // namespace pcrt
