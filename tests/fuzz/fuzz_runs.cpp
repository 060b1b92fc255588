// runs.jsonl as `pcrt fit`, `pcrt merge` and `--resume` read it, then what fit does with the
// runs it accepts: runs.csv rows, the fits and verdicts of the sweep they belong to.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "harness/run_files.hpp"
#include "harness/sweep_fits.hpp"
#include "tests/fuzz/fuzz_small_sweep.hpp"
#include "tests/fuzz/fuzz_target.hpp"

namespace {

// A scratch file whose path names the input, as the readers' errors must.
const std::string& scratch_dir() {
  static const std::string dir = [] {
    const std::string d = std::filesystem::temp_directory_path().string() + "/pcrt-fuzz-runs-" +
                          std::to_string(getpid());
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pcrt;
  const std::string path = scratch_dir() + "/" + fuzz::kName + ".jsonl";
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), long(size));
  fuzz::expect_accepted_or_refused([&] {
    const RunsFile file = read_runs_file(path);
    write_runs_csv(scratch_dir() + "/" + fuzz::kName + ".csv", file.runs);
    (void)fit_runs(fuzz::small_sweep(), file.runs);
  });
  return 0;
}
