// What every fuzz target checks: the input is either accepted or refused with an InputError
// naming it on one line; any other exception, a crash, a hang or a sanitizer report is a finding.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "core/error.hpp"

namespace pcrt::fuzz {

inline constexpr const char* kName = "fuzz-input";

template <typename Read>
void expect_accepted_or_refused(Read&& read) {
  try {
    read();
  } catch (const InputError& e) {
    if (std::string(e.what()).find(kName) == std::string::npos) {
      std::fprintf(stderr, "the error does not name the input: %s\n", e.what());
      std::abort();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "not an InputError: %s\n", e.what());
    std::abort();
  }
}

inline std::string text_of(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace pcrt::fuzz
