// Cover's preview render against Intel Embree 3 (the fastest CPU ray tracer; Debian
// libembree-dev), in one process on the same machine, both on `--threads` threads (default 2:
// a TBB global limit for Cover, "threads=N" for Embree's device and a task arena of N for its
// frame loop). Input: a JSON scene (bench/preview_scene.py writes the 10-leaf preview scene) or
// one mesh file; 1024×1024, the iso orthographic camera Cover frames on the result's box.
//   Cover first frame:  cover::load (parse, transform, leaf checks, CSG concatenation) + BVH +
//                       render() — the exact CSG image of `cover render`.
//   Embree first frame: the same mesh files parsed by Cover's reader (the fastest reader at hand;
//                       no leaf checks; each distinct file once, as Cover's loader) and
//                       transformed, fan triangles into float buffers,
//                       rtcCommitScene, and a first-hit frame (rtcIntersect8 packets of 4×2
//                       pixels) of the same triangles WITHOUT any CSG (the union of all leaves'
//                       surfaces, not the CSG result).
//   Later frames:       Cover's render() on the already-built Model against Embree's first-hit
//                       frame (single rays, rtcIntersect1; and 4×2 packets, rtcIntersect8) and its
//                       every-hit frame (rtcIntersect1 with a context intersection filter that
//                       records every hit along the ray and rejects it, so the walk goes on:
//                       what a CSG ray caster needs before any span logic).
// Every frame writes an RGB image (headlight shading), so no side does less than drawing.
// Figures: medians of --runs (default 3) interleaved runs (Cover, Embree, Cover, ...); per-ray
// times are a frame's wall time over its pixels; cpu_s: the same spans in process CPU time (user
// + system of all threads), a measure a loaded host disturbs less. Embree's device (its thread
// pool) is created outside the timings, as Cover's TBB pool exists before its load. Checks: Cover's
// images for 1 and N threads are identical (rgb, depth, ids); the later frame equals the first; and
// for a single mesh (no CSG) the pixels Cover and Embree see as covered agree (reported as a
// fraction: Embree uses floats). Usage: render_vs_embree INPUT [--runs 3] [--threads 2] [--size
// 1024] [--png OUT.png]
//        [--cover-only]   (--cover-only: Cover's timings alone, for profiling or A/B runs)
#include <embree3/rtcore.h>
#include <sys/resource.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "cover/io/mesh_io.h"
#include "cover/io/png.h"
#include "cover/model/model.h"
#include "cover/solid/parallel.h"
#include "cover/solid/transform.h"

namespace {

using bench::Clock;
using bench::since;
using nlohmann::json;

/// A mesh leaf of the input: its file and the product of the transforms above it.
struct LeafFile {
  std::filesystem::path file;
  cover::Transform world;
};

/// The mesh leaves of a scene (matrix transforms only: what preview_scene.py writes).
void collect_leaves(const json& j, const std::filesystem::path& scene,
                    const cover::Transform& parent, std::vector<LeafFile>& out) {
  cover::Transform world = parent;
  if (j.contains("transform")) {
    const json& t = j.at("transform");
    if (!t.contains("matrix")) throw std::runtime_error("render_vs_embree: matrix transforms only");
    std::array<double, 16> rows{};
    for (int i = 0; i < 16; ++i) rows[i] = t.at("matrix").at(i).get<double>();
    world = parent * cover::Transform::from_matrix(rows);
  }
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it.key() == "transform") continue;
    if (it.key() == "mesh") {
      std::filesystem::path f = it.value().get<std::string>();
      if (f.is_relative()) f = scene.parent_path() / f;
      out.push_back({f, world});
    } else if (it.key() == "complement") {
      collect_leaves(it.value(), scene, world, out);
    } else if (it.value().is_array()) {
      for (const json& k : it.value()) collect_leaves(k, scene, world, out);
    } else {
      throw std::runtime_error("render_vs_embree: mesh leaves only, found '" + it.key() + "'");
    }
  }
}

std::vector<LeafFile> input_leaves(const std::filesystem::path& input) {
  if (input.extension() != ".json") return {{input, cover::Transform{}}};
  std::ifstream f(input);
  std::vector<LeafFile> out;
  collect_leaves(json::parse(f), input, cover::Transform{}, out);
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

/// Headlight shade of a hit with geometric normal n (any orientation) for ray direction d.
uint8_t shade(float nx, float ny, float nz, const cover::Vec3& d) {
  const double l = std::sqrt(double(nx) * nx + double(ny) * ny + double(nz) * nz);
  const double c = l > 0 ? std::abs(nx * d.x + ny * d.y + nz * d.z) / l : 0;
  return static_cast<uint8_t>(40 + 200 * c);
}

/// Embree's side: a device with N threads and the scene of the input's triangles.
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  size_t triangles = 0;
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

/// Parses each distinct file once and transforms a copy per leaf (in parallel, as Cover's scene
/// loader does), copies their fan triangles into one float geometry per leaf, and commits the
/// scene; returns the seconds of rtcCommitScene (the BVH build).
double embree_load(const std::vector<LeafFile>& leaves, EmbreeScene& e) {
  std::vector<std::filesystem::path> files;
  std::vector<size_t> file_of(leaves.size());
  for (size_t i = 0; i < leaves.size(); ++i) {
    const auto it = std::find(files.begin(), files.end(), leaves[i].file);
    file_of[i] = static_cast<size_t>(it - files.begin());
    if (it == files.end()) files.push_back(leaves[i].file);
  }
  std::vector<cover::PolygonMesh> read(files.size());
  cover::parallel_for(files.size(), 1, [&](size_t b, size_t end) {
    for (size_t i = b; i < end; ++i) read[i] = cover::read_mesh(files[i]);
  });
  std::vector<cover::PolygonMesh> meshes(leaves.size());
  cover::parallel_for(leaves.size(), 1, [&](size_t b, size_t end) {
    for (size_t i = b; i < end; ++i) {
      meshes[i] = read[file_of[i]];
      cover::apply_transform(leaves[i].world, meshes[i]);
    }
  });
  e.triangles = 0;
  for (const cover::PolygonMesh& m : meshes) {
    size_t tris = 0;
    for (size_t f = 0; f < m.face_count(); ++f) tris += m.face(f).size() - 2;
    RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris));
    cover::parallel_for(m.vertices.size(), 1 << 15, [&](size_t b, size_t end) {
      for (size_t i = b; i < end; ++i)
        for (int a = 0; a < 3; ++a) v[3 * i + a] = static_cast<float>(m.vertices[i][a]);
    });
    size_t k = 0;
    for (size_t f = 0; f < m.face_count(); ++f) {
      const auto face = m.face(f);
      for (size_t i = 1; i + 1 < face.size(); ++i) {
        idx[3 * k] = face[0];
        idx[3 * k + 1] = face[i];
        idx[3 * k + 2] = face[i + 1];
        ++k;
      }
    }
    e.triangles += tris;
    rtcCommitGeometry(g);
    rtcAttachGeometry(e.scene, g);
    rtcReleaseGeometry(g);
  }
  const auto t0 = Clock::now();
  rtcCommitScene(e.scene);
  return since(t0);
}

/// Every-hit context: counts the hits of one ray and keeps the nearest.
struct AllHits {
  RTCIntersectContext context;  // first: Embree passes &context back to the filter
  unsigned count = 0;
  float t = std::numeric_limits<float>::infinity();
  float nx = 0, ny = 0, nz = 0;
};

void collect_hit(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<AllHits*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    ++c->count;
    if (t < c->t) {
      c->t = t;
      c->nx = RTCHitN_Ng_x(args->hit, args->N, i);
      c->ny = RTCHitN_Ng_y(args->hit, args->N, i);
      c->nz = RTCHitN_Ng_z(args->hit, args->N, i);
    }
    args->valid[i] = 0;  // rejected: the traversal continues past it
  }
}

enum class EmbreeFrame { kSingle, kPacket, kEveryHit };

/// One frame through `cam`: per pixel a grey shade (0 for background) into `out`; returns the
/// total number of hits (every-hit frame) or of covered pixels.
size_t embree_frame(const EmbreeScene& e, const cover::Camera& cam, EmbreeFrame kind,
                    tbb::task_arena& arena, std::vector<uint8_t>& out) {
  out.assign(static_cast<size_t>(cam.width) * cam.height, 0);
  std::atomic<size_t> total{0};
  auto set_ray = [&](int px, int py, float& ox, float& oy, float& oz, float& dx, float& dy,
                     float& dz) {
    const cover::Ray r = cam.ray(px, py);
    ox = float(r.origin.x), oy = float(r.origin.y), oz = float(r.origin.z);
    dx = float(r.dir.x), dy = float(r.dir.y), dz = float(r.dir.z);
  };
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range2d<int>(0, cam.height, 32, 0, cam.width, 32),
                      [&](const tbb::blocked_range2d<int>& r) {
                        size_t local = 0;
                        if (kind == EmbreeFrame::kPacket) {
                          RTCIntersectContext ctx;
                          rtcInitIntersectContext(&ctx);
                          ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
                          for (int y0 = r.rows().begin(); y0 < r.rows().end(); y0 += 2)
                            for (int x0 = r.cols().begin(); x0 < r.cols().end(); x0 += 4) {
                              alignas(32) RTCRayHit8 rh;
                              alignas(32) int valid[8];
                              for (int k = 0; k < 8; ++k) {
                                const int px = x0 + k % 4, py = y0 + k / 4;
                                valid[k] = px < r.cols().end() && py < r.rows().end() ? -1 : 0;
                                set_ray(std::min(px, cam.width - 1), std::min(py, cam.height - 1),
                                        rh.ray.org_x[k], rh.ray.org_y[k], rh.ray.org_z[k],
                                        rh.ray.dir_x[k], rh.ray.dir_y[k], rh.ray.dir_z[k]);
                                rh.ray.tnear[k] = 0;
                                rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
                                rh.ray.mask[k] = ~0u;
                                rh.ray.time[k] = 0;
                                rh.ray.flags[k] = 0;
                                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                              }
                              rtcIntersect8(valid, e.scene, &ctx, &rh);
                              for (int k = 0; k < 8; ++k) {
                                const int px = x0 + k % 4, py = y0 + k / 4;
                                if (!valid[k] || rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID)
                                  continue;
                                ++local;
                                out[size_t(py) * cam.width + px] = shade(
                                    rh.hit.Ng_x[k], rh.hit.Ng_y[k], rh.hit.Ng_z[k], cam.forward);
                              }
                            }
                        } else {
                          for (int py = r.rows().begin(); py < r.rows().end(); ++py)
                            for (int px = r.cols().begin(); px < r.cols().end(); ++px) {
                              RTCRayHit rh;
                              set_ray(px, py, rh.ray.org_x, rh.ray.org_y, rh.ray.org_z,
                                      rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
                              rh.ray.tnear = 0;
                              rh.ray.tfar = std::numeric_limits<float>::infinity();
                              rh.ray.mask = ~0u;
                              rh.ray.time = 0;
                              rh.ray.flags = 0;
                              rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                              const cover::Vec3 d{rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z};
                              if (kind == EmbreeFrame::kSingle) {
                                RTCIntersectContext ctx;
                                rtcInitIntersectContext(&ctx);
                                rtcIntersect1(e.scene, &ctx, &rh);
                                if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                                ++local;
                                out[size_t(py) * cam.width + px] =
                                    shade(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z, d);
                              } else {
                                AllHits c;
                                rtcInitIntersectContext(&c.context);
                                c.context.filter = collect_hit;
                                rtcIntersect1(e.scene, &c.context, &rh);
                                local += c.count;
                                if (c.count > 0)
                                  out[size_t(py) * cam.width + px] = shade(c.nx, c.ny, c.nz, d);
                              }
                            }
                        }
                        total += local;
                      });
  });
  return total;
}

struct CoverRun {
  double load_s = 0, bvh_s = 0, frame_s = 0, first_frame_s = 0, later_frame_s = 0;
  double first_cpu_s = 0, later_cpu_s = 0;  ///< process CPU time (user + system, all threads)
};

/// CPU seconds of the whole process so far (user + system, every thread): a second measure that a
/// loaded host disturbs less than wall time (time spent waiting for a core is not counted).
double cpu_seconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double median_of(const std::vector<CoverRun>& runs, double CoverRun::*field) {
  std::vector<double> v;
  for (const CoverRun& c : runs) v.push_back(c.*field);
  return median(v);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: render_vs_embree INPUT [--runs 3] [--threads 2] [--size 1024] "
                 "[--png OUT.png]\n");
    return 2;
  }
  const std::filesystem::path input = argv[1];
  const int runs = static_cast<int>(bench::arg(argc, argv, "--runs", 3));
  const int threads = static_cast<int>(bench::arg(argc, argv, "--threads", 2));
  const int size = static_cast<int>(bench::arg(argc, argv, "--size", 1024));
  std::string png;
  bool cover_only = false;
  for (int i = 2; i < argc; ++i) {
    if (i + 1 < argc && std::string(argv[i]) == "--png") png = argv[i + 1];
    cover_only |= std::string(argv[i]) == "--cover-only";
  }
  const std::vector<LeafFile> leaves = input_leaves(input);

  cover::ThreadLimit limit(threads);  // Cover's TBB (and every TBB arena in the process)
  tbb::task_arena arena(threads);
  cover::CameraOptions co;
  co.width = co.height = size;
  // The camera (data only) from an untimed load: both sides trace the same rays.
  const cover::Camera cam = cover::load(input).camera(co);

  std::vector<CoverRun> cover_runs;
  std::vector<double> e_load, e_build, e_first, e_single, e_packet, e_every, e_first_cpu,
      e_every_cpu;
  size_t e_triangles = 0, e_hits = 0;
  cover::Image reference;
  bool later_identical = true;
  std::vector<uint8_t> e_image;
  const std::string config = "threads=" + std::to_string(threads);
  // One ray per pixel, as Embree's frames: no anti-aliasing (RenderOptions::samples).
  cover::RenderOptions one_ray;
  one_ray.samples = 1;
  for (int run = 0; run < runs; ++run) {
    {  // Cover
      CoverRun c;
      const auto t0 = Clock::now();
      const double cpu0 = cpu_seconds();
      const cover::Model model = cover::load(input);
      c.load_s = since(t0);
      // The BVH, when the render walks one (open leaves): built once per Model, timed apart.
      // The object-order path (closed leaves) needs none.
      if (!cover::renders_in_object_order(model.solid(), cam, one_ray)) model.bvh();
      c.bvh_s = since(t0) - c.load_s;
      const cover::Image first = model.render(cam, one_ray);
      c.first_frame_s = since(t0);
      c.frame_s = c.first_frame_s - c.load_s - c.bvh_s;
      c.first_cpu_s = cpu_seconds() - cpu0;
      const auto t1 = Clock::now();
      const double cpu1 = cpu_seconds();
      const cover::Image later = model.render(cam, one_ray);
      c.later_frame_s = since(t1);
      c.later_cpu_s = cpu_seconds() - cpu1;
      later_identical &=
          later.rgb == first.rgb && later.depth == first.depth && later.ids == first.ids;
      if (run == 0) reference = first;
      cover_runs.push_back(c);
    }
    if (cover_only) continue;
    {  // Embree
      EmbreeScene e;
      e.device = rtcNewDevice(config.c_str());  // its thread pool: started once per program
      const auto t0 = Clock::now();
      const double cpu0 = cpu_seconds();
      e.scene = rtcNewScene(e.device);
      rtcSetSceneFlags(e.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
      e_build.push_back(embree_load(leaves, e));
      const double load_build = since(t0);
      e_first.push_back(load_build);  // completed below with the first frame
      const auto t1 = Clock::now();
      embree_frame(e, cam, EmbreeFrame::kPacket, arena, e_image);
      const double packet_first = since(t1);
      e_first.back() += packet_first;
      e_first_cpu.push_back(cpu_seconds() - cpu0);
      e_load.push_back(load_build);
      e_triangles = e.triangles;
      const auto t2 = Clock::now();
      std::vector<uint8_t> img;
      embree_frame(e, cam, EmbreeFrame::kSingle, arena, img);
      e_single.push_back(since(t2));
      const auto t3 = Clock::now();
      embree_frame(e, cam, EmbreeFrame::kPacket, arena, img);
      e_packet.push_back(since(t3));
      const auto t4 = Clock::now();
      const double cpu4 = cpu_seconds();
      e_hits = embree_frame(e, cam, EmbreeFrame::kEveryHit, arena, img);
      e_every.push_back(since(t4));
      e_every_cpu.push_back(cpu_seconds() - cpu4);
    }
  }
  // Cover with one thread: the same image; and the same through the BVH walk per ray.
  bool threads_identical, methods_identical;
  {
    cover::ThreadLimit one(1);
    const cover::Image single = cover::load(input).render(cam, one_ray);
    threads_identical = single.rgb == reference.rgb && single.depth == reference.depth &&
                        single.ids == reference.ids;
  }
  {
    cover::RenderOptions rays = one_ray;
    rays.method = cover::RenderMethod::kRays;
    const cover::Image walked = cover::load(input).render(cam, rays);
    methods_identical = walked.rgb == reference.rgb && walked.depth == reference.depth &&
                        walked.ids == reference.ids;
  }
  if (cover_only) {
    std::printf(
        "{\"cover_load_s\": %.4f, \"cover_bvh_s\": %.4f, \"cover_frame_s\": %.4f, "
        "\"cover_later_frame_s\": %.4f, \"images_identical_1_vs_%d_threads\": %s, "
        "\"object_order_identical_to_rays\": %s}\n",
        median_of(cover_runs, &CoverRun::load_s), median_of(cover_runs, &CoverRun::bvh_s),
        median_of(cover_runs, &CoverRun::frame_s), median_of(cover_runs, &CoverRun::later_frame_s),
        threads, threads_identical ? "true" : "false", methods_identical ? "true" : "false");
    return threads_identical && later_identical && methods_identical ? 0 : 1;
  }
  // Coverage agreement (meaningful for a single mesh: no CSG on Embree's side).
  size_t agree = 0;
  const size_t pixels = static_cast<size_t>(cam.width) * cam.height;
  for (size_t i = 0; i < pixels; ++i)
    agree += (reference.ids[i] != cover::Image::kBackgroundId) == (e_image[i] != 0);
  if (!png.empty()) cover::write_png_rgb(png, reference.width, reference.height, reference.rgb);

  auto cm = [&](double CoverRun::*f) { return median_of(cover_runs, f); };
  const double c_first = cm(&CoverRun::first_frame_s), c_later = cm(&CoverRun::later_frame_s);
  const double ns = 1e9 / static_cast<double>(pixels);
  std::printf(
      "{\"input\": \"%s\", \"leaves\": %zu, \"embree_triangles\": %zu, \"pixels\": \"%dx%d\",\n",
      input.filename().string().c_str(), leaves.size(), e_triangles, cam.width, cam.height);
  std::printf(" \"threads\": %d, \"runs\": %d, \"embree\": \"%d.%d.%d\",\n", threads, runs,
              RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH);
  std::printf(
      " \"cover_load_s\": %.4f, \"cover_bvh_s\": %.4f, \"cover_frame_s\": %.4f, "
      "\"cover_first_frame_s\": %.4f, \"cover_later_frame_s\": %.4f,\n",
      cm(&CoverRun::load_s), cm(&CoverRun::bvh_s), cm(&CoverRun::frame_s), c_first, c_later);
  std::printf(
      " \"embree_load_build_s\": %.4f, \"embree_build_s\": %.4f, \"embree_first_frame_s\": %.4f, "
      "\"embree_single_frame_s\": %.4f, \"embree_packet_frame_s\": %.4f, "
      "\"embree_every_hit_frame_s\": %.4f, \"embree_hits_per_ray\": %.2f,\n",
      median(e_load), median(e_build), median(e_first), median(e_single), median(e_packet),
      median(e_every), static_cast<double>(e_hits) / pixels);
  std::printf(
      " \"ns_per_ray\": {\"cover\": %.1f, \"embree_single\": %.1f, \"embree_packet\": %.1f, "
      "\"embree_every_hit\": %.1f},\n",
      c_later * ns, median(e_single) * ns, median(e_packet) * ns, median(e_every) * ns);
  std::printf(
      " \"first_frame_ratio\": %.3f, \"later_vs_every_hit_ratio\": %.3f, "
      "\"later_vs_single_ratio\": %.3f, \"later_vs_packet_ratio\": %.3f,\n",
      c_first / median(e_first), c_later / median(e_every), c_later / median(e_single),
      c_later / median(e_packet));
  std::printf(
      " \"images_identical_1_vs_%d_threads\": %s, \"later_frame_identical\": %s, "
      "\"object_order_identical_to_rays\": %s, \"covered_pixels_agree\": %.5f,\n",
      threads, threads_identical ? "true" : "false", later_identical ? "true" : "false",
      methods_identical ? "true" : "false", static_cast<double>(agree) / pixels);
  std::printf(
      " \"cpu_s\": {\"cover_first_frame\": %.4f, \"cover_later_frame\": %.4f, "
      "\"embree_first_frame\": %.4f, \"embree_every_hit_frame\": %.4f},\n",
      cm(&CoverRun::first_cpu_s), cm(&CoverRun::later_cpu_s), median(e_first_cpu),
      median(e_every_cpu));
  std::printf(" \"cpu_first_frame_ratio\": %.3f, \"cpu_later_vs_every_hit_ratio\": %.3f}\n",
              cm(&CoverRun::first_cpu_s) / median(e_first_cpu),
              cm(&CoverRun::later_cpu_s) / median(e_every_cpu));
  return threads_identical && later_identical && methods_identical ? 0 : 1;
}
