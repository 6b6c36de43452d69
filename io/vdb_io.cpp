// OpenVDB export (io/vdb_io.h). OpenVDB itself lives in the plugin cover_vdb.so
// (io/vdb_plugin.h says why), opened here on the first .vdb write and kept open. Where it is
// looked for, in order:
//   $COVER_PLUGIN_DIR                         a user's override
//   <program folder>/COVER_PLUGIN_RELDIR      the build tree (build/bin → build/lib/cover) and
//                                             an installed tree (bin → lib/cover), wherever moved
//   <folder of the binary holding this code>/COVER_PLUGIN_RELDIR   the same for a shared object
//   COVER_PLUGIN_INSTALL_DIR                  the configured install folder (consumers' programs)

#include "cover/io/vdb_io.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/io/vdb_plugin.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPluginName = "cover_vdb.so";

struct Plugin {
  CoverVdbWriteFn write = nullptr;
  std::string error;  // why there is none
};

std::vector<fs::path> plugin_folders() {
  std::vector<fs::path> folders;
  if (const char* dir = std::getenv("COVER_PLUGIN_DIR"); dir && *dir) folders.emplace_back(dir);
#if defined(COVER_PLUGIN_RELDIR)
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) folders.push_back(exe.parent_path() / COVER_PLUGIN_RELDIR);
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&write_vdb), &info) != 0 && info.dli_fname != nullptr) {
    const fs::path self = fs::weakly_canonical(info.dli_fname, ec);
    if (!ec) folders.push_back(self.parent_path() / COVER_PLUGIN_RELDIR);
  }
#endif
#if defined(COVER_PLUGIN_INSTALL_DIR)
  folders.emplace_back(COVER_PLUGIN_INSTALL_DIR);
#endif
  std::vector<fs::path> unique;  // each folder once, first place kept
  for (const fs::path& f : folders)
    if (std::find(unique.begin(), unique.end(), f.lexically_normal()) == unique.end())
      unique.push_back(f.lexically_normal());
  return unique;
}

Plugin load_plugin() {
  Plugin p;
  std::string looked;
  for (const fs::path& folder : plugin_folders()) {
    const fs::path file = (folder / kPluginName).lexically_normal();
    looked += (looked.empty() ? "" : ", ") + file.string();
    std::error_code ec;
    if (!fs::exists(file, ec)) continue;
    void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      p.error = "cannot load " + file.string() + ": " + (why ? why : "dlopen failed");
      return p;
    }
    auto version = reinterpret_cast<CoverVdbVersionFn>(dlsym(handle, "cover_vdb_plugin_version"));
    auto write = reinterpret_cast<CoverVdbWriteFn>(dlsym(handle, "cover_vdb_write"));
    if (version == nullptr || write == nullptr || version() != COVER_VDB_PLUGIN_VERSION) {
      p.error = file.string() + " is not this Cover's OpenVDB plugin (another version)";
      return p;
    }
    p.write = write;
    return p;
  }
  p.error = "Cover's OpenVDB plugin " + std::string(kPluginName) + " was not found (looked for " +
            looked + "; set COVER_PLUGIN_DIR to its folder, or build Cover with libopenvdb-dev)";
  return p;
}

const Plugin& plugin() {
  static std::once_flag once;
  static Plugin p;
  std::call_once(once, [] { p = load_plugin(); });
  return p;
}

}  // namespace

bool is_vdb_extension(const fs::path& path) { return lower_extension(path) == ".vdb"; }

void write_vdb(const fs::path& path, const VoxelGrid& grid) {
  if (!grid.whole() || grid.bits.size() != grid.word_count())
    throw PreconditionError("write_vdb: a whole grid expected");
  const Plugin& p = plugin();
  if (p.write == nullptr) throw InputError(path.string() + ": .vdb output: " + p.error);
  const VoxelLattice& l = grid.lattice;
  const CoverVdbGrid g{{l.origin.x, l.origin.y, l.origin.z},
                       l.spacing,
                       {grid.nx(), grid.ny(), grid.nz()},
                       grid.words_per_column(),
                       grid.bits.data()};
  write_atomically(
      path,
      [&](const fs::path& temporary) {
        char message[512] = {};
        if (p.write(&g, temporary.c_str(), message, sizeof message) == 0) return true;
        throw InputError(path.string() + ": cannot write the voxels (" + message + ")");
      },
      "the voxels");
}

}  // namespace cover
