// Line-by-line tokenising of text point formats (XYZ, OFF, ASCII PLY) with exact line numbers,
// so every parse error can name the file and line.
#pragma once

#include <charconv>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace pcrt {

class TextScanner {
 public:
  TextScanner(std::string_view text, std::string file, size_t start_line = 0)
      : text_(text), file_(std::move(file)), line_no_(start_line) {}

  // Advances to the next line that has tokens (after stripping '#' comments when `comments`),
  // filling tokens(). Returns false at the end of the text.
  bool next_line(bool comments = true) {
    while (pos_ < text_.size()) {
      size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_no_;
      if (comments) line = line.substr(0, line.find('#'));
      split(line);
      if (!tokens_.empty()) return true;
    }
    tokens_.clear();
    return false;
  }
  [[nodiscard]] const std::vector<std::string_view>& tokens() const { return tokens_; }
  [[nodiscard]] size_t line() const { return line_no_; }
  [[nodiscard]] const std::string& file() const { return file_; }

  template <typename T>
  T number(size_t i) const {
    std::string_view s = tokens_.at(i);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    T v{};
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size())
      input_error("{}: line {}: '{}' is not a number", file_, line_no_, tokens_.at(i));
    return v;
  }

 private:
  void split(std::string_view line) {
    tokens_.clear();
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i])) ++i;
      size_t j = i;
      while (j < line.size() && !is_space(line[j])) ++j;
      if (j > i) tokens_.push_back(line.substr(i, j - i));
      i = j;
    }
  }
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  }

  std::string_view text_;
  std::string file_;
  size_t pos_ = 0;
  size_t line_no_;
  std::vector<std::string_view> tokens_;
};

// A text file from byte `offset` on, read in blocks that end at a line's end: block(text,
// lines_before) for each (lines_before counts from `first_line`, the lines before `offset`), so
// that a TextScanner over the block names the file's own line numbers, until it returns false.
// A line longer than a block (4 MiB) is an InputError; the file is never held whole.
void for_each_line_block(const std::string& path, uint64_t offset, size_t first_line,
                         const std::function<bool(std::string_view, size_t)>& block);

}  // namespace pcrt
