#pragma once
// Atomic, transactional output files (docs/cli.md#conventions-of-every-command): nothing the user
// had is lost when a write fails, and the outputs of one command appear together or not at all.
//   target     the file a path finally names: symbolic links are followed, so writing through a
//              link replaces the file it points to and the link survives.
//   temporary  TARGET.tmp-PID-K in the target's folder (K counts the process's temporaries), so
//              that the final rename stays on one file system. Before the rename it gets the
//              mode of the file it replaces; a new file keeps the writer's 0666 & ~umask.
//   batch      while an OutputBatch is open on the calling thread, write_atomically() leaves the
//              finished temporary in place; commit() renames every one, all or nothing.
//   folders    an output folder (OutputFolder) is built in a temporary folder TARGET.tmp-PID-K
//              beside its target and swapped in whole (one renameat2 RENAME_EXCHANGE), so it
//              never mixes files of two runs and keeps none of an earlier one; the old folder is
//              then removed. An existing target is replaced only when it is an empty folder or
//              one the command's `refusal` check accepts as its own earlier output.
//   signals    every temporary (batched or not, file or folder) is registered until it is
//              renamed or removed; after remove_temporaries_on_signals(), SIGINT / SIGTERM /
//              SIGHUP remove them all before the process ends by that signal.

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace cover {
namespace detail {
class Temporary;
}  // namespace detail

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

/// An output folder (RAII): its files are written into path(), a temporary folder beside the
/// target, and commit() swaps it in whole, or, inside an OutputBatch, hands it to the batch
/// (which swaps it after the files written before its commit(), so write them first).
///   OutputFolder folder(dir, "the pieces", own_pieces);
///   write_mesh(folder.path() / "piece_0000.off", m);  folder.commit();
class OutputFolder {
 public:
  /// Follows `path`'s links to the target folder (the links survive). \throws InputError
  /// "PATH: exists and is not a folder", "PATH: REFUSAL" when the target is a folder that
  /// `refusal` (a reason, or "" to allow its replacement) refuses, "PATH: cannot write WHAT
  /// (reason)" when the temporary folder cannot be made. `refusal` is not called for a path
  /// that does not exist; it is called again when committing.
  OutputFolder(const std::filesystem::path& path, std::string_view what,
               std::function<std::string(const std::filesystem::path& folder)> refusal);
  /// Without commit(): removes the temporary folder; the target is not touched.
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  /// The temporary folder to write into (until commit()).
  const std::filesystem::path& path() const;
  /// Swaps the folder in (the old one is removed), or hands it to the open batch. \throws
  /// InputError "PATH: cannot write WHAT (reason)", the target left as it was.
  void commit();

 private:
  std::string name_, message_;
  std::filesystem::path target_;
  std::function<std::string(const std::filesystem::path&)> refusal_;
  std::unique_ptr<detail::Temporary> temporary_;  ///< the folder until commit()
};

/// The usual refusal of an OutputFolder: "" (replaceable) for an empty folder, or for one that
/// holds `marker` and only regular files whose names `own_name` accepts; otherwise "exists and is
/// not KIND written by Cover (...); remove it or name another folder", naming the missing marker
/// or the first other entry.
std::string refuse_unless_own_folder(const std::filesystem::path& folder, const std::string& marker,
                                     const std::function<bool(const std::string&)>& own_name,
                                     std::string_view kind);

/// Blocks SIGINT, SIGTERM and SIGHUP (those not ignored at the call) in the calling thread and
/// starts a thread that waits for them: it removes every registered temporary, then ends the
/// process by the same signal (default action, so the exit status reports it). Call once, first
/// in main(), before any other thread starts: threads inherit the blocked mask.
void remove_temporaries_on_signals();

}  // namespace cover
