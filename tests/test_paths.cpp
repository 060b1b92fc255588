#include "tests/test_paths.hpp"

namespace pcrt::test {

std::filesystem::path source_dir() { return PCRT_SOURCE_DIR; }
std::filesystem::path data_dir() { return source_dir() / "data"; }

}  // namespace pcrt::test
