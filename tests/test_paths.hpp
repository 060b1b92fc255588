// Where the tests find the source tree's files, compiled into one translation unit
// (test_paths.cpp) so that the test sources themselves do not depend on the checkout's path.
#pragma once

#include <filesystem>

// A test that cannot run here (no data/, no AVX2) says why and returns: ctest reports it as
// skipped (SKIP_REGULAR_EXPRESSION on every Catch2 test, tests/CMakeLists.txt), never as passed.
#define PCRT_SKIP(why)             \
  do {                             \
    WARN("PCRT_SKIPPED: " << why); \
    return;                        \
  } while (false)

namespace pcrt::test {

std::filesystem::path source_dir();
std::filesystem::path data_dir();  // source_dir() / "data", filled by scripts/fetch_data.sh

}  // namespace pcrt::test
