// The viewer's page: plain HTML, CSS and JavaScript with no external resource (it works offline
// and loads nothing but the frames, picks and leaf list of its own server).
// Conventions: every request carries the page's token (t=); frames are requested one at a time
// (the latest view wins), at a quarter of the size with one sample while the view moves and at
// full size with the chosen samples once it has rested for 250 ms; data-state on the image is
// "idle" when the full-size frame of the current view is shown.

#include <string>

#include "cover/view/viewer.h"

namespace cover {

const std::string& viewer_page() {
  static const std::string page = R"HTML(<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>Cover view</title>
<style>
body{margin:0;font:13px system-ui,sans-serif;display:flex;height:100vh;color:#222}
#side{width:270px;padding:10px;overflow:auto;border-right:1px solid #ccc;background:#f7f7f7}
#main{flex:1;position:relative;overflow:hidden;background:#fff}
#frame{position:absolute;left:0;top:0;width:100%;height:100%;cursor:grab;user-select:none}
h1{font-size:15px;margin:0 0 8px} h2{font-size:13px;margin:12px 0 4px}
label{display:block;margin:3px 0} select,input[type=range]{width:100%}
.sw{display:inline-block;width:11px;height:11px;border:1px solid #555;margin-right:4px}
#leaves label{white-space:nowrap;overflow:hidden;text-overflow:ellipsis}
#leaves small{color:#777}
#pick,#status{white-space:pre-wrap;font-family:monospace;font-size:12px}
#error{color:#b00;white-space:pre-wrap}
</style></head><body>
<div id="side">
<h1>Cover view</h1>
<div id="input"></div>
<h2>Camera</h2>
<label>View <select id="view"><option>iso</option><option>front</option><option>back</option>
<option>left</option><option>right</option><option>top</option><option>bottom</option></select>
</label>
<label>Up <select id="up"><option>z</option><option>y</option><option>x</option></select></label>
<label><input type="checkbox" id="perspective"> perspective</label>
<label><button id="reset">Reset view</button></label>
<h2>Section</h2>
<label>Cut <select id="section-axis"><option value="">none</option><option>x</option>
<option>y</option><option>z</option></select></label>
<label><input type="range" id="section-offset" min="0" max="1000" value="500"></label>
<label><input type="checkbox" id="flip"> keep the other side</label>
<label><input type="checkbox" id="fit"> fit the part kept</label>
<h2>Image</h2>
<label>Samples <select id="samples"><option>1</option><option selected>2</option>
<option>3</option><option>4</option></select></label>
<label>Smooth below <select id="crease"><option value="0">0° (flat)</option>
<option value="30" selected>30°</option><option value="45">45°</option>
<option value="60">60°</option></select></label>
<label><input type="checkbox" id="outline" checked> outlines</label>
<label><a id="download" download="cover.png" href="#">Download this frame</a></label>
<h2>Pick</h2>
<div id="pick">click the model</div>
<h2>Leaves</h2>
<div id="leaves"></div>
<div id="error"></div>
<div id="status"></div>
</div>
<div id="main"><img id="frame" alt="frame" data-state="loading" draggable="false"></div>
<script>
"use strict";
const token = new URLSearchParams(location.search).get("t");
const $ = (id) => document.getElementById(id);
const ownElevation = {iso: 35.264389682754654, top: 90, bottom: -90};
const state = {azimuth: 0, elevation: null, zoom: 1, pan: [0, 0], hidden: new Set()};
let info = null, version = 0;
function api(path, params) {
  const q = new URLSearchParams(params);
  q.set("t", token);
  return path + "?" + q.toString();
}
function sectionParam() {
  const axis = $("section-axis").value;
  if (!axis || !info || !info.bbox) return "";
  const k = {x: 0, y: 1, z: 2}[axis];
  const lo = info.bbox[0][k], hi = info.bbox[1][k];
  const f = $("section-offset").value / 1000;
  const d = lo + f * (hi - lo);
  const n = [0, 0, 0];
  const s = $("flip").checked ? -1 : 1;
  n[k] = s;
  return n.join(",") + "," + (s * d);
}
// The frame's parameters: the names and values `cover render` takes (docs/viewer.md).
function view(w, h, samples) {
  const p = {w: w, h: h, view: $("view").value, up: $("up").value,
             azimuth: state.azimuth, zoom: state.zoom, samples: samples,
             outline: $("outline").checked ? 1 : 0, crease: $("crease").value};
  if (state.elevation !== null) p.elevation = state.elevation;
  if (state.pan[0] || state.pan[1]) p.pan = state.pan.join(",");
  if ($("perspective").checked) p.perspective = 1;
  const sec = sectionParam();
  if (sec) {
    p.section = sec;
    if ($("fit").checked) p.fit = 1;
  }
  if (state.hidden.size) p.hidden = [...state.hidden].sort((a, b) => a - b).join(",");
  return p;
}
function size() {
  const m = $("main");
  return [Math.max(1, m.clientWidth), Math.max(1, m.clientHeight)];
}
let inflight = false, pending = null, idleTimer = null, fullUrl = "";
function request(url, full) {
  if (inflight) { pending = [url, full]; return; }
  inflight = true;
  $("frame").dataset.state = "loading";
  const t0 = performance.now();
  fetch(url).then((r) => {
    if (!r.ok) return r.text().then((m) => { throw new Error(m); });
    return r.blob();
  }).then((blob) => {
    const img = $("frame");
    const old = img.src;
    img.src = URL.createObjectURL(blob);
    if (old.startsWith("blob:") && old !== $("download").href) URL.revokeObjectURL(old);
    img.dataset.url = url;
    if (full) {
      $("download").href = img.src;
      fullUrl = url;
    }
    $("status").textContent = (full ? "frame " : "preview ") +
        Math.round(performance.now() - t0) + " ms";
    $("error").textContent = info && info.error ? "reload failed: " + info.error : "";
    finish(full);
  }).catch((e) => {
    $("error").textContent = String(e.message || e);
    finish(full);
  });
}
function finish(full) {
  inflight = false;
  if (pending) {
    const [u, f] = pending;
    pending = null;
    request(u, f);
  } else {
    $("frame").dataset.state = full ? "idle" : "moving";
  }
}
// A moving view: quarter-size previews now, the full frame once it rests.
function redraw(moving) {
  const [w, h] = size();
  if (moving) {
    request(api("frame", view(Math.max(1, w >> 2), Math.max(1, h >> 2), 1)), false);
    clearTimeout(idleTimer);
    idleTimer = setTimeout(() => redraw(false), 250);
  } else {
    clearTimeout(idleTimer);
    request(api("frame", view(w, h, $("samples").value)), true);
  }
}
function leafList() {
  const box = $("leaves");
  box.textContent = "";
  for (const leaf of info.leaves) {
    const label = document.createElement("label");
    const cb = document.createElement("input");
    cb.type = "checkbox";
    cb.checked = !state.hidden.has(leaf.index);
    cb.dataset.leaf = leaf.index;
    cb.addEventListener("change", () => {
      if (cb.checked) state.hidden.delete(leaf.index); else state.hidden.add(leaf.index);
      redraw(false);
    });
    const sw = document.createElement("span");
    sw.className = "sw";
    sw.style.background = "rgb(" + leaf.colour.join(",") + ")";
    label.title = leaf.name + (leaf.origin ? " at " + leaf.origin : "");
    const where = document.createElement("small");
    where.textContent = leaf.origin ? " " + leaf.origin : "";
    label.append(cb, sw, leaf.name.split("/").pop(), where);
    box.append(label);
  }
}
function loadInfo() {
  return fetch(api("info", {})).then((r) => r.json()).then((j) => {
    const fresh = !info || j.leaves.length !== info.leaves.length;
    info = j;
    $("input").textContent = j.input;
    if (fresh) state.hidden = new Set([...state.hidden].filter((l) => l < j.leaves.length));
    leafList();
    $("error").textContent = j.error ? "reload failed: " + j.error : "";
    if (j.version !== version) {
      version = j.version;
      document.body.dataset.version = version;
      return true;
    }
    return false;
  });
}
// Auto-reload: the server reloads when the input or a file it names changes; the page keeps
// its view and draws the new model.
function poll() {
  loadInfo().then((changed) => { if (changed) redraw(false); })
      .catch(() => {}).finally(() => setTimeout(poll, 700));
}
// Mouse: drag to orbit, shift-drag (or the right button) to pan, the wheel to zoom, a click
// to pick.
let drag = null;
const img = $("frame");
img.addEventListener("contextmenu", (e) => e.preventDefault());
img.addEventListener("mousedown", (e) => {
  drag = {x: e.clientX, y: e.clientY, moved: false, pan: e.shiftKey || e.button === 2};
  img.style.cursor = "grabbing";
  e.preventDefault();
});
window.addEventListener("mousemove", (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  if (!drag.moved && Math.abs(dx) + Math.abs(dy) < 3) return;
  drag.moved = true;
  drag.x = e.clientX;
  drag.y = e.clientY;
  const [w, h] = size();
  if (drag.pan) {
    state.pan = [state.pan[0] - dx / w, state.pan[1] + dy / h];
  } else {
    const own = ownElevation[$("view").value] || 0;
    const el = (state.elevation === null ? own : state.elevation) + 0.4 * dy;
    state.elevation = Math.max(-90, Math.min(90, el));
    state.azimuth = ((state.azimuth - 0.4 * dx) % 360 + 360) % 360;
  }
  redraw(true);
});
window.addEventListener("mouseup", (e) => {
  if (!drag) return;
  const d = drag;
  drag = null;
  img.style.cursor = "grab";
  if (!d.moved) pick(e);
});
img.addEventListener("wheel", (e) => {
  e.preventDefault();
  state.zoom *= Math.pow(1.1, e.deltaY < 0 ? 1 : -1);
  redraw(true);
}, {passive: false});
function pick(e) {
  const [w, h] = size();
  const r = img.getBoundingClientRect();
  const x = Math.floor((e.clientX - r.left) * w / r.width);
  const y = Math.floor((e.clientY - r.top) * h / r.height);
  const p = view(w, h, 1);
  p.x = x;
  p.y = y;
  fetch(api("pick", p)).then((r) => r.json()).then((j) => {
    $("pick").dataset.result = JSON.stringify(j);
    $("pick").textContent = !j.hit ? "pixel " + x + "," + y + ": background" :
        "pixel " + x + "," + y + "\npoint " + j.point.map((v) => v.toPrecision(8)).join(", ") +
        "\nclass " + j.class + "\nleaf " + j.leaf + (j.origin ? "\n" + j.origin : "");
  });
}
for (const id of ["view", "up", "perspective", "samples", "crease", "outline", "section-axis",
                  "flip", "fit"]) {
  $(id).addEventListener("change", () => {
    if (id === "view") state.elevation = null;
    redraw(false);
  });
}
$("section-offset").addEventListener("input", () => { if ($("section-axis").value) redraw(true); });
$("reset").addEventListener("click", () => {
  Object.assign(state, {azimuth: 0, elevation: null, zoom: 1, pan: [0, 0]});
  redraw(false);
});
let resizeTimer = null;
window.addEventListener("resize", () => {
  clearTimeout(resizeTimer);
  resizeTimer = setTimeout(() => redraw(false), 150);
});
window.coverView = {state: state, view: view, size: size, redraw: redraw,
                    fullUrl: () => fullUrl};
loadInfo().then(() => { redraw(false); setTimeout(poll, 700); });
</script></body></html>
)HTML";
  return page;
}

}  // namespace cover
