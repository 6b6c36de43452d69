#include "cover/view/viewer.h"

#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "cover/covering/classify.h"
#include "cover/io/png.h"
#include "cover/model/model.h"
#include "cover/render/object_order.h"
#include "cover/render/render.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

using json = nlohmann::json;

/// 128 random bits as 32 hex digits.
std::string random_token() {
  std::random_device rd;
  std::string t;
  const char* hex = "0123456789abcdef";
  for (int i = 0; i < 8; ++i) {
    const uint32_t r = rd();
    for (int k = 0; k < 4; ++k) t += hex[(r >> (4 * k)) & 15];
  }
  return t;
}

bool is_scene(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".json";
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw InputError(p.string() + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A file's identity for change detection: its modification time and size (-1: missing).
struct Stamp {
  int64_t mtime = -1, size = -1;
  bool operator==(const Stamp&) const = default;
};

Stamp stamp(const std::filesystem::path& p) {
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(p, ec);
  if (ec) return {};
  const auto size = std::filesystem::file_size(p, ec);
  if (ec) return {};
  return {static_cast<int64_t>(t.time_since_epoch().count()), static_cast<int64_t>(size)};
}

/// The files a scene names: every string in it that names a regular file next to the scene
/// (relative paths are relative to the scene's folder, as the loader reads them).
void named_files(const json& j, const std::filesystem::path& dir,
                 std::vector<std::filesystem::path>& out) {
  if (j.is_string()) {
    const std::filesystem::path p = dir / j.get<std::string>();
    std::error_code ec;
    if (j.get<std::string>().size() < 4096 && std::filesystem::is_regular_file(p, ec))
      out.push_back(p);
  } else if (j.is_array() || j.is_object()) {
    for (const json& c : j) named_files(c, dir, out);
  }
}

/// Removes the node at `ptr` from `scene`: from its parent's operand list, and an operation (or
/// a node holding it under an object key) left without it goes in turn. False when the root
/// itself goes: nothing is left.
bool prune(json& scene, json::json_pointer ptr) {
  while (!ptr.empty()) {
    json::json_pointer parent = ptr.parent_pointer();
    json& container = scene.at(parent);
    if (container.is_array()) {
      container.erase(static_cast<size_t>(std::stoul(ptr.back())));
      if (!container.empty()) return true;
      ptr = parent.parent_pointer();  // the operation whose list this was
    } else {
      ptr = parent;  // an object that cannot stand without this member
    }
  }
  return false;
}

/// A difference left with one operand is that operand: made a union of one (the scene format
/// wants two or more operands for a difference). After every prune(): renaming a key would
/// change the pointers of the leaves still to go.
void single_differences_to_unions(json& node) {
  if (node.is_object()) {
    const auto it = node.find("difference");
    if (it != node.end() && it->is_array() && it->size() == 1) {
      json operands = std::move(*it);
      node.erase("difference");
      node["union"] = std::move(operands);
    }
  }
  if (node.is_object() || node.is_array())
    for (json& c : node) single_differences_to_unions(c);
}

/// A parameter of a request; `fallback` when absent.
std::string param(const httplib::Request& req, const char* name, const std::string& fallback) {
  return req.has_param(name) ? req.get_param_value(name) : fallback;
}

double number(const httplib::Request& req, const char* name, double fallback) {
  if (!req.has_param(name)) return fallback;
  const std::string s = req.get_param_value(name);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v))
    throw InputError(std::string(name) + ": expected a number, got '" + s + "'");
  return v;
}

std::vector<double> numbers(const std::string& name, const std::string& s, size_t count) {
  std::vector<double> v;
  size_t begin = 0;
  for (;;) {
    const size_t end = std::min(s.find(',', begin), s.size());
    const std::string part = s.substr(begin, end - begin);
    char* stop = nullptr;
    const double x = std::strtod(part.c_str(), &stop);
    if (part.empty() || *stop != '\0' || !std::isfinite(x))
      throw InputError(name + ": expected " + std::to_string(count) + " numbers, got '" + s + "'");
    v.push_back(x);
    if (end == s.size()) break;
    begin = end + 1;
  }
  if (v.size() != count)
    throw InputError(name + ": expected " + std::to_string(count) + " numbers, got '" + s + "'");
  return v;
}

/// A frame request: the view and render options of `cover render` under the same names.
struct FrameRequest {
  CameraOptions camera;
  RenderOptions render;
  std::vector<uint32_t> hidden;  ///< leaves of the loaded input left out, increasing
};

FrameRequest parse_frame(const httplib::Request& req, const ViewerOptions& vo) {
  FrameRequest f;
  CameraOptions& c = f.camera;
  const double w = number(req, "w", 800), h = number(req, "h", 600);
  if (w < 1 || h < 1 || w > vo.max_side || h > vo.max_side || w != std::floor(w) ||
      h != std::floor(h))
    throw InputError("w, h: expected whole numbers from 1 to " + std::to_string(vo.max_side));
  c.width = static_cast<int>(w);
  c.height = static_cast<int>(h);
  c.view = parse_view(param(req, "view", "iso"));
  c.up = parse_up(param(req, "up", "z"));
  if (req.has_param("elevation")) c.elevation_degrees = number(req, "elevation", 0);
  c.azimuth_degrees = number(req, "azimuth", 0);
  c.zoom = number(req, "zoom", 1);
  c.perspective = param(req, "perspective", "0") == "1";
  c.fit = param(req, "fit", "0") == "1";
  if (req.has_param("pan")) {
    const std::vector<double> p = numbers("pan", req.get_param_value("pan"), 2);
    c.pan = {p[0], p[1]};
  }
  RenderOptions& r = f.render;
  const double samples = number(req, "samples", 2);
  if (samples < 1 || samples > kMaxRenderSamples || samples != std::floor(samples))
    throw InputError("samples: expected a whole number from 1 to " +
                     std::to_string(kMaxRenderSamples));
  r.samples = static_cast<int>(samples);
  r.outline = param(req, "outline", "1") == "1";
  r.crease_degrees = number(req, "crease", 30);
  if (!(r.crease_degrees >= 0 && r.crease_degrees <= 180))
    throw InputError("crease: expected a number from 0 to 180");
  if (req.has_param("section") && !req.get_param_value("section").empty()) {
    const std::vector<double> p = numbers("section", req.get_param_value("section"), 4);
    if (p[0] == 0 && p[1] == 0 && p[2] == 0)
      throw InputError("section: the normal must be non-zero");
    r.section = Plane{{p[0], p[1], p[2]}, p[3]};
  }
  if (c.fit && !r.section) throw InputError("fit: needs a section");
  if (req.has_param("hidden") && !req.get_param_value("hidden").empty()) {
    const std::string s = req.get_param_value("hidden");
    size_t begin = 0;
    for (;;) {
      const size_t end = std::min(s.find(',', begin), s.size());
      const std::string part = s.substr(begin, end - begin);
      if (part.empty() || part.size() > 9 ||
          part.find_first_not_of("0123456789") != std::string::npos)
        throw InputError("hidden: expected leaf indices, got '" + s + "'");
      f.hidden.push_back(static_cast<uint32_t>(std::stoul(part)));
      if (end == s.size()) break;
      begin = end + 1;
    }
    std::sort(f.hidden.begin(), f.hidden.end());
    f.hidden.erase(std::unique(f.hidden.begin(), f.hidden.end()), f.hidden.end());
  }
  if (render_bytes(c.width, c.height, r.samples) > static_cast<double>(vo.max_memory_bytes))
    throw InputError("w, h: the frame needs more memory than the viewer's limit");
  return f;
}

}  // namespace

const std::string& viewer_page();

struct Viewer::Impl {
  std::filesystem::path input;
  ViewerOptions options;
  std::string token;
  int port = 0;
  httplib::Server server;
  std::thread serve_thread, poll_thread;
  std::atomic<bool> stopping{false};
  std::mutex stop_mutex;
  std::condition_variable stop_cv;

  // The loaded input; `mutex` guards everything below (renders run one at a time: each is
  // parallel inside).
  mutable std::mutex mutex;
  std::shared_ptr<const Model> model;
  std::string scene_text;  ///< the scene's JSON as loaded (empty for a mesh input)
  std::vector<std::pair<std::filesystem::path, Stamp>> watched;
  ViewerState state;
  // The model with some leaves hidden, for the last hidden set asked for.
  std::vector<uint32_t> cached_hidden;
  std::shared_ptr<const Model> cached;
  std::vector<uint32_t> cached_leaves;  ///< the loaded input's leaf index of each cached leaf

  /// Loads the input and the list of files to watch; throws InputError.
  void load() {
    std::vector<std::filesystem::path> files{input};
    std::string text;
    if (is_scene(input)) {
      text = read_text(input);
      try {
        named_files(json::parse(text), input.parent_path(), files);
      } catch (const json::exception&) {
        // parse_scene below reports the error with its place
      }
    }
    std::vector<std::pair<std::filesystem::path, Stamp>> stamps;
    for (const auto& f : files) stamps.push_back({f, stamp(f)});
    LoadedInput loaded = load_input(input, options.load);
    auto m = std::make_shared<const Model>(std::move(loaded.solid), std::move(loaded.warnings));
    std::lock_guard lock(mutex);
    model = std::move(m);
    scene_text = std::move(text);
    watched = std::move(stamps);
    cached.reset();
    cached_hidden.clear();
    cached_leaves.clear();
  }

  /// The model to draw with `hidden` leaves left out, and each of its leaves' index in the
  /// loaded input. Called with `mutex` held.
  std::shared_ptr<const Model> shown(const std::vector<uint32_t>& hidden,
                                     std::vector<uint32_t>& leaves) {
    const size_t n = model->leaf_count();
    if (hidden.empty() || hidden.front() >= n) {
      leaves.resize(n);
      for (size_t l = 0; l < n; ++l) leaves[l] = static_cast<uint32_t>(l);
      return model;
    }
    if (cached && hidden == cached_hidden) {
      leaves = cached_leaves;
      return cached;
    }
    leaves.clear();
    for (uint32_t l = 0; l < n; ++l)
      if (!std::binary_search(hidden.begin(), hidden.end(), l)) leaves.push_back(l);
    std::shared_ptr<const Model> m;
    if (scene_text.empty()) {  // a mesh input: its one leaf hidden
      m = std::make_shared<const Model>();
    } else {
      json scene = json::parse(scene_text);
      bool left = true;
      // Prune the deepest-last pointers first: removing an element shifts its later siblings,
      // so the hidden leaves go in decreasing order of their (document-order) index.
      for (auto it = hidden.rbegin(); it != hidden.rend() && left; ++it) {
        if (*it >= n) continue;
        const std::string& origin = model->solid().leaves[*it].origin;
        json::json_pointer leaf_ptr(origin);
        left = prune(scene, leaf_ptr.parent_pointer());
      }
      single_differences_to_unions(scene);
      if (!left) {
        m = std::make_shared<const Model>();
        leaves.clear();
      } else {
        LoadedInput loaded = parse_scene(scene.dump(), input, options.load);
        m = std::make_shared<const Model>(std::move(loaded.solid));
        if (m->leaf_count() != leaves.size())
          throw InputError("view: hiding leaves changed the other leaves (" +
                           std::to_string(m->leaf_count()) + " left of " +
                           std::to_string(leaves.size()) + ")");
      }
    }
    cached = m;
    cached_hidden = hidden;
    cached_leaves = leaves;
    return m;
  }

  json info() const {
    std::lock_guard lock(mutex);
    json j;
    j["input"] = input.string();
    j["version"] = state.version;
    j["error"] = state.error;
    j["leaves"] = json::array();
    const Solid& s = model->solid();
    for (size_t l = 0; l < s.leaves.size(); ++l) {
      const std::array<uint8_t, 3> c = display_colour(s, static_cast<uint32_t>(l));
      j["leaves"].push_back({{"index", l},
                             {"name", s.leaves[l].name},
                             {"origin", s.leaves[l].origin},
                             {"colour", {c[0], c[1], c[2]}}});
    }
    const std::optional<Bbox> b = model->bounds();
    if (b) j["bbox"] = {{b->min.x, b->min.y, b->min.z}, {b->max.x, b->max.y, b->max.z}};
    return j;
  }

  std::vector<uint8_t> frame(const FrameRequest& f) {
    std::lock_guard lock(mutex);
    std::vector<uint32_t> leaves;
    const std::shared_ptr<const Model> m = shown(f.hidden, leaves);
    RenderOptions ro = f.render;
    if (!f.hidden.empty())
      for (uint32_t l : leaves) ro.leaf_colours.push_back(display_colour(model->solid(), l));
    const Image image = m->render(m->camera(f.camera, ro.section), ro);
    return encode_png_rgb(image.width, image.height, image.rgb);
  }

  /// The point seen at pixel (x, y) of the frame: where the pixel-centre ray enters the result
  /// (or the section's cap), its exact class, and its leaf.
  json pick(const FrameRequest& f, int x, int y) {
    std::lock_guard lock(mutex);
    std::vector<uint32_t> leaves;
    const std::shared_ptr<const Model> m = shown(f.hidden, leaves);
    const Camera cam = m->camera(f.camera, f.render.section);
    json j;
    j["x"] = x;
    j["y"] = y;
    j["hit"] = false;
    if (x < 0 || y < 0 || x >= cam.width || y >= cam.height || m->empty()) return j;
    // What the renderer shows at the pixel centre: the first span within the section's window.
    const Ray ray = cam.ray(x, y);
    const auto [lo, hi] = section_window(ray, f.render.section);
    if (lo > hi) return j;
    const VisibleHit v = first_visible(m->cast(std::vector<Ray>{ray})[0], lo, hi);
    if (!v.hit) return j;
    const Vec3 p = ray.origin + v.t * ray.dir;
    j["hit"] = true;
    j["point"] = {p.x, p.y, p.z};
    j["class"] = std::string(to_string(m->classify(std::vector<Vec3>{p})[0]));
    if (v.cap) {
      j["leaf"] = "section cap";
    } else {
      const uint32_t l = leaves.at(v.enter.leaf);
      j["leaf"] = model->solid().leaves[l].name;
      j["leaf_index"] = l;
      j["origin"] = model->solid().leaves[l].origin;
    }
    return j;
  }
};

namespace {

void fail(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(message + "\n", "text/plain; charset=utf-8");
}

bool loopback(const std::string& host) {
  return host == "127.0.0.1" || host == "localhost" || host == "::1";
}

}  // namespace

Viewer::Viewer(std::filesystem::path input, ViewerOptions options) : impl_(new Impl) {
  Impl& d = *impl_;
  d.input = std::move(input);
  d.options = std::move(options);
  if (!(d.options.poll_seconds > 0) || d.options.poll_seconds > 3600)
    throw InputError("poll: expected seconds from 0 to 3600");
  if (d.options.port < 0 || d.options.port > 65535)
    throw InputError("port: expected a number from 0 to 65535, got " +
                     std::to_string(d.options.port));
  d.token = random_token();
  d.load();
  httplib::Server& s = d.server;
  // SO_REUSEADDR only: the library's default adds SO_REUSEPORT, with which a second viewer
  // would bind the same port and share its requests instead of being told the port is taken.
  s.set_socket_options([](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  s.set_pre_routing_handler([&d](const httplib::Request& req, httplib::Response& res) {
    if (loopback(d.options.host)) {  // a page on another site cannot reach us by DNS rebinding
      const std::string host = req.get_header_value("Host");
      const std::string port = ":" + std::to_string(d.port);
      if (host != "127.0.0.1" + port && host != "localhost" + port && host != "[::1]" + port) {
        fail(res, 403, "forbidden: Host " + host);
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    if (!req.has_param("t") || req.get_param_value("t") != d.token) {
      fail(res, 403, "forbidden: open the address `cover view` printed (its t= token)");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  s.Get("/", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(viewer_page(), "text/html; charset=utf-8");
  });
  s.Get("/info", [&d](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(d.info().dump(), "application/json");
  });
  s.Get("/frame", [&d](const httplib::Request& req, httplib::Response& res) {
    try {
      const std::vector<uint8_t> png = d.frame(parse_frame(req, d.options));
      res.set_header("Cache-Control", "no-store");
      res.set_content(std::string(png.begin(), png.end()), "image/png");
    } catch (const std::exception& e) {
      fail(res, 400, e.what());
    }
  });
  s.Get("/pick", [&d](const httplib::Request& req, httplib::Response& res) {
    try {
      const FrameRequest f = parse_frame(req, d.options);
      const double x = number(req, "x", -1), y = number(req, "y", -1);
      res.set_content(
          d.pick(f, static_cast<int>(std::floor(x)), static_cast<int>(std::floor(y))).dump(),
          "application/json");
    } catch (const std::exception& e) {
      fail(res, 400, e.what());
    }
  });
  if (d.options.port == 0) {
    d.port = s.bind_to_any_port(d.options.host);
    if (d.port <= 0) throw InputError("view: cannot listen on " + d.options.host);
  } else {
    if (!s.bind_to_port(d.options.host, d.options.port))
      throw InputError("view: cannot listen on " + d.options.host + ":" +
                       std::to_string(d.options.port) + " (in use?)");
    d.port = d.options.port;
  }
  d.serve_thread = std::thread([&d] { d.server.listen_after_bind(); });
  d.poll_thread = std::thread([this] {
    Impl& d = *impl_;
    const auto period = std::chrono::duration<double>(d.options.poll_seconds);
    std::unique_lock lock(d.stop_mutex);
    while (!d.stop_cv.wait_for(lock, period, [&d] { return d.stopping.load(); })) {
      lock.unlock();
      check_files();
      lock.lock();
    }
  });
}

Viewer::~Viewer() { stop(); }

bool Viewer::check_files() {
  Impl& d = *impl_;
  std::vector<std::pair<std::filesystem::path, Stamp>> watched;
  {
    std::lock_guard lock(d.mutex);
    watched = d.watched;
  }
  bool changed = false;
  for (const auto& [path, was] : watched) changed = changed || stamp(path) != was;
  if (!changed) return false;
  // An editor may still be writing: wait for the files to stay the same for a moment.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  try {
    d.load();
    std::lock_guard lock(d.mutex);
    ++d.state.version;
    d.state.error.clear();
  } catch (const std::exception& e) {
    std::lock_guard lock(d.mutex);
    d.state.error = e.what();
    // Watch the new stamps, so that the same broken file is not reloaded again and again.
    for (auto& [path, st] : d.watched) st = stamp(path);
  }
  return true;
}

std::string Viewer::url() const {
  const std::string host = impl_->options.host == "0.0.0.0" ? "127.0.0.1" : impl_->options.host;
  return "http://" + host + ":" + std::to_string(impl_->port) + "/?t=" + impl_->token;
}
int Viewer::port() const { return impl_->port; }
const std::string& Viewer::token() const { return impl_->token; }
ViewerState Viewer::state() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->state;
}

std::vector<std::string> Viewer::warnings(
    const std::function<std::string(std::string_view)>& name_of) const {
  std::lock_guard lock(impl_->mutex);
  return impl_->model->warnings(name_of);
}

void Viewer::stop() {
  Impl& d = *impl_;
  {
    std::lock_guard lock(d.stop_mutex);
    if (d.stopping.exchange(true)) return;
  }
  d.stop_cv.notify_all();
  d.server.stop();
  if (d.serve_thread.joinable()) d.serve_thread.join();
  if (d.poll_thread.joinable()) d.poll_thread.join();
}

}  // namespace cover
