#include "core/json_input.hpp"

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/point_cloud_io.hpp"

namespace pcrt {
namespace {

size_t line_at(std::string_view text, size_t offset) {
  return 1 +
         size_t(std::count(text.begin(), text.begin() + long(std::min(offset, text.size())), '\n'));
}

// Rejects NUL bytes and nesting deeper than kMaxJsonDepth before nlohmann sees the text; brackets
// inside strings do not count.
void check_shape(std::string_view text, const std::string& source) {
  size_t depth = 0;
  bool in_string = false, escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\0') input_error("{}: line {}: a NUL byte; not JSON text", source, line_at(text, i));
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        input_error("{}: line {}: nested deeper than {} levels", source, line_at(text, i),
                    kMaxJsonDepth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

// nlohmann keeps the last of two equal keys in one object; a config or scene whose "grid"
// appears twice would run what the reader did not see. A SAX pass that only tracks the keys of
// each open object finds them. (nlohmann's callback parser could, but its end_object scans the
// enclosing array for discarded values: a list of 10^5 objects took 12 s, quadratically.)
class DuplicateKeys {
 public:
  using json = nlohmann::json;
  explicit DuplicateKeys(const std::string& source) : source_(source) {}
  bool null() { return true; }
  bool boolean(bool) { return true; }
  bool number_integer(json::number_integer_t) { return true; }
  bool number_unsigned(json::number_unsigned_t) { return true; }
  bool number_float(json::number_float_t, const json::string_t&) { return true; }
  bool string(json::string_t&) { return true; }
  bool binary(json::binary_t&) { return true; }
  bool start_object(size_t) {
    open_.emplace_back();
    return true;
  }
  bool key(json::string_t& k) {
    if (!open_.back().insert(k).second)
      input_error("{}: key \"{}\" appears twice in one object (JSON keeps only one of them)",
                  source_, k);
    return true;
  }
  bool end_object() {
    open_.pop_back();
    return true;
  }
  bool start_array(size_t) { return true; }
  bool end_array() { return true; }
  // The DOM parse that follows reports it, with nlohmann's place of the error.
  bool parse_error(size_t, const std::string&, const json::exception&) { return false; }

 private:
  const std::string& source_;
  std::vector<std::set<std::string>> open_;  // keys seen, per open object
};

}  // namespace

nlohmann::json parse_json_text(std::string_view text, const std::string& source) {
  check_shape(text, source);
  DuplicateKeys duplicates(source);
  nlohmann::json::sax_parse(text.begin(), text.end(), &duplicates);
  try {
    return nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {  // parse errors, and numbers beyond double
    // nlohmann's message names the place: "[json.exception.parse_error.101] parse error at line
    // 3, column 5: ..."; its tag is dropped.
    const std::string what = e.what();
    const size_t tag_end = what.find("] ");
    input_error("{}: not valid JSON: {}", source,
                tag_end == std::string::npos ? what : what.substr(tag_end + 2));
  }
}

nlohmann::json read_json_file(const std::string& path) {
  return parse_json_text(read_file(path), path);
}

std::string optional_string(const nlohmann::json& obj, const char* key, const std::string& fallback,
                            const std::string& where) {
  if (!obj.is_object()) input_error("{}: must be an object", where);
  const auto it = obj.find(key);
  if (it == obj.end()) return fallback;
  if (!it->is_string()) input_error("{}: {} must be a string, not {}", where, key, it->type_name());
  return it->get<std::string>();
}

double optional_number(const nlohmann::json& obj, const char* key, double fallback,
                       const std::string& where) {
  if (!obj.is_object()) input_error("{}: must be an object", where);
  const auto it = obj.find(key);
  if (it == obj.end()) return fallback;
  if (!it->is_number()) input_error("{}: {} must be a number, not {}", where, key, it->type_name());
  return it->get<double>();
}

}  // namespace pcrt
