// Writing output files so that a failure never leaves a half-written file in place of a good one,
// and a failing command changes no output at all: each file is written beside its target, then
// renamed over it once everything that can fail has succeeded.
#pragma once

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace pcrt {

using StreamWriter = std::function<void(std::ostream&)>;

// Throws InputError naming `option` and `path` unless `path` can be written: not empty, not a
// directory, and its folder exists. Commands call it for every output before any work.
// Also refuses an existing device, FIFO or socket (never replaced by a file); a symbolic link is
// written through, onto its target.
void check_output_path(const std::string& path, const std::string& option);

// Throws InputError when the output `path` is the same file (by device and inode, through links)
// as one of the command's inputs (path, option): `render --data in.ply --out in.ply`.
void check_not_an_input(const std::string& path, const std::string& option,
                        const std::vector<std::pair<std::string, std::string>>& inputs);

// A file a command writes or reads and the option naming it (an input with an empty path is
// not given; outputs not given are left out).
using NamedPath = std::pair<std::string, std::string>;

// Every check a command makes of its outputs before any work: each one writable
// (check_output_path), none of them one of its inputs (check_not_an_input) and no two of them
// the same file, which would keep only the last one written (`--out a.png --stats a.png`).
void check_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

// An output whose name says another format than the one written is refused (`convert --out
// x.xyz` once wrote a PLY that pcrt then could not read back as XYZ): `extensions` are the ones
// the command writes, lower case with the dot (".png", ".exr").
void require_extension(const std::string& path, const std::string& option,
                       const std::vector<std::string>& extensions);

// Creates the output directory `dir` (and its parents) or throws InputError naming `option`.
void make_output_directory(const std::string& dir, const std::string& option);

// The outputs of one command. stage() writes a file to a temporary beside its target (an error
// there leaves every target as it was); commit() renames them all onto their targets. Temporaries
// not committed are removed when the set is destroyed.
class OutputFiles {
 public:
  OutputFiles() = default;
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  ~OutputFiles();

  void stage(const std::string& path, const StreamWriter& write, bool binary = false);
  void commit();

 private:
  struct Staged {
    std::string path, temporary;
  };
  std::vector<Staged> staged_;
};

// Appends `line` and a newline to the file at `path` (created if missing), whole or not at all:
// if the write fails (a full or read-only file system), the file is cut back to its old length,
// so a log of one record per line stays readable, and InputError names `path` and the cause.
void append_line(const std::string& path, const std::string& line);

// One output on its own: stage and commit.
void write_file_atomically(const std::string& path, const StreamWriter& write, bool binary = false);

}  // namespace pcrt
