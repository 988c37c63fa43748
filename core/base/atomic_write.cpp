#include "core/base/atomic_write.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace cagewrap {

Status write_file_atomic(const std::string& path, std::string_view bytes) {
  const std::string tmp = path + ".tmp";
  auto fail = [&](const char* doing, int fd) -> Status {
    std::string reason = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    return make_error(ErrorCode::kWrite, path + ": could not save (" + doing + " " + tmp + ": " + reason +
                                             "); the previous file, if any, is unchanged");
  };
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    std::string reason = std::strerror(errno);  // not ours to unlink: it may be something else
    return make_error(ErrorCode::kWrite, path + ": could not save (creating " + tmp + ": " + reason +
                                             "); the previous file, if any, is unchanged");
  }
  struct stat old;
  if (::stat(path.c_str(), &old) == 0) ::fchmod(fd, old.st_mode & 07777);  // keep the old permissions
  for (size_t done = 0; done < bytes.size();) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail("writing", fd);
    done += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0) return fail("flushing", fd);
  if (::close(fd) != 0) return fail("closing", -1);
  if (::rename(tmp.c_str(), path.c_str()) != 0) return fail("renaming", -1);
  // make the rename itself durable
  std::string dir = std::filesystem::path(path).parent_path().string();
  int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  return Ok{};
}

}  // namespace cagewrap
