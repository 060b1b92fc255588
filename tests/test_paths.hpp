// Where the tests find the source tree's files, compiled into one translation unit
// (test_paths.cpp) so that the test sources themselves do not depend on the checkout's path.
#pragma once

#include <filesystem>

namespace pcrt::test {

std::filesystem::path source_dir();
std::filesystem::path data_dir();  // source_dir() / "data", filled by scripts/fetch_data.sh

}  // namespace pcrt::test
