#pragma once
// The cover:: exception family, after pmp-library's exceptions.h: a few types, each
// derived from the std exception that names its kind, and each kind of error always thrown as
// the same type. Public functions document what they throw with \throws.
//   InputError         (std::runtime_error) bad input: file contents, scene, arrays, options.
//                      what() names the place: "FILE:LINE: message", "FILE: record N: message",
//                      "scene.json: /json/path: message", "resolution: message". A parameter is
//                      named as the C++ API spells it (an options field), marked with
//                      parameter(): the CLI shows its flag instead ("--res: message"), Python
//                      its keyword ("res: message"); InputError::text renders either. The CLI
//                      prints "cover: error: <message>" and exits with status 2.
//   NotComputable      (std::runtime_error) a well-formed request that this build cannot answer
//                      without a wrong or inexact result (exit 2).
//   PreconditionError  (std::logic_error) a caller broke a documented precondition of a public
//                      function (a programming error in the caller).
//   InternalError      (std::logic_error) an invariant of Cover's own failed: a bug in Cover.
//                      COVER_ASSERT throws it; so do the checks that stay on in every build.
// std::bad_alloc stays what it is (memory). Anything else escaping to the CLI's main() is an
// internal failure (exit 1). A public function documents with \throws what it throws beyond
// std::bad_alloc and InternalError, and with \pre what it does not check; one without \throws
// throws only those two.

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cover {

/// `name`, a parameter as the C++ API spells it ("resolution", "max_memory"), marked inside an
/// InputError message so that each front end can show its own name for it (InputError::text).
std::string parameter(std::string_view name);

/// `marked` with every parameter() mark shown as `name_of(name)`, or as its C++ name when
/// `name_of` is empty: how a front end shows a warning (Model::warnings) or an error's text.
std::string show_parameters(std::string_view marked,
                            const std::function<std::string(std::string_view)>& name_of = {});

/// Invalid input; the message names the file and the place in it, or the parameter.
class InputError : public std::runtime_error {
 public:
  /// `message` may hold parameter() marks; what() shows each parameter's C++ name.
  explicit InputError(const std::string& message);
  /// The message with every marked parameter shown as `name_of(name)`.
  std::string text(const std::function<std::string(std::string_view)>& name_of) const;
  /// The same error with `prefix` before its message (marks kept): "FILE: " + message.
  InputError prefixed(const std::string& prefix) const;

 private:
  std::shared_ptr<const std::string> marked_;  ///< the message with its marks (copies share it)
};

/// A well-formed request that cannot be answered without a wrong or inexact result.
class NotComputable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A violated precondition of a public function.
class PreconditionError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// A violated internal invariant (a bug in Cover).
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

namespace detail {
[[noreturn]] inline void assert_failed(const char* condition, const char* file, int line) {
  throw InternalError(std::string(file) + ":" + std::to_string(line) +
                      ": internal invariant failed: " + condition);
}
}  // namespace detail

}  // namespace cover

/// COVER_ASSERT(condition): checks an internal invariant in Debug builds (no NDEBUG) and in the
/// checked build (COVER_CHECKED, set with COVER_SANITIZE), throwing InternalError naming the
/// file, line and condition; compiled out of Release builds (the condition is not evaluated).
/// For invariants whose check is cheap and whose failure would give a wrong answer, throw
/// InternalError unconditionally instead.
#if !defined(NDEBUG) || defined(COVER_CHECKED)
#define COVER_ASSERT(condition) \
  ((condition) ? void(0) : ::cover::detail::assert_failed(#condition, __FILE__, __LINE__))
#else
#define COVER_ASSERT(condition) ((void)0)
#endif
