// my_pcrt: pcrt's command line with one more method. `my_pcrt list`, `render`, `accuracy`,
// `sweep` (whose child runs are this program again) and every other command know ball_splat.
#include "ball_splat.hpp"
#include "harness/cli_main.hpp"

int main(int argc, char** argv) {
  register_ball_splat(pcrt::MethodRegistry::instance());
  return pcrt::cli_main(argc, argv);
}
