#include "cover/io/atomic_file.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
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

#include "cover/solid/errors.h"

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
  void add(const std::string& path, bool directory) {
    const auto lock = hold();
    entries_.push_back({path, directory});
  }
  void forget(const std::string& path) {
    const auto lock = hold();
    std::erase_if(entries_, [&](const Entry& e) { return e.path == path; });
  }
  /// Removes every registered file and folder; the caller holds the lock so that no new one
  /// registers. A folder is first renamed to PATH.gone, so that threads still writing into it
  /// by name can add nothing to what is being removed.
  void remove_all() const {
    for (const Entry& e : entries_) {
      if (!e.directory) {
        ::unlink(e.path.c_str());
        continue;
      }
      const std::string gone = e.path + ".gone";
      std::error_code ignored;
      fs::remove_all(::rename(e.path.c_str(), gone.c_str()) == 0 ? gone : e.path, ignored);
    }
  }

 private:
  struct Entry {
    std::string path;
    bool directory;
  };
  std::recursive_mutex mutex_;
  std::vector<Entry> entries_;
};

}  // namespace

namespace detail {

/// A registered temporary file or folder TARGET.tmp-PID-K (not created here): removed (a folder
/// with everything in it) and forgotten on destruction unless renamed away.
class Temporary {
 public:
  explicit Temporary(const fs::path& target, bool directory = false)
      : path_(target), directory_(directory) {
    static std::atomic<uint64_t> count{0};
    path_ += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(count++);
    Registry::get().add(path_.string(), directory_);
  }
  Temporary(Temporary&& other) noexcept
      : path_(std::exchange(other.path_, {})), directory_(other.directory_) {}
  Temporary& operator=(Temporary&&) = delete;
  ~Temporary() {
    if (path_.empty()) return;
    std::error_code ignored;
    if (directory_)
      fs::remove_all(path_, ignored);
    else
      fs::remove(path_, ignored);
    Registry::get().forget(path_.string());
  }

  const fs::path& path() const { return path_; }
  bool directory() const { return directory_; }

  /// Renames the file onto `target` (then it is no longer this object's); the error otherwise.
  std::error_code rename_to(const fs::path& target) {
    std::error_code error;
    fs::rename(path_, target, error);
    if (!error) Registry::get().forget(std::exchange(path_, {}).string());
    return error;
  }

  /// Swaps the folder into `target` in one step: renameat2's RENAME_EXCHANGE when `target`
  /// exists (this object then holds the old folder), RENAME_NOREPLACE when not (then it holds
  /// nothing). Where the file system has no RENAME_EXCHANGE, the old folder is first renamed to
  /// this object's name plus ".old" (a moment without a target) and then held here. `replaced`
  /// tells which; the error otherwise, with nothing changed.
  std::error_code swap_into(const fs::path& target, bool& replaced) {
    replaced = false;
    if (::renameat2(AT_FDCWD, path_.c_str(), AT_FDCWD, target.c_str(), RENAME_NOREPLACE) == 0) {
      Registry::get().forget(std::exchange(path_, {}).string());
      return {};
    }
    if (errno != EEXIST && errno != ENOTEMPTY && errno != EINVAL && errno != ENOSYS)
      return {errno, std::system_category()};
    if (::renameat2(AT_FDCWD, path_.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
      replaced = true;
      return {};
    }
    if (errno != EINVAL && errno != ENOSYS) return {errno, std::system_category()};
    // No atomic exchange here: the old folder aside, the new one in, the old one held.
    struct stat info {};
    const bool exists = ::lstat(target.c_str(), &info) == 0;
    const std::string aside = path_.string() + ".old";
    if (exists) {
      Registry::get().add(aside, true);
      if (::rename(target.c_str(), aside.c_str()) != 0) {
        const std::error_code error(errno, std::system_category());
        Registry::get().forget(aside);
        return error;
      }
    }
    if (::rename(path_.c_str(), target.c_str()) != 0) {
      const std::error_code error(errno, std::system_category());
      if (exists) ::rename(aside.c_str(), target.c_str());
      if (exists) Registry::get().forget(aside);
      return error;
    }
    Registry::get().forget(path_.string());
    path_ = exists ? fs::path(aside) : fs::path();
    replaced = exists;
    return {};
  }

 private:
  fs::path path_;
  bool directory_;
};

}  // namespace detail

namespace {

using detail::Temporary;

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
  /// For a folder: why its target may not be replaced ("" when it may), checked again just
  /// before the swap.
  std::function<std::string(const fs::path&)> refusal;
  bool replaced = false;  ///< a folder swapped in over an old one (now held by `temporary`)
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

/// Puts a folder output's old folder (held by its temporary) back in place, or removes the new
/// one when there was none.
void restore_folder(Pending& output) {
  std::error_code ignored;
  if (!output.replaced) {
    fs::remove_all(output.target, ignored);
    return;
  }
  const char* temporary = output.temporary.path().c_str();
  if (::renameat2(AT_FDCWD, temporary, AT_FDCWD, output.target.c_str(), RENAME_EXCHANGE) == 0)
    return;
  const std::string aside = output.temporary.path().string() + ".new";
  if (::rename(output.target.c_str(), aside.c_str()) == 0 &&
      ::rename(temporary, output.target.c_str()) == 0)
    fs::remove_all(aside, ignored);
}

/// Undoes the renames of outputs [0, done): latest first, so that a target written twice gets
/// its contents from before the batch.
void restore(std::vector<Pending>& outputs, std::vector<std::optional<Temporary>>& old,
             size_t done) {
  for (size_t i = done; i-- > 0;) {
    std::error_code ignored;
    if (outputs[i].temporary.directory())
      restore_folder(outputs[i]);
    else if (old[i])
      old[i]->rename_to(outputs[i].target);
    else
      fs::remove(outputs[i].target, ignored);
  }
}

/// Moves output i into place: a file by rename, a folder by swap_into after checking again that
/// its target may be replaced. The error message otherwise ("" on success).
std::string commit_one(Pending& output) {
  if (!output.temporary.directory()) {
    const std::error_code error = output.temporary.rename_to(output.target);
    return error ? output.message + " (" + error.message() + ")" : std::string();
  }
  std::error_code ignored;
  if (fs::exists(fs::symlink_status(output.target, ignored))) {
    const std::string why = output.refusal(output.target);
    if (!why.empty()) return output.message + " (" + why + ")";
  }
  const std::error_code error = output.temporary.swap_into(output.target, output.replaced);
  return error ? output.message + " (" + error.message() + ")" : std::string();
}

/// `path` without trailing separators, links followed: the folder an output folder replaces.
fs::path folder_target(const fs::path& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
  return final_target(p);
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
    t_pending.push_back({std::move(temporary), target, message, {}});
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
  // A folder's old contents are kept by the swap itself.
  std::vector<std::optional<Temporary>> old;
  for (size_t i = 0; i + 1 < outputs.size(); ++i)
    old.push_back(outputs[i].temporary.directory() ? std::nullopt : keep_old(outputs[i]));
  old.resize(outputs.size());
  for (size_t i = 0; i < outputs.size(); ++i) {
    if (const std::string error = commit_one(outputs[i]); !error.empty()) {
      restore(outputs, old, i);
      throw InputError(error);
    }
  }
}

OutputFolder::OutputFolder(const fs::path& path, std::string_view what,
                           std::function<std::string(const fs::path&)> refusal)
    : name_(path.string()),
      message_(name_ + ": cannot write " + std::string(what)),
      target_(folder_target(path)),
      refusal_(std::move(refusal)) {
  std::error_code error;
  const fs::file_status status = fs::status(target_, error);
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) throw InputError(name_ + ": exists and is not a folder");
    const std::string why = refusal_(target_);
    if (!why.empty()) throw InputError(name_ + ": " + why);
  }
  temporary_ = std::make_unique<Temporary>(target_, true);
  if (!fs::create_directory(temporary_->path(), error) || error) {
    const std::string reason = error ? error.message() : "it exists";
    temporary_.reset();
    throw InputError(message_ + " (" + reason + ")");
  }
  // The new folder gets the old one's permission bits, as a file does.
  struct stat info {};
  if (::stat(target_.c_str(), &info) == 0 && S_ISDIR(info.st_mode))
    ::chmod(temporary_->path().c_str(), info.st_mode & 07777);
}

OutputFolder::~OutputFolder() = default;

const fs::path& OutputFolder::path() const { return temporary_->path(); }

void OutputFolder::commit() {
  if (!temporary_) throw PreconditionError("OutputFolder::commit: already committed");
  Pending output{std::move(*temporary_), target_, message_, refusal_, false};
  temporary_.reset();
  if (t_batch_open) {
    t_pending.push_back(std::move(output));
    return;
  }
  const auto lock = Registry::get().hold();
  if (const std::string error = commit_one(output); !error.empty()) throw InputError(error);
}

namespace {

/// One scan of refuse_unless_own_folder. An entry that vanishes while scanned is skipped: the
/// folder is being replaced or emptied by someone else, and what is left decides.
std::string scan_own_folder(const fs::path& folder, const std::string& marker,
                            const std::function<bool(const std::string&)>& own_name,
                            std::string_view kind) {
  const std::string refused = "exists and is not " + std::string(kind) + " written by Cover (";
  const std::string advice = "); remove it or name another folder";
  std::error_code error;
  bool marked = false, empty = true;
  for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    std::error_code status_error;
    const fs::file_status status = it->symlink_status(status_error);
    if (status_error == std::errc::no_such_file_or_directory) continue;
    empty = false;
    if (status_error || !fs::is_regular_file(status) || !own_name(name))
      return refused + "it holds '" + name + "'" + advice;
    marked = marked || name == marker;
  }
  if (error == std::errc::no_such_file_or_directory) return {};
  if (error) return refused + error.message() + advice;
  if (!empty && !marked) return refused + "it has no " + marker + advice;
  return {};
}

}  // namespace

std::string refuse_unless_own_folder(const fs::path& folder, const std::string& marker,
                                     const std::function<bool(const std::string&)>& own_name,
                                     std::string_view kind) {
  // Another run writing the same folder swaps its new folder in and removes the old one, maybe
  // during the scan: a scan whose folder was swapped meanwhile (another inode at the path after
  // it) saw a folder being removed and is repeated, a few times at most.
  std::string why;
  for (int attempt = 0; attempt < 8; ++attempt) {
    struct stat before {
    }, after{};
    if (::stat(folder.c_str(), &before) != 0) return {};  // gone: nothing to refuse
    why = scan_own_folder(folder, marker, own_name, kind);
    if (why.empty()) return why;
    if (::stat(folder.c_str(), &after) == 0 && after.st_ino == before.st_ino &&
        after.st_dev == before.st_dev)
      return why;
  }
  return why;
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
    Registry::get().remove_all();
    ::signal(s, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, s);
    ::pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    ::raise(s);
  }).detach();
}

}  // namespace cover
