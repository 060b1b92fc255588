// pcrt: point cloud ray tracing benchmark harness (its command line is harness/cli_main.cpp).
#include "harness/cli_main.hpp"

PCRT_MAIN()
