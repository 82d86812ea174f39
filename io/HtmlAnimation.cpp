#include "io/HtmlAnimation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/MechanismSvg.hpp"
#include "io/TextOutput.hpp"

namespace flexmb::io {

namespace {
// JSON string literal, safe inside <script> (no "</" sequence survives).
std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\')
      o += '\\', o += c;
    else if (c == '<')
      o += "\\u003c";
    else if (c == '>')
      o += "\\u003e";
    else if (c == '&')
      o += "\\u0026";
    else if (u < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      o += buf;
    } else
      o += c;
  }
  return o + "\"";
}

const char* roleColor(const std::string& role) {  // as in MechanismSvg
  if (role == "input") return "#CC79A7";
  if (role == "DOF") return "#0072B2";
  if (role == "released") return "#009E73";
  return "#444444";
}

const char* kPage = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>loading</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<style>
body { font-family: Helvetica, Arial, sans-serif; margin: 12px; color: #222; background: #fff; }
h1 { font-size: 16px; margin: 0 0 6px 0; }
#view { border: 1px solid #ccc; display: block; max-width: 100%; }
#controls { margin-top: 6px; display: flex; gap: 10px; align-items: center; font-size: 13px; }
#slider { flex: 1; }
#legend span { margin-right: 14px; font-size: 12px; }
</style></head>
<body>
<h1 id="heading"></h1>
<canvas id="view" width="960" height="600"></canvas>
<div id="controls">
<button id="play" type="button">pause</button>
<input id="slider" type="range" min="0" max="0" value="0" step="1">
<label>speed <select id="speed"></select></label>
<span id="clock"></span>
</div>
<div id="legend"></div>
<script>
"use strict";
window.onerror = function (msg) { document.title = "error: " + msg; };
const DATA = @DATA@;
(function () {
  try {
    const canvas = document.getElementById("view"), ctx = canvas.getContext("2d");
    const slider = document.getElementById("slider"), play = document.getElementById("play");
    const speedSel = document.getElementById("speed"), clock = document.getElementById("clock");
    document.getElementById("heading").textContent = DATA.title;
    const nf = DATA.times.length;
    if (nf === 0 || DATA.frames.length !== nf) throw new Error("no frames");
    slider.max = String(nf - 1);
    const b = DATA.bounds, W = canvas.width, H = canvas.height, margin = 30;
    const du = Math.max(b[2] - b[0], 1e-12), dv = Math.max(b[3] - b[1], 1e-12);
    const s = Math.min((W - 2 * margin) / du, (H - 2 * margin) / dv);
    const uc = 0.5 * (b[0] + b[2]), vc = 0.5 * (b[1] + b[3]);
    const X = (u) => W / 2 + (u - uc) * s, Y = (v) => H / 2 - (v - vc) * s;
    const duration = DATA.times[nf - 1] - DATA.times[0];
    const speeds = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10];
    let auto = duration > 0 ? duration / 6 : 1;  // the whole run in about 6 s
    speedSel.add(new Option("auto (x" + auto.toPrecision(2) + ")", String(auto)));
    for (const v of speeds) speedSel.add(new Option("x" + v, String(v)));
    const legend = document.getElementById("legend");
    for (const r of DATA.legend) {
      const sp = document.createElement("span");
      sp.textContent = "\u2014 " + r[0];
      sp.style.color = r[1];
      legend.appendChild(sp);
    }
    let frame = 0, playing = true, simTime = DATA.times[0], last = null;

    function draw(k) {
      const f = DATA.frames[k];
      ctx.fillStyle = "#ffffff";
      ctx.fillRect(0, 0, W, H);
      // Trace of the node that moves most, up to this frame.
      if (DATA.trace >= 0) {
        ctx.strokeStyle = "#bbbbbb"; ctx.lineWidth = 1; ctx.beginPath();
        for (let j = 0; j <= k; ++j) {
          const g = DATA.frames[j], i = 2 * DATA.trace;
          if (j === 0) ctx.moveTo(X(g[i]), Y(g[i + 1])); else ctx.lineTo(X(g[i]), Y(g[i + 1]));
        }
        ctx.stroke();
      }
      ctx.lineCap = "round"; ctx.lineJoin = "round";
      for (const e of DATA.elements) {
        ctx.strokeStyle = e.color;
        if (e.joint) {
          ctx.lineWidth = 2; ctx.beginPath();
          ctx.arc(X(f[2 * e.first]), Y(f[2 * e.first + 1]), 6, 0, 2 * Math.PI); ctx.stroke();
          continue;
        }
        ctx.lineWidth = 3.5; ctx.beginPath();
        for (let j = 0; j < e.n; ++j) {
          const i = 2 * (e.first + j);
          if (j === 0) ctx.moveTo(X(f[i]), Y(f[i + 1])); else ctx.lineTo(X(f[i]), Y(f[i + 1]));
        }
        ctx.stroke();
      }
      for (const n of DATA.nodes) {
        const x = X(f[2 * n.point]), y = Y(f[2 * n.point + 1]);
        if (n.fixed) {
          ctx.fillStyle = "rgba(0,0,0,0.35)"; ctx.strokeStyle = "#000000"; ctx.lineWidth = 1.2;
          ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x - 8, y + 13); ctx.lineTo(x + 8, y + 13); ctx.closePath();
          ctx.fill(); ctx.stroke();
        }
        ctx.fillStyle = "#ffffff"; ctx.strokeStyle = "#222222"; ctx.lineWidth = 1.2;
        ctx.beginPath(); ctx.arc(x, y, 3, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      }
      clock.textContent = "t = " + DATA.times[k].toFixed(4) + " s   frame " + (k + 1) + " / " + nf;
      slider.value = String(k);
    }
    function frameAt(t) {  // last frame with time <= t
      let lo = 0, hi = nf - 1;
      while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (DATA.times[mid] <= t) lo = mid; else hi = mid - 1; }
      return lo;
    }
    function tick(now) {
      if (playing) {
        if (last !== null) {
          simTime += (now - last) / 1000 * Number(speedSel.value);
          if (simTime > DATA.times[nf - 1]) simTime = DATA.times[0];
        }
        last = now;
        const k = frameAt(simTime);
        if (k !== frame) { frame = k; draw(frame); }
      }
      window.requestAnimationFrame(tick);
    }
    play.addEventListener("click", () => {
      playing = !playing; last = null; play.textContent = playing ? "pause" : "play";
    });
    slider.addEventListener("input", () => {
      playing = false; play.textContent = "play";
      frame = Number(slider.value); simTime = DATA.times[frame]; draw(frame);
    });
    draw(0);
    window.requestAnimationFrame(tick);
    document.title = "ok";
  } catch (e) {
    document.title = "error: " + e.message;
  }
})();
</script>
</body></html>
)HTML";
}  // namespace

std::string renderHtmlAnimation(const core::Model& model, const core::Trajectory& traj, const AnimationOptions& opt) {
  if (traj.time.empty() || traj.states.size() != traj.time.size())
    throw std::invalid_argument("animation: the trajectory has no output times");
  const MechanismGeometry g(model);
  const View view = resolveView(opt.view, g);
  // Frames to show: all, or evenly thinned to maxFrames.
  const size_t nt = traj.time.size(), maxF = static_cast<size_t>(std::max(2, opt.maxFrames));
  std::vector<size_t> pick;
  if (nt <= maxF) {
    for (size_t k = 0; k < nt; ++k) pick.push_back(k);
  } else {
    for (size_t j = 0; j < maxF; ++j)
      pick.push_back(static_cast<size_t>(std::llround(double(j) * double(nt - 1) / double(maxF - 1))));
  }
  std::vector<std::vector<Point2>> frames;
  std::vector<Point3> p3;
  double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
  for (size_t k : pick) {
    if (traj.states[k].x.size() != model.nx)
      throw std::invalid_argument("animation: x has the wrong size at t = " + shortNumber(traj.time[k], 10));
    g.points(traj.states[k].x, p3);
    std::vector<Point2> f(p3.size());
    for (size_t i = 0; i < p3.size(); ++i) {
      f[i] = project(p3[i], view);
      if (!std::isfinite(f[i].u) || !std::isfinite(f[i].v))
        throw std::invalid_argument("animation: a position is not finite at t = " + shortNumber(traj.time[k], 10));
      u0 = std::min(u0, f[i].u), u1 = std::max(u1, f[i].u), v0 = std::min(v0, f[i].v), v1 = std::max(v1, f[i].v);
    }
    frames.push_back(std::move(f));
  }
  if (!(u0 <= u1)) u0 = v0 = -1, u1 = v1 = 1;

  // Nodes: the first point of each position node; the trace follows the one that travels most.
  std::vector<int> nodePoint(model.nodes.size(), -1);
  for (int i = 0; i < g.numPoints(); ++i)
    if (g.pointNodes()[i] >= 0 && nodePoint[g.pointNodes()[i]] < 0) nodePoint[g.pointNodes()[i]] = i;
  int trace = -1;
  double longest = 0.0;
  for (int p : nodePoint) {
    if (p < 0) continue;
    double len = 0.0;
    for (size_t k = 1; k < frames.size(); ++k)
      len += std::hypot(frames[k][p].u - frames[k - 1][p].u, frames[k][p].v - frames[k - 1][p].v);
    if (len > longest) longest = len, trace = p;
  }

  std::string d = "{\"title\":" + jsonString(opt.title) + ",\"times\":[";
  // Appended piecewise: `"," + std::string` inside `+=` trips GCC 12's -Wrestrict (tools/README.md).
  for (size_t j = 0; j < pick.size(); ++j) {
    if (j) d += ',';
    d += shortNumber(traj.time[pick[j]], 10);
  }
  d += "],\"bounds\":[" + shortNumber(u0, 8) + "," + shortNumber(v0, 8) + "," + shortNumber(u1, 8) + "," +
       shortNumber(v1, 8) + "]";
  d += ",\"trace\":" + std::to_string(trace) + ",\"elements\":[";
  bool first = true;
  for (const DrawnElement& e : g.elements()) {
    const core::ElementEntry& el = model.elements[e.element];
    d += std::string(first ? "" : ",") + "{\"label\":" + std::to_string(el.label) +
         ",\"type\":" + jsonString(el.type->keyword) +
         ",\"joint\":" + (e.shape == DrawnShape::Joint ? "true" : "false") +
         ",\"first\":" + std::to_string(e.firstPoint) + ",\"n\":" + std::to_string(e.numPoints) +
         ",\"color\":" + jsonString(roleColor(elementRole(model, e.element))) + "}";
    first = false;
  }
  d += "],\"nodes\":[";
  first = true;
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    if (nodePoint[n] < 0) continue;
    const std::string role = nodeRole(model, static_cast<int>(n));
    d += std::string(first ? "" : ",") + "{\"label\":" + std::to_string(model.nodes[n].label) +
         ",\"point\":" + std::to_string(nodePoint[n]) +
         ",\"fixed\":" + (role == "fixed" || role == "partly fixed" ? "true" : "false") + "}";
    first = false;
  }
  d += "],\"legend\":[[\"rigid\",\"#444444\"],[\"flexible "
       "(DOF)\",\"#0072B2\"],[\"released\",\"#009E73\"],[\"input\",\"#CC79A7\"]]";
  d += ",\"frames\":[\n";
  for (size_t k = 0; k < frames.size(); ++k) {
    d += k ? ",\n[" : "[";
    for (size_t i = 0; i < frames[k].size(); ++i) {
      if (i) d += ',';
      d += shortNumber(frames[k][i].u, 7);
      d += ',';
      d += shortNumber(frames[k][i].v, 7);
    }
    d += "]";
  }
  d += "]}";

  std::string page = kPage;
  const size_t at = page.find("@DATA@");
  page.replace(at, 6, d);
  return page;
}

void writeHtmlAnimation(const std::string& path, const core::Model& model, const core::Trajectory& traj,
                        const AnimationOptions& options) {
  writeTextFile(path, renderHtmlAnimation(model, traj, options));
}

}  // namespace flexmb::io
