#include "cover/solid/memory_limit.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "cover/solid/errors.h"

namespace cover {
namespace {

/// Closes a POSIX file descriptor on scope exit.
struct FdGuard {
  int fd;
  ~FdGuard() { ::close(fd); }
};

std::string mib(double bytes) {
  return std::to_string(static_cast<unsigned long long>(std::ceil(bytes / 1048576)));
}

}  // namespace

void check_memory(double estimate_bytes, uint64_t limit_bytes, const std::string& what) {
  if (estimate_bytes > static_cast<double>(limit_bytes))
    throw InputError(what + " needs " + mib(estimate_bytes) + " MiB, over " +
                     parameter("max_memory") + " " + mib(static_cast<double>(limit_bytes)) +
                     " MiB");
}

FileBytes read_regular_file(const std::filesystem::path& path, uint64_t max_bytes) {
  const std::string file = path.string();
  // O_NONBLOCK: opening a FIFO must not wait for a writer (it is refused just below); reads
  // from a regular file never block anyway.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(file + ": cannot open: " + std::strerror(errno));
  const FdGuard guard{fd};
  struct stat info {};
  if (::fstat(fd, &info) != 0) throw InputError(file + ": cannot read: " + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) throw InputError(file + ": not a regular file");
  const auto size = static_cast<uint64_t>(info.st_size);
  check_memory(static_cast<double>(size), max_bytes, file + ": the file");
  // One byte more than the size so that the final read() sees end of file without growing; a
  // file that grows while it is read is cut off at the limit like a stream.
  FileBytes out;
  LargeBuffer<char>& data = out.bytes_;
  data.resize(size + 1);
  size_t used = 0;
  for (;;) {
    if (used == data.size()) {
      check_memory(static_cast<double>(used) + 1, max_bytes, file + ": the file");
      data.resize(std::min<uint64_t>(2 * data.size(), max_bytes + 1));
    }
    const ssize_t got = ::read(fd, data.data() + used, data.size() - used);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InputError(file + ": cannot read: " + std::strerror(errno));
    }
    if (got == 0) break;
    used += static_cast<size_t>(got);
  }
  out.size_ = used;
  return out;
}

FileBytes read_stream(std::istream& in, uint64_t max_bytes, const std::string& name) {
  constexpr size_t kBlock = size_t{1} << 20;
  FileBytes out;
  LargeBuffer<char>& text = out.bytes_;
  while (in) {
    if (text.size() < out.size_ + kBlock)
      text.resize(std::max(2 * text.size(), out.size_ + kBlock));
    in.read(text.data() + out.size_, static_cast<std::streamsize>(kBlock));
    out.size_ += static_cast<size_t>(in.gcount());
    check_memory(static_cast<double>(out.size_), max_bytes, name + ": the input");
  }
  if (in.bad()) throw InputError(name + ": cannot read");
  return out;
}

}  // namespace cover
