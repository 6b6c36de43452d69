// stress_csg: the random-CSG stress harness (docs/benchmarks.md "Random-CSG stress harness").
// For each seed a random 2–3-level scene of boxes and libcgal-demo meshes (random_scene.h) is
// evaluated, cut into cells at several N and decomposed, in a forked child per scene so that a
// crash or a hang is recorded for its stage and the run goes on; every output is checked by
// Cover's exact validity test and by CGAL (checks.h), and the evaluated volume against CGAL
// corefinement (cgal_oracle.h).
//
// Usage:
//   stress_csg --meshes DIR [--catalogue small|medium] [--first S] [--count C] [--seeds A,B,..]
//              [--cells 2,3,5,8] [--timeout SEC] [--threads T] [--memory MIB]
//              [--failures DIR] [--results FILE] [--verbose]
//   stress_csg --summarize [--failures DIR] [--label TEXT] RESULTS...
// Exit status: 0 when every outcome is ok, refused or unavailable; 1 otherwise; 2 bad usage.
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cgal_oracle.h"
#include "checks.h"
#include "cover/boolean/evaluate.h"
#include "cover/io/mesh_io.h"
#include "cover/io/scene.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "random_scene.h"
#include "summary.h"

namespace fs = std::filesystem;
using namespace cover;
using namespace cover::stress;

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  fs::path meshes;
  std::string catalogue = "medium";
  uint64_t first = 1;
  uint64_t count = 10;
  std::vector<uint64_t> seeds;  ///< explicit seeds (instead of first / count)
  std::vector<int> cells{2, 3, 5, 8};
  double timeout = 60;  ///< seconds per stage (the oracle gets 4×)
  int threads = 1;
  long memory_mib = 4096;  ///< address-space limit of a child; 0: none (sanitized builds)
  fs::path failures, results;
  bool verbose = false;
};

// Closed, self-intersection-free libcgal-demo meshes (checked at start-up as loaded, an
// inside-out one reversed: a mesh that fails is dropped with a note). `small` is the ctest slice's:
// a few hundred faces.
const std::vector<std::string> kSmall = {"tetrahedron.off", "octahedron.off", "icosahedron.off",
                                         "cross.off",       "tripod.off",     "sphere.off"};
const std::vector<std::string> kMedium = {
    "tetrahedron.off", "octahedron.off", "icosahedron.off", "cross.off",    "tripod.off",
    "sphere.off",      "ellipsoid.off",  "blob-closed.off", "dragknob.off", "part.off",
    "joint.off",       "eight.off",      "oblong.off",      "anchor.off",   "rotor.off",
    "cactus.off",      "spool.off",      "pinion.off",      "hand.off",     "helmet.off",
    "couplingdown.off"};

void put(int fd, const std::string& line) {
  std::string s = line + "\n";
  const char* p = s.data();
  size_t left = s.size();
  while (left > 0) {
    const ssize_t n = write(fd, p, left);
    if (n <= 0) return;
    p += n;
    left -= static_cast<size_t>(n);
  }
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\t' || c == '\n' || c == '\r') c = ' ';
  return s;
}

void limit_child(const Options& o) {
  if (o.memory_mib > 0) {
    const rlim_t bytes = static_cast<rlim_t>(o.memory_mib) << 20;
    const rlimit r{bytes, bytes};
    setrlimit(RLIMIT_AS, &r);
  }
  if (!o.verbose) {
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
  }
}

/// Runs `body(fd)` in a forked child and returns what it wrote to fd (empty on a crash).
std::string in_child(const Options& o, const std::function<void(int)>& body) {
  int p[2];
  if (pipe(p) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    close(p[0]);
    limit_child(o);
    body(p[1]);
    _exit(0);
  }
  close(p[1]);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = read(p[0], buf, sizeof buf)) > 0;) out.append(buf, static_cast<size_t>(n));
  close(p[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return out;
}

/// The catalogue's meshes that load as valid leaves (checked in a child: Cover's parallel code
/// never runs in this process, so forking stays safe).
std::vector<MeshEntry> load_catalogue(const Options& o) {
  const std::vector<std::string>& names = o.catalogue == "small" ? kSmall : kMedium;
  const std::string text = in_child(o, [&](int fd) {
    for (const std::string& name : names) {
      const fs::path path = fs::absolute(o.meshes / name);
      try {
        const LoadedInput in = load_input(path);
        const PolygonMesh m = leaf_mesh(in.solid, 0);
        const Outcome c = check_mesh(m);
        std::string why;
        if (in.solid.leaves[0].open())
          why = "open";
        else if (c.kind != "ok")
          why = c.detail;
        else if (!corefined_volume(in.solid, why))
          why = "CGAL: " + why;
        if (!why.empty()) {
          put(fd, "D\t" + name + "\t" + one_line(why));
          continue;
        }
        const Bbox b = face_bbox(m);
        char line[512];
        std::snprintf(line, sizeof line, "M\t%s\t%zu\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g",
                      path.c_str(), m.face_count(), b.min.x, b.min.y, b.min.z, b.max.x, b.max.y,
                      b.max.z);
        put(fd, line);
      } catch (const std::exception& e) {
        put(fd, "D\t" + name + "\t" + one_line(e.what()));
      }
    }
  });
  std::vector<MeshEntry> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream f(line);
    std::string tag, name;
    std::getline(f, tag, '\t');
    std::getline(f, name, '\t');
    if (tag == "D") {
      std::string why;
      std::getline(f, why);
      std::fprintf(stderr, "stress_csg: %s dropped from the catalogue: %s\n", name.c_str(),
                   why.c_str());
      continue;
    }
    MeshEntry m;
    m.path = name;
    f >> m.faces >> m.box.min.x >> m.box.min.y >> m.box.min.z >> m.box.max.x >> m.box.max.y >>
        m.box.max.z;
    out.push_back(m);
  }
  return out;
}

/// The failure folder's stage: cells-N are one folder "cells".
std::string failure_folder(const std::string& stage) {
  return stage.rfind("cells-", 0) == 0 ? "cells" : stage;
}

std::vector<std::string> stage_names(const Options& o) {
  std::vector<std::string> s{"oracle", "evaluate"};
  for (int n : o.cells) s.push_back("cells-" + std::to_string(n));
  s.push_back("decompose");
  return s;
}

/// The child of one scene: runs the stages from `start` on, writing "B stage" when one begins
/// and "R stage kind seconds detail" when it ends.
void run_stages(const Options& o, uint64_t seed, const std::string& json, size_t start,
                std::optional<double> reference, int fd) {
  const ThreadLimit threads(o.threads);
  const std::vector<std::string> names = stage_names(o);
  auto report = [&](size_t s, const Outcome& r, double seconds) {
    char secs[32];
    std::snprintf(secs, sizeof secs, "%.3f", seconds);
    put(fd, "R\t" + names[s] + "\t" + r.kind + "\t" + secs + "\t" + one_line(r.detail));
  };
  auto timed = [&](size_t s, const std::function<Outcome()>& f) {
    put(fd, "B\t" + names[s]);
    const auto t = Clock::now();
    Outcome r;
    try {
      r = f();
    } catch (...) {
      r = outcome_of_exception();
    }
    report(s, r, std::chrono::duration<double>(Clock::now() - t).count());
    if (!o.failures.empty() && r.evidence.face_count() > 0) {
      try {
        const fs::path dir = o.failures / (failure_folder(names[s]) + "-" + r.kind);
        fs::create_directories(dir);
        write_mesh(dir / ("seed-" + std::to_string(seed) + "-" + names[s] + ".off"), r.evidence);
      } catch (const std::exception&) {
      }
    }
    return r;
  };
  Solid solid;
  try {
    solid = parse_scene(json, "scene.json").solid;
  } catch (...) {
    for (size_t s = std::max<size_t>(start, 1); s < names.size(); ++s)
      report(s, s == 1 ? outcome_of_exception() : Outcome{"skipped", "the scene did not load"}, 0);
    return;
  }
  if (start == 0) {
    const Outcome r = timed(0, [&] {
      std::string why;
      const std::optional<double> v = corefined_volume(solid, why);
      if (!v) return Outcome{"unavailable", why};
      reference = v;
      char text[40];
      std::snprintf(text, sizeof text, "%.17g", *v);
      return Outcome{"ok", text};
    });
    (void)r;
  }
  PolygonMesh mesh;
  Outcome evaluated;
  if (start <= 1) {
    evaluated = timed(1, [&] { return stage_evaluate(solid, reference, mesh); });
  } else {
    try {
      mesh = evaluate(solid).mesh;
    } catch (...) {
      evaluated = outcome_of_exception();
    }
  }
  const bool usable = evaluated.kind == "ok" || evaluated.kind == "volume" ||
                      evaluated.kind == "touching" || evaluated.kind == "degenerate";
  for (size_t s = std::max<size_t>(start, 2); s < names.size(); ++s) {
    if (!usable) {
      report(s, {"skipped", "evaluate: " + evaluated.kind}, 0);
      continue;
    }
    if (s + 1 < names.size())
      timed(s, [&] { return stage_cells(solid, mesh, o.cells[s - 2]); });
    else
      timed(s, [&] { return stage_decompose(solid, mesh); });
  }
}

std::string signal_text(int sig) {
  const char* name = sigabbrev_np(sig);
  return std::string("signal ") + std::to_string(sig) +
         (name ? std::string(" (SIG") + name + ")" : "");
}

/// Runs every stage of one scene, restarting after a crash or a timeout with the next stage.
std::vector<Record> run_scene(const Options& o, uint64_t seed, const RandomScene& scene) {
  const std::vector<std::string> names = stage_names(o);
  std::vector<std::optional<Record>> done(names.size());
  std::optional<double> reference;
  size_t next = 0;
  auto record = [&](size_t s, const std::string& kind, double seconds, const std::string& detail) {
    done[s] = Record{seed, names[s], kind, seconds, detail, scene.description};
    if (s == 0 && kind == "ok") reference = std::stod(detail);
  };
  while (next < names.size()) {
    int p[2];
    if (pipe(p) != 0) break;
    const pid_t pid = fork();
    if (pid == 0) {
      close(p[0]);
      limit_child(o);
      run_stages(o, seed, scene.json, next, reference, p[1]);
      _exit(0);
    }
    close(p[1]);
    // The stage running or about to run (a restarted child re-evaluates within its limit).
    size_t active = next;
    auto started = Clock::now();
    std::string buffer;
    bool timed_out = false;
    for (;;) {
      const double limit = (active == 0 ? 4 : 1) * o.timeout;
      const double left = limit - std::chrono::duration<double>(Clock::now() - started).count();
      if (left <= 0) {
        timed_out = true;
        kill(pid, SIGKILL);
        break;
      }
      pollfd pf{p[0], POLLIN, 0};
      const int ready = poll(&pf, 1, static_cast<int>(left * 1000) + 1);
      if (ready == 0 || (ready < 0 && errno == EINTR)) continue;
      if (ready < 0) break;
      char buf[4096];
      const ssize_t n = read(p[0], buf, sizeof buf);
      if (n <= 0) break;
      buffer.append(buf, static_cast<size_t>(n));
      for (size_t eol; (eol = buffer.find('\n')) != std::string::npos;) {
        std::vector<std::string> f;
        std::istringstream in(buffer.substr(0, eol));
        buffer.erase(0, eol + 1);
        for (std::string x; std::getline(in, x, '\t');) f.push_back(x);
        size_t s = 0;
        while (s < names.size() && (f.size() < 2 || names[s] != f[1])) ++s;
        if (s == names.size()) continue;
        if (f[0] == "B") {
          active = s;
          started = Clock::now();
        } else if (f[0] == "R" && f.size() >= 4) {
          record(s, f[2], std::stod(f[3]), f.size() > 4 ? f[4] : "");
          active = s + 1;
          started = Clock::now();
        }
      }
    }
    close(p[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (active >= names.size()) break;
    const double secs = std::chrono::duration<double>(Clock::now() - started).count();
    if (timed_out)
      record(active, "timeout", secs,
             "no result after " + std::to_string(static_cast<int>(secs)) + " s");
    else
      record(active, "crash", secs,
             WIFSIGNALED(status) ? signal_text(WTERMSIG(status))
                                 : "exit " + std::to_string(WEXITSTATUS(status)));
    next = active + 1;
    if (active == 1) {  // no evaluated mesh: the later stages have nothing to cut
      for (size_t s = 2; s < names.size(); ++s)
        record(s, "skipped", 0, "evaluate: " + done[1]->kind);
      next = names.size();
    }
  }
  std::vector<Record> out;
  for (auto& r : done)
    if (r) out.push_back(*r);
  return out;
}

/// Failing case files: DIR/<stage>-<kind>/seed-<s>.json and .txt (one line per outcome); the
/// child has written the failing output mesh beside them (seed-<s>-<stage>.off).
void write_failure(const Options& o, const RandomScene& scene, const Record& r) {
  if (o.failures.empty() || r.kind == "ok" || r.kind == "skipped") return;
  const fs::path dir = o.failures / (failure_folder(r.stage) + "-" + r.kind);
  fs::create_directories(dir);
  const std::string base = "seed-" + std::to_string(r.seed);
  std::ofstream(dir / (base + ".json")) << scene.json;
  std::ofstream(dir / (base + ".txt"), std::ios::app)
      << "seed " << r.seed << " " << r.stage << " " << r.kind << ": " << r.detail << " | scene "
      << scene.description << "\n";
}

bool parse_list(const std::string& text, const std::function<void(const std::string&)>& add) {
  std::istringstream in(text);
  for (std::string x; std::getline(in, x, ',');) {
    if (x.empty()) return false;
    add(x);
  }
  return true;
}

int usage(const char* why) {
  std::fprintf(stderr,
               "stress_csg: %s\nusage: stress_csg --meshes DIR [--catalogue small|medium] "
               "[--first S] [--count C] [--seeds A,B,..] [--cells 2,3,5,8] [--timeout SEC] "
               "[--threads T] [--memory MIB] [--failures DIR] [--results FILE] [--verbose]\n"
               "       stress_csg --summarize [--failures DIR] [--label TEXT] RESULTS...\n",
               why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  bool summarize = false;
  std::string label;
  std::vector<fs::path> inputs;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--meshes")
        o.meshes = value();
      else if (a == "--catalogue")
        o.catalogue = value();
      else if (a == "--first")
        o.first = std::stoull(value());
      else if (a == "--count")
        o.count = std::stoull(value());
      else if (a == "--seeds") {
        if (!parse_list(value(), [&](const std::string& x) { o.seeds.push_back(std::stoull(x)); }))
          return usage("--seeds: expected A,B,...");
      } else if (a == "--cells") {
        o.cells.clear();
        if (!parse_list(value(), [&](const std::string& x) { o.cells.push_back(std::stoi(x)); }))
          return usage("--cells: expected N,N,...");
      } else if (a == "--timeout")
        o.timeout = std::stod(value());
      else if (a == "--threads")
        o.threads = std::stoi(value());
      else if (a == "--memory")
        o.memory_mib = std::stol(value());
      else if (a == "--failures")
        o.failures = value();
      else if (a == "--results")
        o.results = value();
      else if (a == "--label")
        label = value();
      else if (a == "--verbose")
        o.verbose = true;
      else if (a == "--summarize")
        summarize = true;
      else if (!a.empty() && a[0] != '-' && summarize)
        inputs.push_back(a);
      else
        return usage(("unknown argument " + a).c_str());
    }
  } catch (const std::exception& e) {
    return usage(e.what());
  }
  if (summarize) {
    std::vector<Record> all;
    for (const fs::path& p : inputs) {
      const std::vector<Record> r = read_records(p);
      all.insert(all.end(), r.begin(), r.end());
    }
    const std::string text = summary(all, label);
    std::fputs(text.c_str(), stdout);
    if (!o.failures.empty()) {
      fs::create_directories(o.failures);
      std::ofstream(o.failures / "SUMMARY.txt") << text;
    }
    return passed(all) ? 0 : 1;
  }
  if (o.meshes.empty()) return usage("--meshes DIR is required");
  if (o.catalogue != "small" && o.catalogue != "medium")
    return usage("--catalogue: small or medium");
  const std::vector<MeshEntry> meshes = load_catalogue(o);
  if (meshes.empty()) return usage("no usable mesh in the catalogue");
  if (o.seeds.empty())
    for (uint64_t s = o.first; s < o.first + o.count; ++s) o.seeds.push_back(s);
  std::ofstream results;
  if (!o.results.empty()) results.open(o.results, std::ios::app);
  std::vector<Record> all;
  for (uint64_t seed : o.seeds) {
    const RandomScene scene = random_scene(seed, meshes);
    const auto t = Clock::now();
    const std::vector<Record> records = run_scene(o, seed, scene);
    std::string line = "seed " + std::to_string(seed);
    for (const Record& r : records) {
      write_failure(o, scene, r);
      if (results.is_open()) results << format_record(r) << std::flush;
      if (r.kind != "ok" || o.verbose) line += "  " + r.stage + " " + r.kind;
      all.push_back(r);
    }
    char secs[32];
    std::snprintf(secs, sizeof secs, "  (%.1f s)",
                  std::chrono::duration<double>(Clock::now() - t).count());
    std::printf("%s%s\n", line.c_str(), secs);
    std::fflush(stdout);
  }
  std::fputs(summary(all, label).c_str(), stdout);
  return passed(all) ? 0 : 1;
}
