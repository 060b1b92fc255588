// The pcrt command line as a library, the way Google Benchmark provides main: a program of one's
// own registers its methods (MethodRegistry::instance().add) and hands main to pcrt; every
// command, sweeps and their child runs included, then knows those methods like the built-in ones
// (child runs start /proc/self/exe, the same program). examples/out_of_tree_method/ is one.
#pragma once

namespace pcrt {

// Parses and runs one pcrt command: 0 on success, 1 with one line on stderr for bad input,
// 3 for an internal error.
int cli_main(int argc, char** argv);

}  // namespace pcrt

// A main() that is pcrt's command line and nothing else (what the pcrt executable is).
#define PCRT_MAIN() \
  int main(int argc, char** argv) { return ::pcrt::cli_main(argc, argv); }
