#include "core/file_output.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace pcrt {

namespace fs = std::filesystem;

void check_output_path(const std::string& path, const std::string& option) {
  if (path.empty()) input_error("{}: an empty file name", option);
  std::error_code ec;
  if (fs::is_directory(path, ec)) input_error("{} {}: is a directory, not a file", option, path);
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

OutputFiles::~OutputFiles() {
  for (const Staged& s : staged_) std::remove(s.temporary.c_str());
}

void OutputFiles::stage(const std::string& path, const StreamWriter& write, bool binary) {
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
