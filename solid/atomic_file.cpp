#include "solid/atomic_file.h"

#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <mutex>
#include <optional>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "solid/errors.h"

namespace cover {
namespace {

namespace fs = std::filesystem;

/// Every temporary of the process that exists or is about to, for the signal thread. Recursive:
/// commit() holds it across its renames, which register and forget files themselves. Never
/// destroyed, since the signal thread may use it while the process exits.
class Registry {
 public:
  static Registry& get() {
    static Registry* registry = new Registry;
    return *registry;
  }
  std::unique_lock<std::recursive_mutex> hold() { return std::unique_lock(mutex_); }
  void add(const std::string& path) {
    const auto lock = hold();
    paths_.push_back(path);
  }
  void forget(const std::string& path) {
    const auto lock = hold();
    std::erase(paths_, path);
  }
  /// Unlinks every registered file; the caller holds the lock so that no new one registers.
  void unlink_all() const {
    for (const std::string& path : paths_) ::unlink(path.c_str());
  }

 private:
  std::recursive_mutex mutex_;
  std::vector<std::string> paths_;
};

/// A registered temporary file TARGET.tmp-PID-K (not created here): removed and forgotten on
/// destruction unless renamed away.
class Temporary {
 public:
  explicit Temporary(const fs::path& target) : path_(target) {
    static std::atomic<uint64_t> count{0};
    path_ += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(count++);
    Registry::get().add(path_.string());
  }
  Temporary(Temporary&& other) noexcept : path_(std::exchange(other.path_, {})) {}
  Temporary& operator=(Temporary&&) = delete;
  ~Temporary() {
    if (path_.empty()) return;
    std::error_code ignored;
    fs::remove(path_, ignored);
    Registry::get().forget(path_.string());
  }

  const fs::path& path() const { return path_; }

  /// Renames the file onto `target` (then it is no longer this object's); the error otherwise.
  std::error_code rename_to(const fs::path& target) {
    std::error_code error;
    fs::rename(path_, target, error);
    if (!error) Registry::get().forget(std::exchange(path_, {}).string());
    return error;
  }

 private:
  fs::path path_;
};

/// The file `path` finally names: symbolic links followed (at most 40, the kernel's limit), a
/// relative link target taken from the link's folder. It need not exist.
fs::path final_target(const fs::path& path) {
  fs::path target = path;
  for (int hop = 0; hop < 40; ++hop) {
    std::error_code error;
    if (!fs::is_symlink(target, error)) break;
    const fs::path link = fs::read_symlink(target, error);
    if (error) break;
    target = link.is_absolute() ? link : target.parent_path() / link;
  }
  return target;
}

/// Gives `temporary` the permission bits of the regular file `target` when it exists.
std::error_code copy_mode(const fs::path& target, const fs::path& temporary) {
  struct stat info {};
  if (::stat(target.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) return {};
  if (::chmod(temporary.c_str(), info.st_mode & 07777) != 0) return {errno, std::system_category()};
  return {};
}

/// A finished temporary waiting for OutputBatch::commit().
struct Pending {
  Temporary temporary;
  fs::path target;
  std::string message;  ///< "PATH: cannot write WHAT"
};

/// The calling thread's open batch: whether there is one, and its outputs in write order.
thread_local bool t_batch_open = false;
thread_local std::vector<Pending> t_pending;

/// The old contents of `output`'s target as a hard link (or a copy), empty when there is none.
std::optional<Temporary> keep_old(const Pending& output) {
  struct stat info {};
  if (::lstat(output.target.c_str(), &info) != 0) return std::nullopt;
  Temporary old(output.target);
  if (::link(output.target.c_str(), old.path().c_str()) == 0) return old;
  std::error_code error;
  fs::copy_file(output.target, old.path(), error);
  if (error)
    throw InputError(output.message + " (cannot keep the old file: " + error.message() + ")");
  return old;
}

/// Undoes the renames of outputs [0, done): latest first, so that a target written twice gets
/// its contents from before the batch.
void restore(std::vector<Pending>& outputs, std::vector<std::optional<Temporary>>& old,
             size_t done) {
  for (size_t i = done; i-- > 0;) {
    std::error_code ignored;
    if (old[i])
      old[i]->rename_to(outputs[i].target);
    else
      fs::remove(outputs[i].target, ignored);
  }
}

}  // namespace

void write_atomically(const fs::path& path, const std::function<bool(const fs::path&)>& write,
                      std::string_view what) {
  const std::string message = path.string() + ": cannot write " + std::string(what);
  const fs::path target = final_target(path);
  Temporary temporary(target);
  if (!write(temporary.path())) throw InputError(message);
  if (const std::error_code error = copy_mode(target, temporary.path()))
    throw InputError(message + " (" + error.message() + ")");
  if (t_batch_open) {
    t_pending.push_back({std::move(temporary), target, message});
    return;
  }
  if (const std::error_code error = temporary.rename_to(target))
    throw InputError(message + " (" + error.message() + ")");
}

OutputBatch::OutputBatch() : open_(!t_batch_open) { t_batch_open = true; }

OutputBatch::~OutputBatch() {
  if (!open_) return;
  t_pending.clear();
  t_batch_open = false;
}

void OutputBatch::commit() {
  if (!open_) return;
  open_ = false;
  t_batch_open = false;
  std::vector<Pending> outputs = std::exchange(t_pending, {});
  const auto lock = Registry::get().hold();  // a signal waits until the batch is settled
  // The last rename has nothing after it to fail: its target needs no copy.
  std::vector<std::optional<Temporary>> old;
  for (size_t i = 0; i + 1 < outputs.size(); ++i) old.push_back(keep_old(outputs[i]));
  for (size_t i = 0; i < outputs.size(); ++i) {
    if (const std::error_code error = outputs[i].temporary.rename_to(outputs[i].target)) {
      restore(outputs, old, i);
      throw InputError(outputs[i].message + " (" + error.message() + ")");
    }
  }
}

void remove_temporaries_on_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  int handled = 0;
  for (const int s : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction action {};
    if (::sigaction(s, nullptr, &action) == 0 && action.sa_handler != SIG_IGN) {
      sigaddset(&signals, s);
      ++handled;
    }
  }
  if (handled == 0) return;
  ::pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread([signals] {
    int s = 0;
    while (::sigwait(&signals, &s) != 0) {
    }
    const auto lock = Registry::get().hold();  // held until the process ends: no new temporary
    Registry::get().unlink_all();
    ::signal(s, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, s);
    ::pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    ::raise(s);
  }).detach();
}

}  // namespace cover
