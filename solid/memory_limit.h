#pragma once
// The memory limit of every command (`--max-memory`, docs/cli.md#conventions-of-every-command), and
// input reading that honours it. Conventions: limits and estimates are in bytes; messages state
// them in MiB (the estimate rounded up) and name the option, so that a refusal reads the same
// everywhere:
//   "WHAT needs N MiB, over --max-memory M MiB"
// An estimate is checked before the allocation it predicts; inputs are read only from regular
// files (whose size is known before reading) or from a stream cut off at the limit.

#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>
#include <string_view>

#include "cover/solid/large_vector.h"

namespace cover {

/// The one default of --max-memory (every command, and the library's readers), in MiB.
inline constexpr uint64_t kDefaultMaxMemoryMiB = 4096;
inline constexpr uint64_t kDefaultMaxMemoryBytes = kDefaultMaxMemoryMiB << 20;

/// Throws InputError "WHAT needs N MiB, over --max-memory M MiB" when estimate_bytes exceeds
/// limit_bytes. `estimate_bytes` is a double so that products of large counts cannot wrap.
void check_memory(double estimate_bytes, uint64_t limit_bytes, const std::string& what);

/// The bytes of an input, read into a buffer on huge pages that is not zero-filled first: zero
/// filling 4 KiB pages would cost ~40 ms of first-touch page faults for a 62 MB points file
/// (solid/large_vector.h).
class FileBytes {
 public:
  std::string_view view() const { return {bytes_.data(), size_}; }
  operator std::string_view() const { return view(); }  // NOLINT: a view of the bytes
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

 private:
  friend FileBytes read_regular_file(const std::filesystem::path&, uint64_t);
  friend FileBytes read_stream(std::istream&, uint64_t, const std::string&);
  LargeBuffer<char> bytes_;  ///< capacity ≥ size_; bytes past size_ are indeterminate
  size_t size_ = 0;
};

/// The whole contents of the regular file `path` (symbolic links followed). Throws InputError
/// "FILE: cannot open: reason" / "FILE: cannot read: reason", "FILE: not a regular file" (FIFO,
/// device, directory, socket: refused before any byte is read, without blocking), and the
/// check_memory() message "FILE: the file needs N MiB, ..." for a file larger than `max_bytes`
/// (refused before reading).
FileBytes read_regular_file(const std::filesystem::path& path, uint64_t max_bytes);

/// The rest of `in` (e.g. std::cin), read in blocks; throws InputError "NAME: the input needs N
/// MiB, over --max-memory M MiB" (N: what was read so far) as soon as it exceeds `max_bytes`, and
/// "NAME: cannot read" on a stream error.
FileBytes read_stream(std::istream& in, uint64_t max_bytes, const std::string& name);

}  // namespace cover
