// libFuzzer target for the JSON scene loader (no mesh files: leaves that name files fail with
// an InputError like any missing file).
#include <cstddef>
#include <cstdint>
#include <string>

#include "cover/io/scene.h"
#include "cover/solid/errors.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const cover::LoadedInput in = cover::parse_scene(text, "/nonexistent/fuzz.json");
    if (in.solid.leaves.empty()) __builtin_trap();
  } catch (const cover::InputError&) {
  }
  return 0;
}
