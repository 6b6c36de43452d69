// libFuzzer target for the mesh readers. One binary per format (COVER_FUZZ_FORMAT selects the
// reader at compile time); the whole input is the file contents. Anything but a clean parse or a
// cover::InputError is a finding (crash, sanitizer report, timeout, or an allocation over
// libFuzzer's -malloc_limit_mb).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cover/io/parse.h"
#include "cover/io/scene.h"
#include "cover/solid/errors.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const cover::PolygonMesh mesh = cover::detail::COVER_FUZZ_READER("fuzz-input", bytes);
    // Every index a reader returns must be in range.
    for (uint32_t v : mesh.face_vertices)
      if (v >= mesh.vertices.size()) __builtin_trap();
    // The leaf preparation every command runs (range check, loop collapse, re-orientation).
    std::vector<std::string> warnings;
    cover::prepare_leaf(mesh, "fuzz-input", "fuzz-input", cover::LoadOptions{}, warnings);
  } catch (const cover::InputError&) {
  }
  return 0;
}
