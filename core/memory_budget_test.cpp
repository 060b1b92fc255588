#include "core/memory_budget.hpp"

#include <catch2/catch.hpp>
#include <string>

#include "core/error.hpp"
#include "core/offsets.hpp"

namespace pcrt {

TEST_CASE("require_memory refuses what cannot fit, naming the input and the estimate") {
  CHECK(available_memory_bytes() > 0);
  CHECK_NOTHROW(require_memory(1, "tiny"));
  try {
    require_memory(size_t(1) << 62, "sphere:n=9");
    FAIL("4 EiB fitted");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("out of memory: sphere:n=9 is too large for this machine") == 0);
    CHECK(what.find("GiB needed (estimate)") != std::string::npos);
  }
}

TEST_CASE("offset32 refuses offsets beyond 32 bits instead of wrapping") {
  CHECK(offset32(size_t(UINT32_MAX), "kd_tree") == UINT32_MAX);
  CHECK_THROWS_AS(offset32(size_t(UINT32_MAX) + 1, "kd_tree"), InputError);
}

}  // namespace pcrt
