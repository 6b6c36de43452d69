#pragma once
// Atomic, transactional output files (CONTRACT.md "Output conventions"): nothing the user had is
// lost when a write fails, and the outputs of one command appear together or not at all.
//   target     the file a path finally names: symbolic links are followed, so writing through a
//              link replaces the file it points to and the link survives.
//   temporary  TARGET.tmp-PID-K in the target's folder (K counts the process's temporaries), so
//              that the final rename stays on one file system. Before the rename it gets the
//              mode of the file it replaces; a new file keeps the writer's 0666 & ~umask.
//   batch      while an OutputBatch is open on the calling thread, write_atomically() leaves the
//              finished temporary in place; commit() renames every one, all or nothing.
//   signals    every temporary (batched or not) is registered until it is renamed or removed;
//              after remove_temporaries_on_signals(), SIGINT / SIGTERM / SIGHUP remove them all
//              before the process ends by that signal.

#include <filesystem>
#include <functional>
#include <string_view>

namespace cover {

/// Runs write(temporary) on a fresh temporary for `path`'s target and renames it onto the
/// target, or, inside an OutputBatch, hands it to the batch. Throws InputError "PATH: cannot
/// write WHAT" when write returns false, with " (reason)" when giving it the target's mode or the
/// rename fails; the temporary is removed on every failure (exceptions from `write` included,
/// then rethrown).
void write_atomically(const std::filesystem::path& path,
                      const std::function<bool(const std::filesystem::path& temporary)>& write,
                      std::string_view what);

/// The outputs of one command (RAII). Opened before the first write, committed after the last:
///   OutputBatch batch;  write_png_rgb(...);  write_png_gray16(...);  batch.commit();
/// A batch opened while another is open on the same thread joins it: its commit() and its
/// destructor do nothing, and the outermost batch commits or discards everything.
class OutputBatch {
 public:
  OutputBatch();
  /// Without commit(): removes every temporary; no target is touched.
  ~OutputBatch();
  OutputBatch(const OutputBatch&) = delete;
  OutputBatch& operator=(const OutputBatch&) = delete;

  /// Renames every temporary onto its target, in the order written (a target written twice
  /// ends with the later contents). Targets that a later rename could still have to restore are
  /// first kept as hard links (a copy where the file system has none), so when a rename fails
  /// the targets already replaced get their old contents back (new ones are removed), the
  /// remaining temporaries are removed, and InputError "PATH: cannot write WHAT (reason)" names
  /// the failed output.
  /// Closes the batch either way: later writes on the thread are no longer batched.
  void commit();

 private:
  bool open_;  ///< this object opened the thread's batch and has not committed it
};

/// Blocks SIGINT, SIGTERM and SIGHUP (those not ignored at the call) in the calling thread and
/// starts a thread that waits for them: it removes every registered temporary, then ends the
/// process by the same signal (default action, so the exit status reports it). Call once, first
/// in main(), before any other thread starts: threads inherit the blocked mask.
void remove_temporaries_on_signals();

}  // namespace cover
