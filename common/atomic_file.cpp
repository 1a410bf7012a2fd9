#include "common/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <string>
#include <system_error>

namespace bumprad {
namespace {

// Returns errno, or 0.
int fsync_path(const std::filesystem::path& p, int flags) {
  int fd = ::open(p.c_str(), flags);
  if (fd < 0) return errno;
  int error = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  return error;
}

}  // namespace

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path dir = target.has_parent_path() ? target.parent_path() : ".";
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  name += target.extension().string();
  std::filesystem::path tmp = dir / name;
  try {
    write(tmp);
    // Some file systems report a full disk only when the data is flushed.
    if (int error = fsync_path(tmp, O_RDONLY))
      throw std::system_error(error, std::generic_category(), "cannot write " + target.string());
    std::filesystem::rename(tmp, target);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
  fsync_path(dir, O_RDONLY | O_DIRECTORY);
}

void write_file_atomically(const std::filesystem::path& target, std::string_view contents) {
  write_atomically(target, [&](const std::filesystem::path& tmp) {
    // POSIX calls rather than a stream, so that a failure says why (errno): a full disk
    // must be told apart from other failures.
    auto fail = [&](int error) {
      throw std::system_error(error, std::generic_category(), "cannot write " + target.string());
    };
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail(errno);
    for (std::string_view rest = contents; !rest.empty();) {
      ssize_t n = ::write(fd, rest.data(), rest.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        int error = n < 0 ? errno : EIO;
        ::close(fd);
        fail(error);
      }
      rest.remove_prefix(std::size_t(n));
    }
    if (::close(fd) != 0) fail(errno);
  });
}

}  // namespace bumprad
