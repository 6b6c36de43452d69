#pragma once
// The cover:: exception family (STYLE.md §5).
//   InputError    — bad input (file contents, scene, usage). The CLI prints
//                   "cover: error: <what()>" and exits with status 2. what() already names the
//                   place: "FILE:LINE: message", "FILE: record N: message" or
//                   "scene.json: /json/path: message".
//   NotComputable — the request is valid but this build cannot answer it exactly (exit 2).
// Anything else escaping to main() is an internal failure (exit 1).

#include <stdexcept>
#include <string>

namespace cover {

/// Invalid input; the message names the file and the place in it.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A well-formed request that cannot be answered without a wrong or inexact result.
class NotComputable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace cover
