#pragma once
// Atomic output files: nothing the user had is lost when a write fails (CONTRACT.md).

#include <filesystem>
#include <functional>
#include <string_view>

namespace cover {

/// Runs write(temporary) on a sibling PATH.tmp-PID and renames it onto `path`. Throws InputError
/// "PATH: cannot write WHAT" when write returns false or the rename fails; the temporary is
/// removed on every failure (exceptions from `write` included, then rethrown).
void write_atomically(const std::filesystem::path& path,
                      const std::function<bool(const std::filesystem::path& temporary)>& write,
                      std::string_view what);

}  // namespace cover
