// Errors caused by what a user gave us (files, specs, options). The CLI prints what() on one line
// and exits non-zero; anything else escaping is a bug.
#pragma once

#include <fmt/format.h>

#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcrt {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

template <typename... Args>
[[noreturn]] void input_error(fmt::format_string<Args...> f, Args&&... args) {
  throw InputError(fmt::format(f, std::forward<Args>(args)...));
}

// Notes about an input that was read all the same (duplicate points dropped, zero normals taken
// as none). Printed on stderr at once, unless a NoteHold is alive: the CLI holds them while a
// command runs, so that a command that fails prints its error alone, on one line.
struct HeldNotes {
  std::mutex mutex;
  int holds = 0;
  std::vector<std::string> lines;
};
inline HeldNotes& held_notes() {
  static HeldNotes notes;
  return notes;
}

template <typename... Args>
void note(fmt::format_string<Args...> f, Args&&... args) {
  const std::string line = fmt::format(f, std::forward<Args>(args)...);
  HeldNotes& n = held_notes();
  const std::lock_guard<std::mutex> lock(n.mutex);
  if (n.holds > 0)
    n.lines.push_back(line);
  else
    std::fprintf(stderr, "%s\n", line.c_str());
}

// Holds notes while alive; print() writes those held so far (the command went on to its end),
// and notes never printed are dropped (the command failed: its error says what matters).
class NoteHold {
 public:
  NoteHold() {
    const std::lock_guard<std::mutex> lock(held_notes().mutex);
    ++held_notes().holds;
  }
  ~NoteHold() {
    HeldNotes& n = held_notes();
    const std::lock_guard<std::mutex> lock(n.mutex);
    if (--n.holds == 0) n.lines.clear();
  }
  NoteHold(const NoteHold&) = delete;
  NoteHold& operator=(const NoteHold&) = delete;
  void print() {
    HeldNotes& n = held_notes();
    const std::lock_guard<std::mutex> lock(n.mutex);
    for (const std::string& line : n.lines) std::fprintf(stderr, "%s\n", line.c_str());
    n.lines.clear();
  }
};

}  // namespace pcrt
