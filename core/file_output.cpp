#include "core/file_output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/point_cloud_io.hpp"

namespace pcrt {

namespace fs = std::filesystem;

namespace {

// A device, FIFO or socket is never replaced by a file (a rename onto /dev/null would delete the
// node); pcrt writes regular files only.
void check_replaceable(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st) || fs::is_regular_file(st) || fs::is_directory(st)) return;
  input_error(
      "{}: is a device, FIFO or socket, not a regular file (pcrt writes regular files only)", what);
}

// Where an output lands: through symbolic links (dangling ones too) to their target, so that a
// link stays a link.
std::string landing(const std::string& path) {
  std::error_code ec;
  fs::path p = path;
  for (int hops = 0; hops < 40 && fs::is_symlink(p, ec); ++hops) {
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) return path;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  if (fs::is_symlink(p, ec)) input_error("{}: a loop of symbolic links", path);
  return p.string();
}

}  // namespace

void check_output_path(const std::string& path, const std::string& option) {
  if (path.empty()) input_error("{}: an empty file name", option);
  std::error_code ec;
  if (fs::is_directory(path, ec)) input_error("{} {}: is a directory, not a file", option, path);
  check_replaceable(path, option + " " + path);
  (void)landing(path);  // a loop of links is refused before any work
  const fs::path folder = fs::path(path).parent_path();
  if (!folder.empty() && !fs::is_directory(folder, ec))
    input_error("{} {}: folder {} does not exist", option, path, folder.string());
}

void make_output_directory(const std::string& dir, const std::string& option) {
  if (dir.empty()) input_error("{}: an empty directory name", option);
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    input_error("{} {}: is a file, not a directory", option, dir);
  fs::create_directories(dir, ec);
  if (ec) input_error("{} {}: cannot create: {}", option, dir, ec.message());
}

void require_extension(const std::string& path, const std::string& option,
                       const std::vector<std::string>& extensions) {
  const std::string ext = lowercase_extension(path);
  if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) return;
  input_error("{} {}: writes {} files; give a name ending in {}", option, path,
              fmt::join(extensions, " or "), fmt::join(extensions, " or "));
}

void check_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
  std::vector<std::pair<fs::path, const NamedPath*>> seen;
  for (const NamedPath& out : outputs) {
    const auto& [path, option] = out;
    check_output_path(path, option);
    check_not_an_input(path, option, inputs);
    std::error_code ec;  // absolute first: a missing relative name would come back as given
    const fs::path where =
        fs::weakly_canonical(fs::absolute(landing(path), ec), ec).lexically_normal();
    for (const auto& [other, named] : seen)
      if (!ec && where == other)
        input_error("{} {}: is also the output {} {}; two outputs cannot share a file", option,
                    path, named->second, named->first);
    if (!ec) seen.emplace_back(where, &out);
  }
}

OutputFiles::~OutputFiles() {
  for (const Staged& s : staged_) std::remove(s.temporary.c_str());
}

void check_not_an_input(const std::string& path, const std::string& option,
                        const std::vector<std::pair<std::string, std::string>>& inputs) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  for (const auto& [input, input_option] : inputs)
    if (!input.empty() && fs::equivalent(path, input, ec) && !ec)
      input_error("{} {}: is also the input {} {}; refusing to overwrite it", option, path,
                  input_option, input);
}

void OutputFiles::stage(const std::string& given, const StreamWriter& write, bool binary) {
  check_replaceable(given, given);
  const std::string path = landing(given);
  static std::atomic<unsigned> serial{0};
  const std::string tmp =
      fmt::format("{}.tmp.{}.{}", path, static_cast<long>(getpid()), serial.fetch_add(1));
  {
    std::ofstream out(tmp, binary ? std::ios::binary | std::ios::out : std::ios::out);
    if (!out) input_error("{}: cannot open for writing: {}", path, std::strerror(errno));
    try {
      write(out);
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      input_error("{}: write failed: {}", path, std::strerror(errno));
    }
  }
  staged_.push_back({path, tmp});
}

void OutputFiles::commit() {
  for (size_t i = 0; i < staged_.size(); ++i) {
    std::error_code ec;
    fs::rename(staged_[i].temporary, staged_[i].path, ec);
    if (ec) input_error("{}: cannot replace: {}", staged_[i].path, ec.message());
  }
  staged_.clear();
}

void append_line(const std::string& path, const std::string& line) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) input_error("{}: cannot append: {}", path, std::strerror(errno));
  struct stat st {};
  const off_t old_size = ::fstat(fd, &st) == 0 ? st.st_size : -1;
  const std::string text = line + '\n';
  size_t done = 0;
  int error = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : ENOSPC;
      break;
    }
    done += size_t(n);
  }
  if (error != 0 && done > 0 && old_size >= 0) (void)::ftruncate(fd, old_size);
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) input_error("{}: write failed: {}", path, std::strerror(error));
}

void write_file_atomically(const std::string& path, const StreamWriter& write, bool binary) {
  OutputFiles one;
  one.stage(path, write, binary);
  one.commit();
}

}  // namespace pcrt
