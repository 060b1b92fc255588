// Errors caused by what a user gave us (files, specs, options). The CLI prints what() on one line
// and exits non-zero; anything else escaping is a bug.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace pcrt {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

template <typename... Args>
[[noreturn]] void input_error(fmt::format_string<Args...> f, Args&&... args) {
  throw InputError(fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace pcrt
