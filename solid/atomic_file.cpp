#include "solid/atomic_file.h"

#include <string>
#include <unistd.h>

#include "solid/errors.h"

namespace cover {

void write_atomically(const std::filesystem::path& path,
                      const std::function<bool(const std::filesystem::path&)>& write,
                      std::string_view what) {
  namespace fs = std::filesystem;
  fs::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  std::error_code ec;
  bool written = false;
  try {
    written = write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  const std::string message = path.string() + ": cannot write " + std::string(what);
  if (!written) {
    fs::remove(tmp, ec);
    throw InputError(message);
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw InputError(message + " (" + ec.message() + ")");
  }
}

}  // namespace cover
