// Cover's uniform subdivision (subdivision/subdivide.h) vs CGAL's Subdivision_method_3 and, with
// -DCOVER_SUBDIVISION_PEERS=ON, OpenSubdiv Far (uniform refinement + PrimvarRefiner, one thread)
// and OpenMesh's uniform subdividers, in one process: Catmull–Clark and Loop, levels 1–3.
// Every side starts from the same in-memory mesh (file reading excluded). Cover: subdivide()
// from the PolygonMesh (its half-edge view included) on 1 and 2 threads. CGAL, OpenMesh: a copy
// of their mesh built beforehand (the conversion excluded, the copy included) and its subdivision.
// OpenSubdiv: the topology refiner built from the face arrays, uniform refinement and the
// interpolation of the double positions through every level. Timings: median of --repeat runs
// (default 3), interleaved (every configuration once per round). Usage: subdivide_vs_peers MESH
// [--repeat R] [--levels L]
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/parallel.h"
#include "cover/subdivision/subdivide.h"

#ifdef COVER_SUBDIVISION_PEERS
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#endif

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using bench::Clock;
using bench::since;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

SurfaceMesh to_surface_mesh(const cover::PolygonMesh& m) {
  SurfaceMesh s;
  for (const cover::Vec3& p : m.vertices) s.add_vertex(Kernel::Point_3(p.x, p.y, p.z));
  std::vector<SurfaceMesh::Vertex_index> f;
  for (size_t i = 0; i < m.face_count(); ++i) {
    f.clear();
    for (uint32_t k : m.face(i)) f.push_back(SurfaceMesh::Vertex_index(k));
    s.add_face(f);
  }
  return s;
}

#ifdef COVER_SUBDIVISION_PEERS
struct OmTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using OmPoly = OpenMesh::PolyMesh_ArrayKernelT<OmTraits>;
using OmTri = OpenMesh::TriMesh_ArrayKernelT<OmTraits>;

template <class Mesh>
Mesh to_openmesh(const cover::PolygonMesh& m) {
  Mesh s;
  std::vector<typename Mesh::VertexHandle> v;
  for (const cover::Vec3& p : m.vertices) v.push_back(s.add_vertex({p.x, p.y, p.z}));
  std::vector<typename Mesh::VertexHandle> f;
  for (size_t i = 0; i < m.face_count(); ++i) {
    f.clear();
    for (uint32_t k : m.face(i)) f.push_back(v[k]);
    s.add_face(f);
  }
  return s;
}

struct OsdVertex {
  double p[3];
  void Clear() { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const OsdVertex& s, float w) {
    for (int k = 0; k < 3; ++k) p[k] += w * s.p[k];
  }
};

/// OpenSubdiv Far: refiner from the arrays, uniform refinement, positions through every level.
size_t opensubdiv(const cover::PolygonMesh& m, bool loop, int levels) {
  using namespace OpenSubdiv;
  using Descriptor = Far::TopologyDescriptor;
  std::vector<int> sizes(m.face_count());
  for (size_t f = 0; f < m.face_count(); ++f) sizes[f] = static_cast<int>(m.face(f).size());
  Descriptor d;
  d.numVertices = static_cast<int>(m.vertices.size());
  d.numFaces = static_cast<int>(m.face_count());
  d.numVertsPerFace = sizes.data();
  d.vertIndicesPerFace = reinterpret_cast<const Far::Index*>(m.face_vertices.data());
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  Far::TopologyRefiner* refiner = Far::TopologyRefinerFactory<Descriptor>::Create(
      d, Far::TopologyRefinerFactory<Descriptor>::Options(
             loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, options));
  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
  std::vector<OsdVertex> buffer(refiner->GetNumVerticesTotal());
  for (size_t i = 0; i < m.vertices.size(); ++i)
    buffer[i] = {{m.vertices[i].x, m.vertices[i].y, m.vertices[i].z}};
  Far::PrimvarRefiner primvar(*refiner);
  OsdVertex* src = buffer.data();
  for (int level = 1; level <= levels; ++level) {
    OsdVertex* dst = src + refiner->GetLevel(level - 1).GetNumVertices();
    primvar.Interpolate(level, src, dst);
    src = dst;
  }
  const size_t n = static_cast<size_t>(refiner->GetLevel(levels).GetNumVertices());
  delete refiner;
  return n;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: subdivide_vs_peers MESH [--repeat R] [--levels L]\n");
    return 2;
  }
  int repeat = 3, max_level = 3;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--repeat")) repeat = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--levels")) max_level = std::atoi(argv[i + 1]);
  }
  const cover::PolygonMesh mesh = cover::read_mesh(argv[1]);
  const SurfaceMesh cgal_mesh = to_surface_mesh(mesh);
#ifdef COVER_SUBDIVISION_PEERS
  const OmPoly om_poly = to_openmesh<OmPoly>(mesh);
  const OmTri om_tri = to_openmesh<OmTri>(mesh);
#endif
  std::printf("%s: %zu vertices, %zu faces; median of %d interleaved runs, seconds\n", argv[1],
              mesh.vertices.size(), mesh.face_count(), repeat);
  // name -> function returning the output vertex count.
  std::vector<std::pair<std::string, std::function<size_t(bool, int)>>> sides;
  for (int threads : {1, 2})
    sides.push_back({"cover " + std::to_string(threads) + "t", [&, threads](bool loop, int level) {
                       cover::ThreadLimit limit(threads);
                       cover::SubdivideOptions o;
                       o.scheme = loop ? cover::Scheme::kLoop : cover::Scheme::kCatmullClark;
                       o.levels = level;
                       return cover::subdivide(mesh, o).vertices.size();
                     }});
  sides.push_back({"CGAL", [&](bool loop, int level) {
                     SurfaceMesh s = cgal_mesh;
                     const auto np = CGAL::parameters::number_of_iterations(level);
                     if (loop)
                       CGAL::Subdivision_method_3::Loop_subdivision(s, np);
                     else
                       CGAL::Subdivision_method_3::CatmullClark_subdivision(s, np);
                     return static_cast<size_t>(s.number_of_vertices());
                   }});
#ifdef COVER_SUBDIVISION_PEERS
  sides.push_back(
      {"OpenSubdiv 1t", [&](bool loop, int level) { return opensubdiv(mesh, loop, level); }});
  sides.push_back({"OpenMesh", [&](bool loop, int level) -> size_t {
                     if (loop) {
                       OmTri s = om_tri;
                       OpenMesh::Subdivider::Uniform::LoopT<OmTri> sub;
                       sub.attach(s);
                       sub(level);
                       sub.detach();
                       return s.n_vertices();
                     }
                     OmPoly s = om_poly;
                     OpenMesh::Subdivider::Uniform::CatmullClarkT<OmPoly> sub;
                     sub.attach(s);
                     sub(level);
                     sub.detach();
                     return s.n_vertices();
                   }});
#endif
  std::printf("%-6s %-5s", "scheme", "level");
  for (const auto& s : sides) std::printf(" %14s", s.first.c_str());
  std::printf("   output vertices\n");
  for (bool loop : {false, true})
    for (int level = 1; level <= max_level; ++level) {
      std::map<std::string, std::vector<double>> times;
      std::map<std::string, size_t> counts;
      for (int r = 0; r < repeat; ++r)
        for (const auto& [name, run] : sides) {
          const Clock::time_point t = Clock::now();
          counts[name] = run(loop, level);
          times[name].push_back(since(t));
        }
      std::printf("%-6s %-5d", loop ? "Loop" : "CC", level);
      for (const auto& s : sides) std::printf(" %14.4f", median(times[s.first]));
      std::printf("  ");
      for (const auto& s : sides) std::printf(" %zu", counts[s.first]);
      std::printf("\n");
      std::fflush(stdout);
    }
  return 0;
}
