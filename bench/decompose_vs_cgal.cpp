// `cover decompose` against CGAL's convex_decomposition_3, in one process on the same meshes:
//   Cover: brep::decompose (reflex-edge plane cuts, exact hulls; all threads for the hulls),
//          median of 3 runs.
//   CGAL:  Nef_polyhedron_3<Epeck> built from the same triangles (one Nef per connected shell,
//          combined by symmetric difference so that cavities subtract), then convex_decomposition_3
//          (one run: Nef polyhedra are slow); the pieces are the marked volumes after it.
// Prints pieces, seconds and volume for both, and Cover's reflex-edge and cut counts.
// Usage: decompose_vs_cgal MESH...   (e.g. models/*.off, libcgal-demo data/meshes/cross.off)
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_decomposition_3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <vector>

#include "cover/brep/decompose.h"
#include "cover/io/mesh_io.h"
#include "cover/mesh/triangulate.h"
#include "cover/solid/measure.h"
#include "cover/solid/union_find.h"

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Nef = CGAL::Nef_polyhedron_3<K>;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// One Surface_mesh per connected component of the triangulated mesh.
std::vector<Mesh> to_cgal(const cover::PolygonMesh& m) {
  std::vector<std::array<uint32_t, 3>> tris, all;
  const std::span<const cover::Vec3> pts(m.vertices.data(), m.vertices.size());
  for (size_t f = 0; f < m.face_count(); ++f) {
    tris.clear();
    cover::triangulate_face(pts, m.face(f), tris);
    all.insert(all.end(), tris.begin(), tris.end());
  }
  cover::UnionFind uf(m.vertices.size());
  for (const auto& t : all) {
    uf.unite(t[0], t[1]);
    uf.unite(t[0], t[2]);
  }
  std::map<uint32_t, Mesh> parts;
  std::map<uint32_t, std::map<uint32_t, Mesh::Vertex_index>> index;
  for (const auto& t : all) {
    const uint32_t root = uf.find(t[0]);
    Mesh& out = parts[root];
    auto& ids = index[root];
    Mesh::Vertex_index v[3];
    for (int k = 0; k < 3; ++k) {
      auto it = ids.find(t[k]);
      if (it == ids.end()) {
        const cover::Vec3& p = m.vertices[t[k]];
        it = ids.emplace(t[k], out.add_vertex(K::Point_3(p.x, p.y, p.z))).first;
      }
      v[k] = it->second;
    }
    out.add_face(v[0], v[1], v[2]);
  }
  std::vector<Mesh> out;
  for (auto& [root, mesh] : parts) out.push_back(std::move(mesh));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::printf(
      "| model | faces | reflex edges | Cover pieces | Cover s | CGAL pieces | CGAL s "
      "(Nef build + decomposition) | Cover / CGAL time |\n|---|---|---|---|---|---|---|---|\n");
  for (int i = 1; i < argc; ++i) {
    const std::filesystem::path path = argv[i];
    const cover::PolygonMesh m = cover::read_mesh(path);
    std::vector<double> times;
    cover::brep::DecomposeResult r;
    for (int run = 0; run < 3; ++run) {
      const auto t = Clock::now();
      r = cover::brep::decompose(m);
      times.push_back(since(t));
    }
    std::sort(times.begin(), times.end());
    const double cover_s = times[1];

    const std::vector<Mesh> shells = to_cgal(m);
    const auto t0 = Clock::now();
    // Shells combined by symmetric difference: nested shells (a cavity) subtract, apart ones add.
    Nef nef(shells[0]);
    for (size_t k = 1; k < shells.size(); ++k) nef ^= Nef(shells[k]);
    const double build_s = since(t0);
    const auto t1 = Clock::now();
    CGAL::convex_decomposition_3(nef);
    const double decompose_s = since(t1);
    long cgal_pieces = 0;
    for (auto ci = ++nef.volumes_begin(); ci != nef.volumes_end(); ++ci)
      if (ci->mark()) ++cgal_pieces;
    const double cgal_s = build_s + decompose_s;
    std::printf("| %s | %zu | %lld | %zu | %.3f | %ld | %.2f (%.2f + %.2f) | %.3f |\n",
                path.filename().string().c_str(), m.face_count(),
                static_cast<long long>(r.reflex_edges), r.pieces.size(), cover_s, cgal_pieces,
                cgal_s, build_s, decompose_s, cover_s / cgal_s);
    std::fflush(stdout);
  }
  return 0;
}
