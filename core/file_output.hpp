// Writing output files so that a failure never leaves a half-written file in place of a good one:
// write beside the target, then rename over it.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace pcrt {

// Calls `write` with a stream on a temporary file next to `path` and renames it to `path` when
// `write` returns and the stream is good. Throws InputError naming `path` otherwise.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary = false);

}  // namespace pcrt
