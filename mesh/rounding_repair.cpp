// Rounding repair by edge collapse (rounding_repair.h has the contract).
//
// Notation: a loop is one face's vertex cycle; `around[v]` lists the faces that use v (it may
// hold faces dropped since: they are skipped). For the kept vertex b of a collapse, a face F
// around b enters b from in(F) (the corner before b) and leaves it to out(F) (the corner after):
// the faces around b form one fan exactly when each in and each out occurs once and stepping
// from F to the face G with in(G) == out(F) (the face across the edge b → out(F)) visits them all.
#include "cover/mesh/rounding_repair.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include "cover/mesh/validate.h"
#include "cover/solid/predicates.h"

namespace cover {
namespace {

constexpr int kMaxRounds = 16;

class Collapser {
 public:
  Collapser(PolygonMesh& mesh, std::span<const uint8_t> rounded)
      : mesh_(mesh), flag_(mesh.vertices.size(), 0), around_(mesh.vertices.size()) {
    std::copy_n(rounded.begin(), std::min(rounded.size(), flag_.size()), flag_.begin());
    loops_.resize(mesh.face_count());
    for (uint32_t f = 0; f < mesh.face_count(); ++f) {
      const auto loop = mesh.face(f);
      loops_[f].assign(loop.begin(), loop.end());
      for (uint32_t v : loop) around_[v].push_back(f);
    }
    alive_.assign(loops_.size(), 1);
    double scale = 0;
    for (const Vec3& p : mesh.vertices)
      scale = std::max({scale, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    const double limit = scale * kMaxCollapseRelative;
    limit2_ = limit * limit;
  }

  /// One round: collapses the shortest allowed edges of the faces in `pairs`, at most one
  /// collapse per neighbourhood. Returns how many were made.
  int64_t round(const std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
    // Candidates: the edges of the faces around the corners of the meeting faces (a face of
    // zero area, e.g. with two corners at one point, tiles into nothing and is never reported
    // itself: its neighbour is).
    std::vector<std::tuple<double, uint32_t, uint32_t>> edges;
    for (const auto& [f, g] : pairs)
      for (uint32_t face : {f, g})
        for (uint32_t corner : loops_[face])
          for (uint32_t h : around_[corner]) {
            if (!alive_[h]) continue;
            const auto& loop = loops_[h];
            for (size_t i = 0; i < loop.size(); ++i) {
              const uint32_t x = loop[i], y = loop[(i + 1) % loop.size()];
              const Vec3 d = mesh_.vertices[x] - mesh_.vertices[y];
              const double len2 = dot(d, d);
              if (len2 <= limit2_) edges.emplace_back(len2, std::min(x, y), std::max(x, y));
            }
          }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::vector<uint32_t> touched;
    int64_t made = 0;
    for (const auto& [len2, x, y] : edges) {
      if (is_touched(x) || is_touched(y)) continue;
      // Keep the vertex that was not rounded (an input point), else the lower index.
      const bool keep_x = !flag_[x] || flag_[y];
      const uint32_t keep = keep_x ? x : y, drop = keep_x ? y : x;
      if (!collapse(drop, keep) && !collapse(keep, drop)) continue;
      ++made;
      const uint32_t kept = removed_.back() == drop ? keep : drop;
      for (uint32_t f : around_[kept])
        if (alive_[f])
          for (uint32_t v : loops_[f]) touch(v);
    }
    stamp_.clear();
    return made;
  }

  /// The mesh of the live faces; `origin` gets each face's index in the input.
  PolygonMesh current(std::vector<uint32_t>& origin) const {
    PolygonMesh out;
    out.vertices = mesh_.vertices;
    origin.clear();
    for (uint32_t f = 0; f < loops_.size(); ++f)
      if (alive_[f]) {
        out.add_face(loops_[f]);
        origin.push_back(f);
      }
    return out;
  }

  /// Faces (of current()) with a flagged vertex.
  std::vector<uint8_t> suspects(const std::vector<uint32_t>& origin) const {
    std::vector<uint8_t> s(origin.size(), 0);
    for (size_t i = 0; i < origin.size(); ++i)
      for (uint32_t v : loops_[origin[i]])
        if (flag_[v]) s[i] = 1;
    return s;
  }

  /// Writes the repaired mesh back: live faces in order, removed vertices dropped.
  void finish(RoundingRepair& out) {
    std::vector<uint8_t> gone(mesh_.vertices.size(), 0);
    for (uint32_t v : removed_) gone[v] = 1;
    std::vector<uint32_t> index(mesh_.vertices.size());
    std::vector<Vec3> vertices;
    for (uint32_t v = 0; v < mesh_.vertices.size(); ++v) {
      index[v] = static_cast<uint32_t>(vertices.size());
      if (!gone[v]) vertices.push_back(mesh_.vertices[v]);
    }
    PolygonMesh result;
    result.vertices = std::move(vertices);
    std::vector<uint32_t> loop;
    for (uint32_t f = 0; f < loops_.size(); ++f) {
      if (!alive_[f]) {
        ++out.dropped_faces;
        continue;
      }
      loop.clear();
      for (uint32_t v : loops_[f]) loop.push_back(index[v]);
      result.add_face(loop);
      out.face_origin.push_back(f);
    }
    mesh_ = std::move(result);
  }

 private:
  bool is_touched(uint32_t v) const { return stamp_.count(v) > 0; }
  void touch(uint32_t v) { stamp_.emplace(v, 1); }

  /// Removes vertex a, its faces using b instead, if the mesh stays a closed oriented 2-manifold
  /// around b (module comment). Returns whether it did.
  bool collapse(uint32_t a, uint32_t b) {
    struct Changed {
      uint32_t face;
      std::vector<uint32_t> loop;  ///< empty: dropped
    };
    std::vector<Changed> changed;
    std::vector<uint32_t> fan;  // live faces around b after the collapse
    for (uint32_t f : around_[a]) {
      if (!alive_[f]) continue;
      std::vector<uint32_t> loop;
      for (uint32_t v : loops_[f]) {
        const uint32_t w = v == a ? b : v;
        if (loop.empty() || loop.back() != w) loop.push_back(w);
      }
      while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
      if (std::count(loop.begin(), loop.end(), b) > 1) return false;
      if (loop.size() < 3) loop.clear();
      changed.push_back({f, std::move(loop)});
    }
    std::unordered_map<uint32_t, const std::vector<uint32_t>*> loop_of;
    for (const Changed& c : changed)
      if (!c.loop.empty()) loop_of[c.face] = &c.loop;
    for (uint32_t f : around_[b])
      if (alive_[f] && !loop_of.count(f) &&
          std::none_of(changed.begin(), changed.end(),
                       [&](const Changed& c) { return c.face == f; }))
        loop_of[f] = &loops_[f];
    // in/out corners of b per face; each must be unique, and the fan one cycle.
    std::unordered_map<uint32_t, uint32_t> by_in, by_out;
    std::vector<std::pair<uint32_t, uint32_t>> corners;  // (in, out) per face
    std::vector<std::vector<uint32_t>> sorted;
    for (const auto& [f, loop] : loop_of) {
      const auto& l = *loop;
      const size_t i = static_cast<size_t>(std::find(l.begin(), l.end(), b) - l.begin());
      const uint32_t in = l[(i + l.size() - 1) % l.size()], out = l[(i + 1) % l.size()];
      if (!by_in.emplace(in, static_cast<uint32_t>(corners.size())).second) return false;
      if (!by_out.emplace(out, static_cast<uint32_t>(corners.size())).second) return false;
      corners.push_back({in, out});
      std::vector<uint32_t> s = l;
      std::sort(s.begin(), s.end());
      sorted.push_back(std::move(s));
    }
    if (corners.size() < 3) return false;
    size_t steps = 0;
    uint32_t at = 0;
    do {
      const auto it = by_in.find(corners[at].second);
      if (it == by_in.end()) return false;
      at = it->second;
      ++steps;
    } while (at != 0 && steps <= corners.size());
    if (steps != corners.size()) return false;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
    // Apply.
    for (Changed& c : changed) {
      if (c.loop.empty()) {
        alive_[c.face] = 0;
        continue;
      }
      loops_[c.face] = std::move(c.loop);
      around_[b].push_back(c.face);
    }
    around_[a].clear();
    flag_[b] = 1;
    removed_.push_back(a);
    return true;
  }

  PolygonMesh& mesh_;
  std::vector<uint8_t> flag_;
  std::vector<std::vector<uint32_t>> around_;
  std::vector<std::vector<uint32_t>> loops_;
  std::vector<uint8_t> alive_;
  std::vector<uint32_t> removed_;
  std::unordered_map<uint32_t, uint8_t> stamp_;
  double limit2_ = 0;
};

/// The face pairs that meet (intersecting_face_pairs), plus (f, f) for each suspect face whose
/// vertices all lie on one line: a face of zero area that rounding made (its corners moved onto
/// one line) tiles into nothing, and its neighbours need not meet, but as written it is a
/// degenerate face, which a reader's self-intersection test reports.
std::vector<std::pair<uint32_t, uint32_t>> contacts(const PolygonMesh& mesh,
                                                    std::span<const uint8_t> suspect,
                                                    std::span<const uint32_t> group) {
  std::vector<std::pair<uint32_t, uint32_t>> pairs = intersecting_face_pairs(mesh, suspect, group);
  const size_t found = pairs.size();
  for (uint32_t f = 0; f < mesh.face_count(); ++f)
    if ((suspect.empty() || suspect[f]) && all_collinear(mesh.vertices, mesh.face(f)))
      pairs.push_back({f, f});
  if (pairs.size() > found) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  }
  return pairs;
}

}  // namespace

RoundingRepair repair_rounding(PolygonMesh& mesh, std::span<const uint8_t> rounded,
                               std::span<const uint32_t> group) {
  RoundingRepair out;
  std::vector<uint8_t> suspect(mesh.face_count(), 0);
  bool any = false;
  for (size_t f = 0; f < mesh.face_count(); ++f)
    for (uint32_t v : mesh.face(f))
      if (v < rounded.size() && rounded[v]) suspect[f] = 1, any = true;
  if (!any) return out;
  std::vector<std::pair<uint32_t, uint32_t>> pairs = contacts(mesh, suspect, group);
  if (pairs.empty()) return out;
  Collapser collapser(mesh, rounded);
  std::vector<uint32_t> origin(mesh.face_count());
  std::iota(origin.begin(), origin.end(), 0u);
  for (int r = 0; r < kMaxRounds && !pairs.empty(); ++r) {
    ++out.rounds;
    // Pairs are in current() numbering: back to the collapser's face indices.
    for (auto& [f, g] : pairs) f = origin[f], g = origin[g];
    const int64_t made = collapser.round(pairs);
    if (made == 0) break;
    out.collapsed_edges += made;
    const PolygonMesh now = collapser.current(origin);
    std::vector<uint32_t> now_group;
    if (!group.empty())
      for (uint32_t f : origin) now_group.push_back(group[f]);
    pairs = contacts(now, collapser.suspects(origin), now_group);
  }
  out.remaining_pairs = static_cast<int64_t>(pairs.size());
  if (out.collapsed_edges > 0) collapser.finish(out);
  return out;
}

}  // namespace cover
