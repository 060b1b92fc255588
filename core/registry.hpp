// A list of entries (methods, structures, mesh engines, reconstructions) looked up by id. pcrt's
// own entries are listed once, explicitly, by the register_builtins() overload of each kind (as
// pbrt and Mitsuba list their plugins), called on first use: no static initializer has to survive
// the linker, so the registries are full in any program the library is linked into. Code of one's
// own adds entries with instance().add(...).
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace pcrt {

template <typename Info>
class Registry {
 public:
  static Registry& instance() {
    static Registry r = [] {
      Registry builtin;
      register_builtins(builtin);  // found by argument-dependent lookup: one overload per kind
      return builtin;
    }();
    return r;
  }
  // Throws InputError when the id is taken (a method of one's own named like a built-in one).
  void add(Info info) {
    if (contains(info.id)) input_error("'{}' is registered twice", info.id);
    entries_.push_back(std::move(info));
    std::sort(entries_.begin(), entries_.end(),
              [](const Info& a, const Info& b) { return a.id < b.id; });
  }
  [[nodiscard]] const std::vector<Info>& all() const { return entries_; }
  [[nodiscard]] bool contains(const std::string& id) const {
    return std::any_of(entries_.begin(), entries_.end(), [&](const Info& e) { return e.id == id; });
  }
  // Throws InputError "unknown <kind> '<id>' (known: ...)".
  [[nodiscard]] const Info& get(const std::string& id, const char* kind) const {
    for (const Info& e : entries_)
      if (e.id == id) return e;
    std::string known;
    for (const Info& e : entries_) known += (known.empty() ? "" : ", ") + e.id;
    input_error("unknown {} '{}' (known: {})", kind, id, known);
  }

 private:
  std::vector<Info> entries_;
};

}  // namespace pcrt
