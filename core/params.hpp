// Named numeric parameters with defaults and valid ranges, shared by methods, structures and
// generators, so that `--set name=value` and `pcrt list` treat them all alike.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace pcrt {

struct ParamSpec {
  std::string name;
  double default_value = 0;
  double min_value = 0;  // inclusive
  double max_value = 0;  // inclusive
  std::string description;
  bool integer = false;
};

using ParamValues = std::map<std::string, double>;

// Defaults for every spec, overridden by `given` (which must only name specs in `specs`).
// Throws InputError "<context>: ..." for unknown names, non-integers and out-of-range values.
ParamValues resolve_params(const std::vector<ParamSpec>& specs, const ParamValues& given,
                           const std::string& context);

// Checks one value against its spec; throws InputError naming `context` and the parameter.
void check_param(const ParamSpec& spec, double value, const std::string& context);

// Parses "name=value" (as given to --set); throws InputError naming the text.
std::pair<std::string, double> parse_assignment(const std::string& text);

// Parses a finite number, or throws InputError "<what>: '<text>' is not a number".
double parse_number(const std::string& text, const std::string& what);

// A typed parameter struct's fields, declared once: each field's name, default, range and doc
// (its ParamSpec) with the member it fills. `pcrt list`, `--set`, the sweep validator, the Python
// module and the method READMEs' tables all read specs(); the method reads its values only through
// read(), so a misspelt name is a compile error, not a lookup failing at run time.
//
//   struct MyParams {
//     float front_depth = 0;
//     static const ParamList<MyParams>& list() {
//       static const auto l = ParamList<MyParams>().add(&MyParams::front_depth,
//           {"front_depth", 0.5, 0, 20, "blend window, in median splat radii"});
//       return l;
//     }
//   };
template <class P>
class ParamList {
 public:
  // An integral, bool or enum member makes the parameter an integer one (whatever spec.integer
  // says); an enum's values are its enumerators' numbers, which the spec's range must cover.
  template <class T>
  ParamList&& add(T P::*member, ParamSpec spec) && {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>, "parameters are numbers");
    spec.integer = !std::is_floating_point_v<T>;
    specs_.push_back(std::move(spec));
    setters_.push_back([member](P& p, double v) {
      if constexpr (std::is_enum_v<T>)
        p.*member = static_cast<T>(static_cast<std::underlying_type_t<T>>(v));
      else
        p.*member = static_cast<T>(v);
    });
    return std::move(*this);
  }
  // The fields of a shared group (splat, MLS, iteration parameters) inside this struct.
  template <class G>
  requires std::is_class_v<G> ParamList && add(G P::*member, const ParamList<G>& group) && {
    for (size_t i = 0; i < group.specs_.size(); ++i) {
      specs_.push_back(group.specs_[i]);
      setters_.push_back([member, set = group.setters_[i]](P& p, double v) { set(p.*member, v); });
    }
    return std::move(*this);
  }
  [[nodiscard]] const std::vector<ParamSpec>& specs() const { return specs_; }
  // The defaults overridden by `given`; throws InputError "<context>: ..." as resolve_params.
  [[nodiscard]] P read(const ParamValues& given, const std::string& context) const {
    const ParamValues values = resolve_params(specs_, given, context);
    P p{};
    for (size_t i = 0; i < specs_.size(); ++i) setters_[i](p, values.at(specs_[i].name));
    return p;
  }

 private:
  template <class>
  friend class ParamList;
  std::vector<ParamSpec> specs_;
  std::vector<std::function<void(P&, double)>> setters_;
};

}  // namespace pcrt
