// cover._cover: the Python bindings of cover::Model (docs/python.md). numpy in, numpy out; the
// conversions and the GIL / threads / Ctrl-C discipline are in arrays.h. The package cover/
// (__init__.py) re-exports everything and adds the load warnings; cover/__init__.pyi holds the
// stubs, which python/tests/test_stubs.py keeps equal to what this module defines.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

#include "arrays.h"
#include "cover/brep/halfedge.h"
#include "cover/mesh/repair.h"
#include "cover/mesh/validate.h"
#include "cover/model/info.h"
#include "cover/model/model.h"
#include "files.h"
#include "grids.h"
#include "modeling.h"
#include "viewer.h"

namespace py = pybind11;
using namespace pybind11::literals;
using cover::python::Interrupt;
using cover::python::KernelScope;

namespace cover::python {
namespace {

/// Points per kernel call between two Ctrl-C checks (results do not depend on it).
constexpr size_t kBatch = size_t{1} << 20;

using Threads = std::optional<int>;

/// Model::classify's check over all points at once, so that the index named is the caller's
/// (the kernel calls below see one batch each).
void check_finite(std::span<const Vec3> points, const char* what) {
  for (size_t i = 0; i < points.size(); ++i)
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y) || !std::isfinite(points[i].z))
      throw InputError(std::string(what) + ": point " + std::to_string(i) +
                       " has a non-finite coordinate");
}

/// A C++ parameter's Python keyword, for InputError messages (InputError::text).
std::string keyword(std::string_view name) {
  if (name == "resolution") return "res";
  if (name == "require_closed") return "closed_only";
  if (name == "crease_degrees") return "crease";
  return std::string(name);
}

Transform matrix_arg(py::handle obj) {
  const py::array a = py::array::ensure(obj);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) {
    PyErr_Clear();
    throw py::value_error("M: expected a 4x4 matrix");
  }
  const auto d = DoubleArray::ensure(a);
  std::array<double, 16> rows{};
  std::copy(d.data(), d.data() + 16, rows.begin());
  return Transform::from_matrix(rows);
}

/// Model.scale's factors: finite, non-zero, and a product (the factor of every volume) within
/// the normal doubles. \throws InputError naming `s`.
void check_scale(const Vec3& f) {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(f[a]))
      throw InputError("s: expected finite scale factors, got " + std::to_string(f[a]));
    if (f[a] == 0)
      throw InputError(std::string("s: the ") + "xyz"[a] +
                       " scale factor is 0 (it flattens the solid)");
  }
  // log2 of |sx·sy·sz| without forming the product (which may underflow or overflow).
  const double log2 =
      std::log2(std::abs(f.x)) + std::log2(std::abs(f.y)) + std::log2(std::abs(f.z));
  if (log2 < -1022 || log2 >= 1024) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "s: scale factors (%g, %g, %g) multiply volumes by about 1e%d, which %s a "
                  "double (their product must be within 2.2e-308 to 1.8e308 in magnitude)",
                  f.x, f.y, f.z, static_cast<int>(std::lround(log2 * std::log10(2.0))),
                  log2 < 0 ? "underflows" : "overflows");
    throw InputError(text);
  }
}

py::array_t<uint8_t> classify_points(const Model& model, py::handle points, Threads threads) {
  const Points p = points_arg(points, "points");
  const std::span<const Vec3> all = p.span();
  check_finite(all, "classify");
  py::array_t<uint8_t> out(static_cast<py::ssize_t>(all.size()));
  uint8_t* dst = out.mutable_data();
  {
    KernelScope scope(threads);
    scope.run([&] {
      Interrupt interrupt;
      for (size_t begin = 0; begin < all.size(); begin += kBatch) {
        const auto part = model.classify(all.subspan(begin, std::min(kBatch, all.size() - begin)));
        std::memcpy(dst + begin, part.data(), part.size());
        interrupt.poll();
      }
    });
  }
  return out;
}

/// Model.distance: signed distances, float64 (n,).
py::array_t<double> distance_values(const Model& model, py::handle points, Threads threads) {
  const Points p = points_arg(points, "points");
  const std::span<const Vec3> all = p.span();
  check_finite(all, "distance");
  Model::Distances d;
  {
    KernelScope scope(threads);
    scope.run([&] { d = model.distance(all); });
  }
  py::array_t<double> out(static_cast<py::ssize_t>(d.distance.size()));
  std::copy(d.distance.begin(), d.distance.end(), out.mutable_data());
  return out;
}

/// Model.field: f (n, k) and ∇f (n, k, 3), float64, for the k field leaves.
py::tuple field_values(const Model& model, py::handle points, Threads threads) {
  const Points p = points_arg(points, "points");
  const std::span<const Vec3> all = p.span();
  Model::FieldValues f;
  {
    KernelScope scope(threads);
    scope.run([&] { f = model.field(all); });
  }
  const size_t n = all.size(), k = f.leaves.size();
  py::array_t<double> value({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(k)});
  py::array_t<double> gradient(
      {static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(k), py::ssize_t{3}});
  double* v = value.mutable_data();
  double* g = gradient.mutable_data();
  for (size_t i = 0; i < n * k; ++i) {
    v[i] = f.values[i].value;
    g[3 * i] = f.values[i].gradient.x;
    g[3 * i + 1] = f.values[i].gradient.y;
    g[3 * i + 2] = f.values[i].gradient.z;
  }
  return py::make_tuple(value, gradient);
}

/// Model.classify(..., with_uncertain=True): the codes and the uncertain count.
py::tuple classify_counted_points(const Model& model, py::handle points, Threads threads) {
  const Points p = points_arg(points, "points");
  const std::span<const Vec3> all = p.span();
  check_finite(all, "classify");
  py::array_t<uint8_t> out(static_cast<py::ssize_t>(all.size()));
  uint8_t* dst = out.mutable_data();
  size_t uncertain = 0;
  {
    KernelScope scope(threads);
    scope.run([&] {
      Interrupt interrupt;
      for (size_t begin = 0; begin < all.size(); begin += kBatch) {
        const Classification part =
            model.classify_counted(all.subspan(begin, std::min(kBatch, all.size() - begin)));
        std::memcpy(dst + begin, part.classes.data(), part.classes.size());
        uncertain += part.uncertain;
        interrupt.poll();
      }
    });
  }
  return py::make_tuple(out, uncertain);
}

py::array_t<int32_t> winding_numbers(const Model& model, py::handle points, Threads threads) {
  const Points p = points_arg(points, "points");
  const std::span<const Vec3> all = p.span();
  check_finite(all, "windings");
  const size_t leaves = model.leaf_count();
  py::array_t<int32_t> out(
      {static_cast<py::ssize_t>(all.size()), static_cast<py::ssize_t>(leaves)});
  int32_t* dst = out.mutable_data();
  {
    KernelScope scope(threads);
    scope.run([&] {
      Interrupt interrupt;
      for (size_t begin = 0; begin < all.size() && leaves > 0; begin += kBatch) {
        const LeafWindings w =
            model.windings(all.subspan(begin, std::min(kBatch, all.size() - begin)));
        std::copy(w.winding.begin(), w.winding.end(), dst + begin * leaves);
        interrupt.poll();
      }
    });
  }
  return out;
}

/// The rays of cast() and first_hits(): one direction for all, or one per origin; Model::cast's
/// checks, naming the caller's index.
std::vector<Ray> rays_arg(py::handle origins, py::handle directions, const char* what) {
  const Points o = points_arg(origins, "origins");
  const std::span<const Vec3> from = o.span();
  std::vector<Ray> rays(from.size());
  const py::array d_any = py::array::ensure(directions);
  if (d_any && d_any.ndim() == 1) {
    const Vec3 d = vec3_arg(directions, "directions");
    for (size_t i = 0; i < rays.size(); ++i) rays[i] = {from[i], d};
  } else {
    PyErr_Clear();
    const Points d = points_arg(directions, "directions");
    if (d.span().size() != from.size())
      throw py::value_error("directions: expected " + std::to_string(from.size()) +
                            " directions (one per origin) or one of shape (3,), got " +
                            std::to_string(d.span().size()));
    for (size_t i = 0; i < rays.size(); ++i) rays[i] = {from[i], d.span()[i]};
  }
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& r = rays[i];
    const double c[6] = {r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z};
    if (!std::all_of(c, c + 6, [](double x) { return std::isfinite(x); }))
      throw InputError(std::string(what) + ": ray " + std::to_string(i) +
                       " has a non-finite origin or direction");
    if (r.dir == Vec3{})
      throw InputError(std::string(what) + ": ray " + std::to_string(i) + " has a zero direction");
  }
  return rays;
}

/// Runs `batch(begin, count)` over [0, n) in batches of kBatch / 4 rays inside one kernel scope
/// (threads, the GIL released), polling for Ctrl-C between batches: cast() and first_hits().
template <class Batch>
void in_ray_batches(size_t n, Threads threads, Batch&& batch) {
  KernelScope scope(threads);
  scope.run([&] {
    Interrupt interrupt;
    for (size_t begin = 0; begin < n; begin += kBatch / 4) {
      batch(begin, std::min(kBatch / 4, n - begin));
      interrupt.poll();
    }
  });
}

/// Model::cast: every crossing of every ray, flattened (ray i's hits are
/// [offsets[i], offsets[i + 1]), its spans [span_offsets[i], span_offsets[i + 1])).
py::object all_hits(const Model& model, py::handle origins, py::handle directions,
                    Threads threads) {
  const std::vector<Ray> rays = rays_arg(origins, directions, "cast");
  const auto n = static_cast<py::ssize_t>(rays.size());
  py::array_t<int64_t> offsets(n + 1), span_offsets(n + 1);
  py::array_t<uint32_t> uncertain(n);
  std::vector<double> t, spans;
  std::vector<int32_t> leaf, sign;
  std::vector<int64_t> face;
  int64_t* off = offsets.mutable_data();
  int64_t* soff = span_offsets.mutable_data();
  uint32_t* unc = uncertain.mutable_data();
  off[0] = soff[0] = 0;
  in_ray_batches(rays.size(), threads, [&](size_t begin, size_t count) {
    const auto r = model.cast(std::span<const Ray>(rays).subspan(begin, count));
    for (size_t k = 0; k < count; ++k) {
      const size_t i = begin + k;
      for (const RayHit& h : r[k].hits) {
        t.push_back(h.t);
        leaf.push_back(static_cast<int32_t>(h.leaf));
        face.push_back(static_cast<int64_t>(h.face));
        sign.push_back(h.sign);
      }
      for (const Span& sp : r[k].spans) spans.insert(spans.end(), {sp.t0, sp.t1});
      off[i + 1] = static_cast<int64_t>(t.size());
      soff[i + 1] = static_cast<int64_t>(spans.size() / 2);
      unc[i] = r[k].uncertain;
    }
  });
  const auto k = static_cast<py::ssize_t>(t.size());
  return py::module_::import("cover._cover")
      .attr("Casts")(offsets, copy_array<double>(t, {k}), copy_array<int32_t>(leaf, {k}),
                     copy_array<int64_t>(face, {k}), copy_array<int32_t>(sign, {k}), span_offsets,
                     copy_array<double>(spans, {static_cast<py::ssize_t>(spans.size() / 2), 2}),
                     uncertain);
}

py::object first_hit_rays(const Model& model, py::handle origins, py::handle directions,
                          Threads threads) {
  const std::vector<Ray> rays = rays_arg(origins, directions, "first_hits");
  const auto n = static_cast<py::ssize_t>(rays.size());
  py::array_t<bool> hit(n);
  py::array_t<double> t(n), normal({n, py::ssize_t{3}});
  py::array_t<int32_t> leaf(n);
  py::array_t<int64_t> face(n);
  bool* hit_p = hit.mutable_data();
  double* t_p = t.mutable_data();
  double* normal_p = normal.mutable_data();
  int32_t* leaf_p = leaf.mutable_data();
  int64_t* face_p = face.mutable_data();
  in_ray_batches(rays.size(), threads, [&](size_t begin, size_t count) {
    const auto hits = model.first_hits(std::span<const Ray>(rays).subspan(begin, count));
    for (size_t k = 0; k < count; ++k) {
      const FirstHit& h = hits[k];
      const size_t i = begin + k;
      hit_p[i] = h.hit;
      t_p[i] = h.hit ? h.t : std::numeric_limits<double>::infinity();
      leaf_p[i] = h.hit ? static_cast<int32_t>(h.leaf) : -1;
      face_p[i] = h.hit ? static_cast<int64_t>(h.face) : -1;
      const double len = std::sqrt(dot(h.normal, h.normal));
      const Vec3 u = h.hit && len > 0 ? (1 / len) * h.normal : Vec3{};
      normal_p[3 * i] = u.x, normal_p[3 * i + 1] = u.y, normal_p[3 * i + 2] = u.z;
    }
  });
  return py::module_::import("cover._cover").attr("Hits")(hit, t, leaf, face, normal);
}

/// A VolumeResult as `cover volume --json` states it (keys by method).
py::dict volume_dict(const VolumeResult& r) {
  py::dict d("volume"_a = r.volume,
             "area"_a = r.area ? py::object(py::float_(*r.area)) : py::none(),
             "method"_a = r.method, "error_bound"_a = r.error_bound);
  if (r.method == "rays") {
    d["rays"] = r.rays;
    d["target_met"] = r.target_met;
  }
  if (r.method == "bracket") {
    d["cells"] = r.rays;
    d["target_met"] = r.target_met;
  }
  return d;
}

VolumeResult volume_result(const Model& model, bool exact, std::optional<int> rays,
                           std::optional<double> tolerance, Threads threads) {
  VolumeOptions o;
  o.exact = exact;
  if (tolerance) {
    if (!(*tolerance >= 1e-12 && *tolerance <= 1))
      throw InputError("tolerance: expected a number from 1e-12 to 1, got " +
                       std::to_string(*tolerance));
    o.target_relative_error = o.bracket_relative_error = *tolerance;
  }
  if (rays) {  // 0: adaptive, as None and as C++'s VolumeOptions::rays
    if (*rays < 0 || *rays > 2048)
      throw InputError("rays: expected a whole number from 0 (adaptive) to 2048, got " +
                       std::to_string(*rays));
    o.rays = *rays;
  }
  KernelScope scope(threads);
  return scope.run([&] {
    Interrupt interrupt;
    o.progress = [&](double) { interrupt.poll(); };
    return model.volume(o);
  });
}

/// The bits of `grid` as bool (nx, ny, nz) [x, y, z], one column per task.
py::array_t<bool> unpack_grid(const VoxelGrid& grid) {
  const auto nx = static_cast<size_t>(grid.nx()), ny = static_cast<size_t>(grid.ny()),
             nz = static_cast<size_t>(grid.nz());
  py::array_t<bool> out(
      {static_cast<py::ssize_t>(nx), static_cast<py::ssize_t>(ny), static_cast<py::ssize_t>(nz)});
  bool* dst = out.mutable_data();
  const size_t words = grid.words_per_column();
  // Eight bits at a time through a table of their eight bytes (a bit at a time took most of a
  // brick's time in cover.dask: 16 MB of bool per 256³ brick).
  static const std::array<uint64_t, 256> kBytes = [] {
    std::array<uint64_t, 256> t{};
    for (int v = 0; v < 256; ++v)
      for (int b = 0; b < 8; ++b) t[v] |= static_cast<uint64_t>((v >> b) & 1) << (8 * b);
    return t;
  }();
  static_assert(sizeof(bool) == 1 && std::endian::native == std::endian::little);
  py::gil_scoped_release release;
  parallel_for(nx * ny, 64, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end; ++c) {
      const uint64_t* col = grid.bits.data() + c * words;
      bool* row = dst + c * nz;
      size_t k = 0;
      for (; k + 8 <= nz; k += 8) {
        const uint64_t bytes = kBytes[(col[k / 64] >> (k % 64)) & 0xff];  // little-endian
        std::memcpy(row + k, &bytes, 8);
      }
      for (; k < nz; ++k) row[k] = (col[k / 64] >> (k % 64)) & 1;
    }
  });
  return out;
}

/// voxelize_brick(res, box, bounds): the voxels of index box (i0, i1, j0, j1, k0, k1) of the
/// cubic res³ grid over `bounds` (default: voxel_bounds(res)), bit-identical to that region of
/// voxelize(res, bounds); res up to 16384 (only the brick is held).
/// Refuses a grid whose packed bits and bool array (9/8 byte per cell) would pass `max_memory`
/// MiB, before allocating either (the CLI's --max-memory estimate).
void check_grid_memory(const char* what, uint64_t cells, uint64_t max_memory) {
  const uint64_t need = cells + cells / 8;
  if (need > max_memory * (uint64_t{1} << 20))
    throw InputError(std::string(what) + ": " + std::to_string(cells) + " voxels need " +
                     std::to_string((need >> 20) + 1) +
                     " MiB (a bool array and the packed grid), " +
                     "over max_memory = " + std::to_string(max_memory) +
                     " MiB; raise max_memory, or use voxelize_brick or cover.dask.voxelize");
}

py::array_t<bool> voxel_brick(const Model& model, int res, const py::object& box,
                              const py::object& bounds, uint64_t max_memory, Threads threads) {
  if (res < 1 || res > 16384)
    throw InputError("res: expected a whole number from 1 to 16384, got " + std::to_string(res));
  const std::vector<double> b = numbers_arg(box, "box", 6);
  IndexBox index;
  for (int a = 0; a < 3; ++a) {
    const double lo = b[2 * a], hi = b[2 * a + 1];
    if (lo != std::floor(lo) || hi != std::floor(hi) || !(0 <= lo && lo < hi && hi <= res))
      throw InputError(
          "box: expected whole numbers 0 <= lo < hi <= res per axis "
          "(i0, i1, j0, j1, k0, k1)");
    index.lo[a] = static_cast<int>(lo);
    index.hi[a] = static_cast<int>(hi);
  }
  const std::optional<VoxelBounds> given = bounds_arg(bounds);
  const uint64_t cells = uint64_t(index.hi[0] - index.lo[0]) * uint64_t(index.hi[1] - index.lo[1]) *
                         uint64_t(index.hi[2] - index.lo[2]);
  check_grid_memory("voxelize_brick", cells, max_memory);
  VoxelGrid grid;
  {
    KernelScope scope(threads);  // releases the GIL
    scope.run([&] {
      const VoxelLattice lattice = cubic_lattice(given ? *given : model.voxel_bounds(res), res);
      model.voxelize_brick(lattice, index, grid);
    });
  }
  return unpack_grid(grid);
}

/// The VoxelizeOptions of voxelize(res, bounds, voxel_size=, dims=): exactly one of the three
/// grid arguments, checked with messages naming the Python parameters.
VoxelizeOptions voxelize_options(std::optional<int> res, const py::object& bounds,
                                 std::optional<double> voxel_size, const py::object& dims) {
  VoxelizeOptions o;
  o.bounds = bounds_arg(bounds);
  const int given = int(res.has_value()) + int(voxel_size.has_value()) + int(!dims.is_none());
  if (given != 1)
    throw InputError(
        "res, voxel_size, dims: give exactly one (a cubic grid of res voxels per "
        "axis, a spacing, or NX, NY, NZ voxel counts), as the CLI's --res, "
        "--voxel-size, --dims");
  if (res) {
    if (*res < 1 || *res > kMaxVoxelResolution)  // before allocating the output
      throw InputError("res: expected a whole number from 1 to " +
                       std::to_string(kMaxVoxelResolution) +
                       " (above, voxelize_brick or "
                       "cover.dask.voxelize, up to " +
                       std::to_string(kMaxVoxelDims) + "), got " + std::to_string(*res));
    o.resolution = *res;
  } else if (voxel_size) {
    if (!(*voxel_size > 0) || !std::isfinite(*voxel_size))
      throw InputError("voxel_size: expected a finite spacing > 0");
    o.voxel_size = *voxel_size;
  } else {
    const std::vector<double> d = numbers_arg(dims, "dims", 3);
    for (int a = 0; a < 3; ++a) {
      if (d[a] != std::floor(d[a]) || d[a] < 1 || d[a] > kMaxVoxelDims)
        throw InputError("dims: expected 3 whole numbers from 1 to " +
                         std::to_string(kMaxVoxelDims));
      o.dims[a] = static_cast<int>(d[a]);
    }
  }
  return o;
}

/// cover.VoxelLattice(origin, spacing, dims, cube_size) of a lattice.
py::object lattice_object(const VoxelLattice& l) {
  return py::module_::import("cover._results")
      .attr("VoxelLattice")(py::make_tuple(l.origin.x, l.origin.y, l.origin.z), l.spacing,
                            py::make_tuple(l.dims[0], l.dims[1], l.dims[2]),
                            l.cube_size ? py::cast(*l.cube_size) : py::none());
}

py::array_t<bool> voxel_grid(const Model& model, std::optional<int> res, const py::object& bounds,
                             std::optional<double> voxel_size, const py::object& dims,
                             uint64_t max_memory, Threads threads) {
  VoxelizeOptions o = voxelize_options(res, bounds, voxel_size, dims);
  const VoxelLattice lattice = model.voxel_lattice(o);  // InputError for a bad spacing or box
  check_grid_memory("voxelize", lattice.voxel_count(), max_memory);
  VoxelGrid grid;
  {
    KernelScope scope(threads);
    scope.run([&] {
      Interrupt interrupt;
      o.progress = [&](double) { interrupt.poll(); };
      grid = model.voxelize(o);
    });
  }
  return unpack_grid(grid);
}

py::array_t<uint8_t> render_image(const Model& model, int width, int height,
                                  const std::string& view, const py::object& section,
                                  bool perspective, const std::string& up,
                                  std::optional<double> elevation, double azimuth, double zoom,
                                  const py::object& pan, bool fit, int samples, double crease,
                                  Threads threads) {
  CameraOptions co;
  co.view = parse_view(view);
  co.width = width;
  co.height = height;
  co.perspective = perspective;
  co.up = parse_up(up);
  co.elevation_degrees = elevation;
  co.azimuth_degrees = azimuth;
  co.zoom = zoom;
  if (!pan.is_none()) {
    const std::vector<double> p = numbers_arg(pan, "pan", 2);
    co.pan = {p[0], p[1]};
  }
  co.fit = fit;
  RenderOptions ro;
  ro.samples = samples;  // range checked by Model::render, naming `samples`
  ro.crease_degrees = crease;
  if (!section.is_none()) {
    const std::vector<double> s = numbers_arg(section, "section", 4);
    ro.section = Plane{{s[0], s[1], s[2]}, s[3]};
  }
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw InputError("width, height: expected whole numbers from 1 to 16384, got " +
                     std::to_string(width) + ", " + std::to_string(height));
  py::array_t<uint8_t> out({py::ssize_t{height}, py::ssize_t{width}, py::ssize_t{3}});
  uint8_t* dst = out.mutable_data();
  {
    KernelScope scope(threads);
    scope.run([&] {
      Interrupt interrupt;
      ro.progress = [&](size_t, size_t) { interrupt.poll(); };
      const Image img = model.render(co, ro);
      // In 16 MiB steps: the output's first touch is page faults too (432 MB at 12000²).
      constexpr size_t kStep = size_t{16} << 20;
      for (size_t at = 0; at < img.rgb.size(); at += kStep) {
        const size_t count = std::min(kStep, img.rgb.size() - at);
        std::copy(img.rgb.begin() + at, img.rgb.begin() + at + count, dst + at);
        interrupt.poll();
      }
    });
  }
  return out;
}

py::tuple mesh_arrays(const PolygonMesh& mesh) {
  return py::make_tuple(vertices_array(mesh.vertices), triangles_array(mesh));
}

py::tuple evaluate_mesh(const Model& model, bool leaf_ids, int mesh_resolution,
                        double mesh_tolerance, Threads threads) {
  EvaluateResult r;
  EvaluateOptions o;
  o.mesh_resolution = mesh_resolution;
  o.mesh_tolerance = mesh_tolerance;
  {
    KernelScope scope(threads);
    scope.run([&] { r = model.evaluate(o); });
  }
  if (!leaf_ids) return mesh_arrays(r.mesh);
  py::array_t<int32_t> leaf(static_cast<py::ssize_t>(r.face_leaf.size()));
  std::copy(r.face_leaf.begin(), r.face_leaf.end(), leaf.mutable_data());
  return py::make_tuple(vertices_array(r.mesh.vertices), triangles_array(r.mesh), leaf);
}

py::tuple polygonize_mesh(const Model& model, int resolution, std::optional<double> cell_size,
                          double tolerance, uint64_t max_memory, Threads threads) {
  PolygonizeOptions o;
  o.resolution = resolution;
  if (cell_size) {
    if (!(*cell_size > 0) || !std::isfinite(*cell_size))
      throw InputError("polygonize: cell_size: expected a finite number > 0");
    o.cell_size = *cell_size;
  }
  o.tolerance = tolerance;
  o.max_memory_bytes = max_memory << 20;
  PolygonizeResult r;
  {
    KernelScope scope(threads);
    scope.run([&] { r = model.polygonize(o); });
  }
  py::dict report;
  report["cell_size"] = r.cell_size;
  report["tolerance"] = r.tolerance;
  report["cells"] = r.cells;
  report["grid_points"] = r.grid_points;
  report["bisections"] = r.bisections;
  report["uncertain"] = r.uncertain;
  report["clipped"] = r.clipped;
  return py::make_tuple(vertices_array(r.mesh.vertices), triangles_array(r.mesh), report);
}

py::tuple clip_halves(const Model& model, py::handle plane, Threads threads) {
  const std::vector<double> p = numbers_arg(plane, "plane", 4);
  brep::ClipOptions o;
  o.triangulate_caps = true;
  brep::ClipResult r;
  {
    KernelScope scope(threads);
    scope.run([&] { r = model.clip(brep::Plane{{p[0], p[1], p[2]}, p[3]}, o); });
  }
  return py::make_tuple(mesh_arrays(r.above.mesh), mesh_arrays(r.below.mesh));
}

/// evaluate_cells(n, bounds): one dict per non-empty cell, in (i, j, k) order.
py::list cell_pieces(const Model& model, int n, const py::object& bounds, int64_t max_memory,
                     Threads threads) {
  const std::optional<VoxelBounds> given = bounds_arg(bounds);
  if (n < 1) throw InputError("n: expected at least 1 cell per axis, got " + std::to_string(n));
  if (max_memory < 1 || max_memory > (int64_t{1} << 40))
    throw InputError("max_memory: expected MiB from 1 to 2^40, got " + std::to_string(max_memory));
  brep::CellsOptions o;
  o.max_memory_bytes = static_cast<uint64_t>(max_memory) << 20;
  // The library's refusal (Model::evaluate_cells), worded with this call's parameters.
  if (const double need = brep::cells_memory_bytes(n); n >= 1 && need > o.max_memory_bytes)
    throw InputError("evaluate_cells: n = " + std::to_string(n) + ": the pieces need " +
                     std::to_string(static_cast<uint64_t>(std::ceil(need / (1 << 20)))) +
                     " MiB, over max_memory = " + std::to_string(max_memory) + " MiB");
  o.glue = false;
  o.clip.triangulate_caps = true;
  CellsEvaluation r;
  {
    KernelScope scope(threads);
    scope.run([&] { r = model.evaluate_cells(n, given, o); });
  }
  py::list out;
  for (const brep::CellPiece& p : r.cells.pieces) {
    py::dict d;
    d["cell"] = py::make_tuple(p.cell[0], p.cell[1], p.cell[2]);
    d["vertices"] = vertices_array(p.mesh.vertices);
    d["faces"] = triangles_array(p.mesh);
    d["volume"] = p.volume;
    d["area"] = p.area;
    d["cap_area"] = p.cap_area;
    out.append(std::move(d));
  }
  return out;
}

py::list decompose_pieces(const Model& model, Threads threads) {
  brep::DecomposeResult r;
  {
    KernelScope scope(threads);
    scope.run([&] { r = model.decompose(); });
  }
  py::list pieces;
  for (const PolygonMesh& piece : r.pieces) pieces.append(mesh_arrays(piece));
  return pieces;
}

py::object bbox_list(const Bbox& b) {
  if (b.empty()) return py::none();
  py::list box;
  box.append(py::make_tuple(b.min.x, b.min.y, b.min.z));
  box.append(py::make_tuple(b.max.x, b.max.y, b.max.z));
  for (int i = 0; i < 2; ++i) box[i] = py::list(box[i]);
  return box;
}

py::object brep_dict(const std::optional<brep::BrepReport>& brep) {
  if (!brep) return py::none();
  const brep::BrepReport& r = *brep;
  return py::dict("closed"_a = r.closed, "manifold"_a = r.manifold, "euler"_a = r.euler,
                  "genus"_a = r.genus >= 0 ? py::object(py::int_(r.genus)) : py::none(),
                  "components"_a = r.components, "boundary_loops"_a = r.boundary_loops);
}

/// Model.info: cover::info (model/info.h) as the dict of `cover info --json`.
py::dict info_dict(const Model& model, bool self_intersection) {
  ModelInfo facts;
  {
    KernelScope scope(std::nullopt);
    facts = info(model, {.check_self_intersection = self_intersection});
  }
  py::list leaves;
  for (const LeafInfo& leaf : facts.leaves) {
    const MeshReport& r = leaf.report;
    py::dict d("name"_a = leaf.name);
    if (!leaf.origin.empty()) d["origin"] = leaf.origin;
    auto vec = [](const Vec3& v) { return py::list(py::make_tuple(v.x, v.y, v.z)); };
    if (leaf.warp) {  // as `cover info --json` (cli/commands.cpp warp_json)
      const WarpLeaf& w = *leaf.warp;
      d["kind"] = "warp";
      d["warp"] = std::string(to_string(w.kind));
      d["axis"] = py::dict("point"_a = vec(w.point), "direction"_a = vec(w.direction));
      if (w.kind == WarpKind::kTwist) d["degrees_per_unit"] = w.degrees_per_unit;
      if (w.kind != WarpKind::kTwist) d["range"] = py::list(py::make_tuple(w.range[0], w.range[1]));
      if (w.kind == WarpKind::kTaper) d["scale"] = py::list(py::make_tuple(w.scale[0], w.scale[1]));
      if (w.kind == WarpKind::kBend) {
        d["toward"] = vec(w.toward);
        d["center"] = w.center;
        d["radius"] = w.radius;
      }
      d["bbox"] = bbox_list(leaf.bbox);
      d["child_leaves"] = leaf.child_leaves;
      leaves.append(d);
      continue;
    }
    if (leaf.field) {  // as `cover info --json` (cli/commands.cpp field_json)
      d["kind"] = "field";
      d["threshold"] = leaf.threshold;
      d["bbox"] = bbox_list(leaf.bbox);
      py::list prims;
      for (const FieldPrimitive& p : leaf.field->primitives) {
        py::dict pd("skeleton"_a = std::string(to_string(p.kind)));
        auto vec = [](const Vec3& v) { return py::make_tuple(v.x, v.y, v.z); };
        if (p.kind == SkeletonKind::kMesh) {
          pd["triangles"] = p.points.size() / 3;
          pd["bbox"] = py::make_tuple(py::list(vec(p.mesh->nodes[0].box.min)),
                                      py::list(vec(p.mesh->nodes[0].box.max)));
        } else if (p.kind == SkeletonKind::kCircle) {
          pd["center"] = py::list(vec(p.points[0]));
          pd["normal"] = py::list(vec(p.points[1]));
          pd["circle_radius"] = p.circle_radius;
        } else {
          py::list pts;
          for (const Vec3& v : p.points) pts.append(py::list(vec(v)));
          pd["points"] = pts;
        }
        pd["radius"] = p.radius;
        pd["influence"] = p.influence;
        pd["exponent"] = p.exponent;
        pd["weight"] = p.weight;
        prims.append(pd);
      }
      d["primitives"] = prims;
      leaves.append(d);
      continue;
    }
    d["kind"] = "mesh";
    d["vertices"] = leaf.vertices;
    d["faces"] = leaf.faces;
    d["closed"] = r.closed;
    d["manifold"] = r.manifold;
    d["oriented"] = r.oriented;
    d["outward"] = r.outward;
    d["boundary_edges"] = r.boundary_edges;
    d["nonmanifold_edges"] = r.nonmanifold_edges;
    d["components"] = r.components;
    d["genus"] = r.genus >= 0 ? py::object(py::int_(r.genus)) : py::none();
    d["degenerate_faces"] = r.degenerate_faces;
    d["self_intersecting"] =
        r.self_intersecting ? py::object(py::bool_(*r.self_intersecting)) : py::none();
    d["self_touching"] = r.self_touching ? py::object(py::bool_(*r.self_touching)) : py::none();
    d["volume"] = r.volume;
    d["bbox"] = bbox_list(leaf.bbox);
    d["brep"] = brep_dict(leaf.brep);
    const RepairReport& rr = leaf.repair;
    d["repair"] =
        py::dict("welded_vertices"_a = rr.welded_vertices, "zero_area_faces"_a = rr.zero_area_faces,
                 "boundary_edges"_a = rr.boundary_edges, "edges"_a = rr.edges);
    d["rule"] = rr.rule();
    d["boundary_edge_fraction"] = rr.boundary_edge_fraction();
    leaves.append(d);
  }
  return py::dict("vertices"_a = facts.vertices, "faces"_a = facts.faces,
                  "leaves"_a = facts.leaves.size(), "bbox"_a = bbox_list(facts.bbox),
                  "leaves_info"_a = leaves);
}

/// `model` after issuing each of its warnings as a Python UserWarning (with the GIL).
Model warned(Model model) {
  for (const std::string& w : model.warnings(keyword))
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
  return model;
}

}  // namespace
}  // namespace cover::python

#include "docstrings.h"

PYBIND11_MODULE(_cover, m) {
  using namespace cover;
  using namespace cover::python;
  namespace doc = cover::python::doc;
  m.doc() = doc::kModule;
  m.attr("__version__") = COVER_VERSION;
  py::tuple names(5);
  for (int c = 0; c < 5; ++c)
    names[c] = py::str(std::string(to_string(static_cast<PointClass>(c))));
  m.attr("CLASS_NAMES") = names;
  m.attr("Hits") =
      py::module_::import("collections")
          .attr("namedtuple")("Hits", py::make_tuple("hit", "t", "leaf", "face", "normal"));
  m.attr("Hits").attr("__doc__") = doc::kHits;
  m.attr("Casts") =
      py::module_::import("collections")
          .attr("namedtuple")("Casts", py::make_tuple("offsets", "t", "leaf", "face", "sign",
                                                      "span_offsets", "spans", "uncertain"));
  m.attr("Casts").attr("__doc__") = doc::kCasts;

  static py::exception<InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<NotComputable> not_computable(m, "NotComputable", PyExc_RuntimeError);
  static py::exception<PreconditionError> precondition(m, "PreconditionError", PyExc_ValueError);
  input_error.doc() = doc::kInputError;
  not_computable.doc() = doc::kNotComputable;
  precondition.doc() = doc::kPreconditionError;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      input_error(e.text(keyword).c_str());
    } catch (const NotComputable& e) {
      not_computable(e.what());
    } catch (const PreconditionError& e) {
      precondition(e.what());
    }
  });

  const auto threads = py::arg("threads") = py::none();

  py::class_<Model> model(m, "Model", doc::kModel);
  model.def(py::init<>(), doc::kModelInit)
      .def_property_readonly("leaves", &Model::leaf_count, doc::kLeaves)
      .def_property_readonly(
          "leaf_colours",
          [](const Model& a) {
            const size_t n = a.leaf_count();
            py::array_t<uint8_t> out({py::ssize_t(n), py::ssize_t{3}});
            for (size_t l = 0; l < n; ++l) {
              const std::array<uint8_t, 3> c = display_colour(a.solid(), static_cast<uint32_t>(l));
              for (int k = 0; k < 3; ++k) out.mutable_at(l, k) = c[k];
            }
            return out;
          },
          doc::kLeafColours)
      .def_property_readonly("empty", &Model::empty, doc::kEmpty)
      .def_property_readonly("bounded", &Model::bounded, doc::kBounded)
      .def_property_readonly(
          "warnings", [](const Model& m) { return m.warnings(keyword); }, doc::kWarnings)
      .def("__repr__",
           [](const Model& a) {
             return "<cover.Model: " + std::to_string(a.leaf_count()) + " leaves, " +
                    std::to_string(a.solid().face_count()) + " faces>";
           })
      .def(
          "__or__", [](const Model& a, const Model& b) { return a | b; }, py::is_operator(),
          doc::kOr)
      .def(
          "__and__", [](const Model& a, const Model& b) { return a & b; }, py::is_operator(),
          doc::kAnd)
      .def(
          "__sub__", [](const Model& a, const Model& b) { return a - b; }, py::is_operator(),
          doc::kSub)
      .def(
          "__invert__", [](const Model& a) { return ~a; }, doc::kInvert)
      .def(
          "transform",
          [](const Model& a, py::handle mat) { return a.transformed(matrix_arg(mat)); },
          py::arg("M"), doc::kTransform)
      .def(
          "translate",
          [](const Model& a, py::handle v) {
            const Vec3 t = vec3_arg(v, "v");
            return a.transformed(Transform::translation(t));
          },
          py::arg("v"), doc::kTranslate)
      .def(
          "scale",
          [](const Model& a, py::handle s) {
            Vec3 f;
            py::array scalar = py::array::ensure(s);
            if (!scalar) PyErr_Clear();
            if (scalar && scalar.ndim() == 0) {
              const double k = DoubleArray::ensure(scalar.reshape({1})).data()[0];
              f = {k, k, k};
            } else {
              f = vec3_arg(s, "s");
            }
            check_scale(f);
            return a.transformed(Transform::scaling(f));
          },
          py::arg("s"), doc::kScale)
      .def(
          "rotate",
          [](const Model& a, py::handle axis, double degrees) {
            const Vec3 ax = vec3_arg(axis, "axis");
            if (ax == Vec3{}) throw InputError("rotate: the axis must be non-zero");
            return a.transformed(Transform::rotation(ax, degrees));
          },
          py::arg("axis"), py::arg("degrees"), doc::kRotate)
      .def(
          "mirror", [](const Model& a, py::handle n) { return a.mirrored(vec3_arg(n, "normal")); },
          py::arg("normal"), doc::kMirror)
      .def("classify", &classify_points, py::arg("points"), py::kw_only(), threads, doc::kClassify)
      .def("distance", &distance_values, py::arg("points"), py::kw_only(), threads, doc::kDistance)
      .def("classify_counted", &classify_counted_points, py::arg("points"), py::kw_only(), threads,
           doc::kClassifyCounted)
      .def("field", &field_values, py::arg("points"), py::kw_only(), threads, doc::kField)
      .def("windings", &winding_numbers, py::arg("points"), py::kw_only(), threads, doc::kWindings)
      .def(
          "winding",
          [](const Model& a, py::handle points, Threads t) {
            if (PyErr_WarnEx(PyExc_DeprecationWarning,
                             "Model.winding() is Model.windings() (the C++ name)", 1) != 0)
              throw py::error_already_set();
            return winding_numbers(a, points, t);
          },
          py::arg("points"), py::kw_only(), threads, doc::kWinding)
      .def("cast", &all_hits, py::arg("origins"), py::arg("directions"), py::kw_only(), threads,
           doc::kCast)
      .def("first_hits", &first_hit_rays, py::arg("origins"), py::arg("directions"), py::kw_only(),
           threads, doc::kFirstHits)
      .def(
          "volume",
          [](const Model& a, bool exact, std::optional<int> rays, std::optional<double> tol,
             Threads t) {
            return py::module_::import("cover._results")
                .attr("VolumeResult")(volume_dict(volume_result(a, exact, rays, tol, t)));
          },
          py::kw_only(), py::arg("exact") = false, py::arg("rays") = py::none(),
          py::arg("tolerance") = py::none(), threads, doc::kVolume)
      .def(
          "volume_info",
          [](const Model& a, bool exact, std::optional<int> rays, std::optional<double> tol,
             Threads t) { return volume_dict(volume_result(a, exact, rays, tol, t)); },
          py::kw_only(), py::arg("exact") = false, py::arg("rays") = py::none(),
          py::arg("tolerance") = py::none(), threads, doc::kVolumeInfo)
      .def(
          "bounds",
          [](const Model& a) {
            const std::optional<Bbox> b = a.bounds();
            if (!b)
              throw NotComputable("bounds: the result is unbounded (a complement at the root)");
            const double v[6] = {b->min.x, b->min.y, b->min.z, b->max.x, b->max.y, b->max.z};
            return copy_array<double>(v, {2, 3});
          },
          doc::kBounds)
      .def(
          "voxel_bounds",
          [](const Model& a, int res) {
            if (res < 1 || res > kMaxVoxelDims)
              throw InputError("res: expected a whole number from 1 to " +
                               std::to_string(kMaxVoxelDims) + ", got " + std::to_string(res));
            const VoxelBounds b = a.voxel_bounds(res);
            return py::make_tuple(b.min.x, b.min.y, b.min.z, b.size);
          },
          py::arg("res"), doc::kVoxelBounds)
      .def(
          "voxel_lattice",
          [](const Model& a, std::optional<int> res, const py::object& bounds,
             std::optional<double> voxel_size, const py::object& dims) {
            return lattice_object(a.voxel_lattice(voxelize_options(res, bounds, voxel_size, dims)));
          },
          py::arg("res") = py::none(), py::arg("bounds") = py::none(), py::kw_only(),
          py::arg("voxel_size") = py::none(), py::arg("dims") = py::none(), doc::kVoxelLattice)
      .def("voxelize", &voxel_grid, py::arg("res") = py::none(), py::arg("bounds") = py::none(),
           py::kw_only(), py::arg("voxel_size") = py::none(), py::arg("dims") = py::none(),
           py::arg("max_memory") = 4096, threads, doc::kVoxelize)
      .def("voxelize_brick", &voxel_brick, py::arg("res"), py::arg("box"),
           py::arg("bounds") = py::none(), py::kw_only(), py::arg("max_memory") = 4096, threads,
           doc::kVoxelizeBrick)
      .def(
          "to_bytes",
          [](const Model& a) {
            const std::string bytes = a.to_bytes();
            return py::bytes(bytes.data(), bytes.size());
          },
          doc::kToBytes)
      .def_static(
          "from_bytes",
          [](const py::bytes& bytes) {
            const std::string_view view = bytes;
            py::gil_scoped_release release;
            return Model::from_bytes(view);
          },
          py::arg("data"), doc::kFromBytes)
      .def(py::pickle(
          [](const Model& a) {
            const std::string bytes = a.to_bytes();
            return py::make_tuple(py::bytes(bytes.data(), bytes.size()));
          },
          [](const py::tuple& t) {
            if (t.size() != 1) throw InputError("pickled cover.Model: expected one bytes object");
            return Model::from_bytes(std::string_view(t[0].cast<py::bytes>()),
                                     "pickled cover.Model");
          }))
      .def("render", &render_image, py::arg("width"), py::arg("height"), py::arg("view") = "iso",
           py::arg("section") = py::none(), py::kw_only(), py::arg("perspective") = false,
           py::arg("up") = "z", py::arg("elevation") = py::none(), py::arg("azimuth") = 0.0,
           py::arg("zoom") = 1.0, py::arg("pan") = py::none(), py::arg("fit") = false,
           py::arg("samples") = 2, py::arg("crease") = 30.0, threads, doc::kRender)
      .def("evaluate", &evaluate_mesh, py::kw_only(), py::arg("leaf_ids") = false,
           py::arg("mesh_resolution") = 128, py::arg("mesh_tolerance") = 0.0, threads,
           doc::kEvaluate)
      .def("polygonize", &polygonize_mesh, py::kw_only(), py::arg("resolution") = 128,
           py::arg("cell_size") = py::none(), py::arg("tolerance") = 0.0,
           py::arg("max_memory") = 4096, threads, doc::kPolygonize)
      .def("clip", &clip_halves, py::arg("plane"), py::kw_only(), threads, doc::kClip)
      .def("evaluate_cells", &cell_pieces, py::arg("n"), py::arg("bounds") = py::none(),
           py::kw_only(), py::arg("max_memory") = 4096, threads, doc::kEvaluateCells)
      .def("decompose", &decompose_pieces, py::kw_only(), threads, doc::kDecompose)
      .def("info", &info_dict, py::kw_only(), py::arg("self_intersection") = true, doc::kInfo);

  m.def(
      "load",
      [](const std::filesystem::path& path, bool closed_only) {
        Model model;
        {
          py::gil_scoped_release release;
          LoadOptions options;
          options.require_closed = closed_only;
          model = cover::load(path, options);
        }
        return warned(std::move(model));
      },
      py::arg("path"), py::kw_only(), py::arg("closed_only") = false, doc::kLoad);
  m.def(
      "scene",
      [](py::object scene, const std::optional<std::filesystem::path>& base, bool closed_only) {
        std::string text;
        if (py::isinstance<py::str>(scene))
          text = scene.cast<std::string>();
        else
          text = py::module_::import("json").attr("dumps")(scene).cast<std::string>();
        Model model;
        {
          py::gil_scoped_release release;
          LoadOptions options;
          options.require_closed = closed_only;
          model = cover::scene(text, base.value_or(std::filesystem::path{}), options);
        }
        return warned(std::move(model));
      },
      py::arg("scene"), py::kw_only(), py::arg("base") = py::none(), py::arg("closed_only") = false,
      doc::kScene);
  // Any iterable of Models (a list, a generator), as Python's sum() takes.
  auto models_arg = [](const py::iterable& models) {
    std::vector<Model> out;
    for (py::handle h : models) out.push_back(h.cast<Model>());
    return out;
  };
  m.def(
      "union_all",
      [models_arg](const py::iterable& models) { return union_all(models_arg(models)); },
      py::arg("models"), doc::kUnionAll);
  m.def(
      "intersection_all",
      [models_arg](const py::iterable& models) { return intersection_all(models_arg(models)); },
      py::arg("models"), doc::kIntersectionAll);
  m.def(
      "box",
      [](py::handle lo, py::handle hi) { return box(vec3_arg(lo, "min"), vec3_arg(hi, "max")); },
      py::arg("min"), py::arg("max"), doc::kBox);
  m.def(
      "sphere",
      [](py::handle c, double r, int segments) {
        return sphere(vec3_arg(c, "center"), r, segments);
      },
      py::arg("center"), py::arg("radius"), py::arg("segments") = 32, doc::kSphere);
  m.def(
      "cylinder",
      [](py::handle base, py::handle top, double r, int segments) {
        return cylinder(vec3_arg(base, "base"), vec3_arg(top, "top"), r, segments);
      },
      py::arg("base"), py::arg("top"), py::arg("radius"), py::arg("segments") = 32, doc::kCylinder);
  m.def(
      "mesh",
      [](py::handle v, py::handle f, bool closed_only) {
        const Points vertices = points_arg(v, "V");
        const auto triangles = triangles_arg(f, vertices.span().size());
        Model model;
        {
          py::gil_scoped_release release;
          LoadOptions options;
          options.require_closed = closed_only;
          model = mesh(vertices.span(), triangles, "mesh", options);
        }
        return warned(std::move(model));
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("closed_only") = false, doc::kMesh);
  m.def(
      "points",
      [](py::handle p, py::handle n, int neighbours) {
        const Points points = points_arg(p, "P");
        std::optional<Points> normals;
        if (!n.is_none()) normals = points_arg(n, "N");
        Model model;
        {
          py::gil_scoped_release release;
          model = point_set(points.span(), normals ? normals->span() : std::span<const Vec3>(),
                            PointSetOptions{.neighbours = neighbours}, "P");
        }
        return model;
      },
      py::arg("P"), py::arg("N") = py::none(), py::kw_only(), py::arg("neighbours") = 16,
      doc::kPoints);
  bind_modeling(m);
  bind_files(m);
  bind_grids(m, model);
  bind_viewer(m);
}
