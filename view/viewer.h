#pragma once
// `cover view`: a local web server and page that show Cover's own exact frames of one loaded
// input (docs/viewer.md). The page asks for frames (render/render.h, PNG from io/png.h: the bytes
// `cover render` writes for the same view), picks (the point under a pixel, its exact class and
// its leaf) and the leaf list; the server reloads the input when it or a file it names changes
// on disk, keeping the page's view. Leaves hidden on the page are left out of the scene, as if
// their nodes were not in it (an operation left without operands goes too).
// Security: it listens on 127.0.0.1 by default; every request must carry the random token of the
// URL it prints (`t=`), and a loopback server answers only Host headers that name loopback.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cover/io/scene.h"

namespace cover {

struct ViewerOptions {
  std::string host = "127.0.0.1";  ///< the interface to listen on
  int port = 0;                    ///< 0: a free port chosen by the system
  LoadOptions load;                ///< how the input is loaded and reloaded
  double poll_seconds = 0.5;       ///< how often the files are checked for changes
  /// The largest frame side the server renders (pixels) and the memory a frame may take
  /// (render_bytes); larger requests are refused with a message.
  int max_side = 4096;
  uint64_t max_memory_bytes = kDefaultMaxMemoryBytes;
};

/// What a viewer shows: the version that counts reloads and the last reload's error.
struct ViewerState {
  uint64_t version = 1;  ///< 1 after the first load, + 1 on each successful reload
  std::string error;     ///< the last failed reload's message (the previous input stays shown)
};

class Viewer {
 public:
  /// Loads `input` (a mesh or scene, as load_input) and starts serving on a thread of its own.
  /// \throws InputError for an input that does not load, or a host/port that cannot be bound.
  Viewer(std::filesystem::path input, ViewerOptions options = {});
  ~Viewer();  ///< stop()
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  /// The page's address with its token, e.g. http://127.0.0.1:8765/?t=3f...
  std::string url() const;
  int port() const;
  const std::string& token() const;
  ViewerState state() const;
  /// The load warnings of the input shown (Model::warnings).
  std::vector<std::string> warnings(
      const std::function<std::string(std::string_view)>& name_of = {}) const;
  /// Checks the watched files now and reloads on a change (the poll thread calls it);
  /// returns true when a reload happened, successful or not.
  bool check_files();
  /// Stops serving and watching; idempotent.
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The page the viewer serves (HTML with its script and style inline).
const std::string& viewer_page();

}  // namespace cover
