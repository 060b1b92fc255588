// Generator specs (name:key=value,...); accepted specs of up to 1000 points are generated and
// validated too.
#include "core/dataset.hpp"
#include "tests/fuzz/fuzz_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string spec = fuzz::text_of(data, size);
  // Errors name the spec itself; an empty or path-like spec would name (or read) a file instead.
  if (spec.empty() || spec.find('/') != std::string::npos || spec.find('\0') != std::string::npos)
    return 0;
  try {
    const ParamValues values = parse_generator_spec(spec, nullptr);
    if (values.at("n") > 1000) return 0;
    load_dataset(spec).cloud.validate();
  } catch (const InputError& e) {
    if (std::string(e.what()).find(spec) == std::string::npos) {
      std::fprintf(stderr, "the error does not name the spec: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
