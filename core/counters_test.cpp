#include "core/counters.hpp"

#include <catch2/catch.hpp>

using namespace pcrt;

namespace {
const Counter kTestCounter{"test_counter", "for the counter test"};
}

TEST_CASE("counters add, merge and report by name", "[counters]") {
  OpCounters a, b;
  a.add(kTestCounter, 5);
  b.add(kTestCounter);
  b.add(kRaysCast, 3);
  a.merge(b);
  REQUIRE(a.get(kTestCounter) == 6);
  const auto m = a.to_map();
  REQUIRE(m.at("test_counter") == 6);
  REQUIRE(m.at("rays_cast") == 3);
  REQUIRE(m.count("ray_hits") == 0);  // zero counters are left out
  // A counter declared twice under one name shares its slot.
  const Counter again{"test_counter", "same name"};
  REQUIRE(again.id() == kTestCounter.id());
}
