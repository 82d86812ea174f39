#include "io/pictures/HtmlAnimation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <stdexcept>

#include "io/formats/TextOutput.hpp"
#include "io/pictures/MechanismSvg.hpp"

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

std::string hexColor(const double* c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02X%02X%02X", static_cast<int>(std::lround(255 * c[0])),
                static_cast<int>(std::lround(255 * c[1])), static_cast<int>(std::lround(255 * c[2])));
  return buf;
}

const char* kPage = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>loading</title>
<meta name="viewport" content="width=device-width, initial-scale=1">
<style>
body { font-family: Helvetica, Arial, sans-serif; margin: 12px; color: #222; background: #fff; }
h1 { font-size: 16px; margin: 0 0 6px 0; }
#view { border: 1px solid #ccc; display: block; max-width: 100%; cursor: grab; touch-action: none; }
.bar { margin-top: 6px; display: flex; gap: 10px; align-items: center; font-size: 13px; flex-wrap: wrap; }
#slider { flex: 1; min-width: 200px; }
#legend span { margin-right: 14px; font-size: 12px; }
#hint { color: #777; font-size: 12px; }
</style></head>
<body>
<h1 id="heading"></h1>
<canvas id="view" width="960" height="600"></canvas>
<div class="bar">
<select id="sequence"></select>
<button id="play" type="button">pause</button>
<input id="slider" type="range" min="0" max="0" value="0" step="1">
<label id="speedLabel">speed <select id="speed"></select></label>
<span id="clock"></span>
</div>
<div class="bar">
view <button type="button" data-view="iso">iso</button><button type="button" data-view="xy">xy</button>
<button type="button" data-view="xz">xz</button><button type="button" data-view="yz">yz</button>
<button type="button" id="fit">fit</button>
<label><input type="checkbox" id="numbers"> numbers</label>
<label><input type="checkbox" id="solids" checked> cross-sections</label>
<label><input type="checkbox" id="reference" checked> initial configuration</label>
<label id="fileColorsLabel"><input type="checkbox" id="fileColors"> file colours</label>
<label>displacements x <select id="magnify"><option>1</option><option>10</option><option>100</option><option>1000</option></select></label>
<span id="hint">drag: rotate, wheel: zoom, shift-drag: pan</span>
</div>
<div id="legend"></div>
<script>
"use strict";
window.onerror = function (msg) { document.title = "error: " + msg; };
const DATA = @DATA@;
(function () {
  try {
    const canvas = document.getElementById("view"), ctx = canvas.getContext("2d");
    const W = canvas.width, H = canvas.height, margin = 30;
    const $ = (id) => document.getElementById(id);
    const slider = $("slider"), play = $("play"), speedSel = $("speed"), clock = $("clock"), seqSel = $("sequence");
    $("heading").textContent = DATA.title;
    if (DATA.seqs.length === 0) throw new Error("no frames");
    const hash = {};
    for (const part of window.location.hash.replace(/^#/, "").split("&")) {
      if (!part) continue;
      const kv = part.split("=");
      hash[kv[0]] = kv.length > 1 ? decodeURIComponent(kv[1]) : "";
    }
    const VIEWS = @VIEWS@;
    let az = 0, el = 0, scale = 1, panX = 0, panY = 0, centre = [0, 0, 0];
    let seq = null, frame = 0, playing = !("pause" in hash), last = null, clockTime = 0;
    $("numbers").checked = DATA.numbers || ("numbers" in hash);
    if ("noreference" in hash) $("reference").checked = false;
    const anyFileColour = DATA.elements.some((e) => e.file);
    if (!anyFileColour) $("fileColorsLabel").style.display = "none";
    for (const r of DATA.legend) {
      const sp = document.createElement("span");
      sp.textContent = "\u2014 " + r[0];
      sp.style.color = r[1];
      $("legend").appendChild(sp);
    }
    DATA.seqs.forEach((s, i) => seqSel.add(new Option(s.name, String(i))));
    const speeds = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10];
    // Framed points (section axes given) and joint axes: their places in a frame's arrays.
    const framedAt = new Map();
    let nFramed = 0;
    for (const e of DATA.elements) if (e.framed) for (let j = 0; j < e.n; ++j) framedAt.set(e.first + j, nFramed++);
    const jointAt = new Map();
    DATA.elements.forEach((e, i) => { if (e.axis) jointAt.set(i, jointAt.size); });
    const rgb = (h) => [parseInt(h.substr(1, 2), 16), parseInt(h.substr(3, 2), 16), parseInt(h.substr(5, 2), 16)];
    const shade = (c, f) => {
      const v = c.map((x) => Math.max(0, Math.min(255, Math.round(f <= 1 ? x * f : x + (255 - x) * (f - 1)))));
      return "rgb(" + v[0] + "," + v[1] + "," + v[2] + ")";
    };
    function camera() {
      const a = az * Math.PI / 180, b = el * Math.PI / 180;
      const ca = Math.cos(a), sa = Math.sin(a), cb = Math.cos(b), sb = Math.sin(b);
      return { d: [cb * ca, cb * sa, sb], r: [-sa, ca, 0], u: [-sb * ca, -sb * sa, cb] };
    }
    const dot = (p, q) => p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    // A frame's points, with the corners of the cross-sections where solids are drawn (a leaf's
    // width can be most of a flexure's extent).
    function framePoints(j) {
      const f = magnified(seq.frames[j]), out = [];
      for (let i = 0; i < f.length; i += 3) out.push([f[i], f[i + 1], f[i + 2]]);
      if (!$("solids").checked) return out;
      const ax = seq.axes[j];
      for (const e of DATA.elements) {
        if (e.joint || !e.sec || !e.framed) continue;
        const a = 0.5 * e.sec[1], b = 0.5 * (e.sec[0] === 1 ? e.sec[2] : e.sec[1]);
        for (let k = 0; k < e.n; ++k) {
          const i = e.first + k, s = 6 * framedAt.get(i);
          for (const c of [[a, b], [-a, b], [-a, -b], [a, -b]])
            out.push([0, 1, 2].map((d) => f[3 * i + d] + c[0] * ax[s + d] + c[1] * ax[s + 3 + d]));
        }
      }
      return out;
    }
    function fit() {  // the whole sequence in view, cross-sections included, about its 3-D centre
      const cam = camera();
      let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
      const frames = seq.frames.map((_, j) => framePoints(j));
      for (const f of frames)
        for (const q of f)
          for (let k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], q[k]); hi[k] = Math.max(hi[k], q[k]); }
      centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])];
      let u0 = Infinity, u1 = -Infinity, v0 = Infinity, v1 = -Infinity;
      for (const f of frames)
        for (const q of f) {
          const p = [q[0] - centre[0], q[1] - centre[1], q[2] - centre[2]];
          const u = dot(p, cam.r), v = dot(p, cam.u);
          u0 = Math.min(u0, u); u1 = Math.max(u1, u); v0 = Math.min(v0, v); v1 = Math.max(v1, v);
        }
      const du = Math.max(u1 - u0, 1e-12), dv = Math.max(v1 - v0, 1e-12);
      scale = Math.min((W - 2 * margin) / du, (H - 2 * margin) / dv);
      if (!isFinite(scale) || scale <= 0) scale = 1;
      panX = -0.5 * (u0 + u1) * scale;
      panY = 0.5 * (v0 + v1) * scale;
    }
    function setView(name) {
      const v = VIEWS[name] || VIEWS[DATA.view];
      az = v[0]; el = v[1];
      fit();
      draw();
    }
    // Displacements from the initial configuration magnified k times (small elastic motions).
    function magnified(f) {
      const k = Number($("magnify").value);
      if (k === 1 || !DATA.ref || DATA.ref.length !== f.length) return f;
      return f.map((v, i) => DATA.ref[i] + k * (v - DATA.ref[i]));
    }
    function draw() {
      const f = magnified(seq.frames[frame]), ax = seq.axes[frame], ja = seq.jaxes[frame];
      const cam = camera();
      const P = (i) => {
        const p = [f[3 * i] - centre[0], f[3 * i + 1] - centre[1], f[3 * i + 2] - centre[2]];
        return [W / 2 + panX + scale * dot(p, cam.r), H / 2 + panY - scale * dot(p, cam.u), dot(p, cam.d)];
      };
      const light = [0, 1, 2].map((k) => cam.d[k] + 0.5 * cam.u[k] - 0.4 * cam.r[k]);
      const ln = Math.hypot(light[0], light[1], light[2]);
      const solids = $("solids").checked, fileColours = $("fileColors").checked;
      ctx.fillStyle = "#ffffff";
      ctx.fillRect(0, 0, W, H);
      // Trace of the node that moves most, up to this frame.
      if (seq.trace >= 0 && seq.times) {
        ctx.strokeStyle = "#bbbbbb"; ctx.lineWidth = 1; ctx.beginPath();
        for (let j = 0; j <= frame; ++j) {
          const g = magnified(seq.frames[j]), i = 3 * seq.trace;
          const p = [g[i] - centre[0], g[i + 1] - centre[1], g[i + 2] - centre[2]];
          const x = W / 2 + panX + scale * dot(p, cam.r), y = H / 2 + panY - scale * dot(p, cam.u);
          if (j === 0) ctx.moveTo(x, y); else ctx.lineTo(x, y);
        }
        ctx.stroke();
      }
      const prims = [];
      DATA.elements.forEach((e, ei) => {
        const colour = fileColours && e.file ? e.file : e.color;
        if (e.joint) {
          const c = P(e.first), prim = { kind: 0, c: c, depth: c[2] + 1e-9, colour: colour };
          if (e.axis) {
            const j = 3 * jointAt.get(ei), a = 0.04 * DATA.size * scale;
            const dx = a * dot([ja[j], ja[j + 1], ja[j + 2]], cam.r), dy = -a * dot([ja[j], ja[j + 1], ja[j + 2]], cam.u);
            prim.axis = [c[0] - dx, c[1] - dy, c[0] + dx, c[1] + dy];
          }
          prims.push(prim);
          return;
        }
        if (!(solids && e.sec && e.framed)) {
          const pts = [];
          let dep = 0;
          for (let j = 0; j < e.n; ++j) { const p = P(e.first + j); pts.push(p); dep += p[2]; }
          prims.push({ kind: 1, pts: pts, depth: dep / e.n, colour: colour, opacity: e.opacity });
          return;
        }
        // Cross-section outline in (y, z), swept along the axis.
        const outline = [];
        if (e.sec[0] === 1) {
          const a = 0.5 * e.sec[1], b = 0.5 * e.sec[2];
          outline.push([a, b], [-a, b], [-a, -b], [a, -b]);
        } else {
          const r = 0.5 * e.sec[1];
          for (let k = 0; k < 12; ++k) outline.push([r * Math.cos(k * Math.PI / 6), r * Math.sin(k * Math.PI / 6)]);
        }
        const base = rgb(colour);
        const corner = (j, s) => {
          const i = e.first + j, a = 6 * framedAt.get(i);
          const q = [0, 1, 2].map((k) => f[3 * i + k] + outline[s][0] * ax[a + k] + outline[s][1] * ax[a + 3 + k]);
          return q;
        };
        const ring = [];
        for (let j = 0; j < e.n; ++j) ring.push(outline.map((_, s) => corner(j, s)));
        const toScreen = (q) => {
          const p = [q[0] - centre[0], q[1] - centre[1], q[2] - centre[2]];
          return [W / 2 + panX + scale * dot(p, cam.r), H / 2 + panY - scale * dot(p, cam.u), dot(p, cam.d)];
        };
        const face = (qs) => {
          const a = qs[0], c = qs[2], b = qs[1], d = qs[qs.length - 1];
          const u = [c[0] - a[0], c[1] - a[1], c[2] - a[2]], v = [d[0] - b[0], d[1] - b[1], d[2] - b[2]];
          const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
          const nn = Math.hypot(n[0], n[1], n[2]);
          const f = nn > 0 ? 0.55 + 0.6 * Math.abs(dot(n, light)) / (nn * ln) : 1;
          const pts = qs.map(toScreen);
          let dep = 0;
          for (const p of pts) dep += p[2];
          prims.push({ kind: 2, pts: pts, depth: dep / pts.length, fill: shade(base, f), opacity: e.opacity });
        };
        const ns = outline.length;
        for (let j = 0; j + 1 < e.n; ++j)
          for (let s = 0; s < ns; ++s) face([ring[j][s], ring[j][(s + 1) % ns], ring[j + 1][(s + 1) % ns], ring[j + 1][s]]);
        face(ring[0]);
        face(ring[e.n - 1]);
      });
      prims.sort((a, b) => a.depth - b.depth);
      ctx.lineCap = "round"; ctx.lineJoin = "round";
      for (const q of prims) {
        ctx.globalAlpha = q.opacity === undefined ? 1 : q.opacity;
        if (q.kind === 0) {
          ctx.strokeStyle = q.colour;
          if (q.axis) {
            ctx.lineWidth = 2; ctx.beginPath(); ctx.moveTo(q.axis[0], q.axis[1]); ctx.lineTo(q.axis[2], q.axis[3]); ctx.stroke();
          }
          ctx.fillStyle = "#ffffff"; ctx.lineWidth = 2; ctx.beginPath();
          ctx.arc(q.c[0], q.c[1], 6, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
        } else if (q.kind === 1) {
          ctx.strokeStyle = q.colour; ctx.lineWidth = 3.5; ctx.beginPath();
          q.pts.forEach((p, j) => { if (j === 0) ctx.moveTo(p[0], p[1]); else ctx.lineTo(p[0], p[1]); });
          ctx.stroke();
        } else {
          ctx.fillStyle = q.fill; ctx.strokeStyle = q.fill; ctx.lineWidth = 0.6; ctx.beginPath();
          q.pts.forEach((p, j) => { if (j === 0) ctx.moveTo(p[0], p[1]); else ctx.lineTo(p[0], p[1]); });
          ctx.closePath(); ctx.fill(); ctx.stroke();
        }
      }
      ctx.globalAlpha = 1;
      // The initial configuration's centre lines, dashed over the shapes: what a deformation is
      // measured from stays visible, also behind a solid leaf.
      if ($("reference").checked && DATA.ref && DATA.ref.length === f.length) {
        ctx.strokeStyle = "#888888"; ctx.lineWidth = 1.2; ctx.setLineDash([6, 4]);
        for (const e of DATA.elements) {
          if (e.joint || e.n < 2) continue;
          ctx.beginPath();
          for (let j = 0; j < e.n; ++j) {
            const i = 3 * (e.first + j);
            const p = [DATA.ref[i] - centre[0], DATA.ref[i + 1] - centre[1], DATA.ref[i + 2] - centre[2]];
            const x = W / 2 + panX + scale * dot(p, cam.r), y = H / 2 + panY - scale * dot(p, cam.u);
            if (j === 0) ctx.moveTo(x, y); else ctx.lineTo(x, y);
          }
          ctx.stroke();
        }
        ctx.setLineDash([]);
      }
      for (const n of DATA.nodes) {
        const p = P(n.point), x = p[0], y = p[1];
        if (n.fixed) {
          ctx.fillStyle = "rgba(0,0,0,0.35)"; ctx.strokeStyle = "#000000"; ctx.lineWidth = 1.2;
          ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x - 8, y + 13); ctx.lineTo(x + 8, y + 13); ctx.closePath();
          ctx.fill(); ctx.stroke();
        }
        ctx.fillStyle = "#ffffff"; ctx.strokeStyle = "#222222"; ctx.lineWidth = 1.2;
        ctx.beginPath(); ctx.arc(x, y, 3, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      }
      if ($("numbers").checked) {
        ctx.font = "12px Helvetica, Arial, sans-serif"; ctx.textAlign = "left";
        for (const n of DATA.nodes) {
          const p = P(n.point);
          ctx.fillStyle = n.color; ctx.fillText(String(n.label), p[0] + 6, p[1] - 6);
        }
        ctx.textAlign = "center";
        for (const e of DATA.elements) {
          const p = P(e.first + Math.floor((e.n - 1) / 2)), q = P(e.first + Math.floor(e.n / 2));
          ctx.fillStyle = e.color;
          ctx.fillText("[" + e.label + "]", 0.5 * (p[0] + q[0]) + (e.joint ? -16 : 0), 0.5 * (p[1] + q[1]) - 8);
        }
      }
      // The global axes in the lower left corner.
      const o = [40, H - 40];
      ctx.font = "11px Helvetica, Arial, sans-serif"; ctx.textAlign = "center"; ctx.lineWidth = 1.2;
      ["x", "y", "z"].forEach((name, k) => {
        const e = [0, 0, 0]; e[k] = 1;
        const dx = 24 * dot(e, cam.r), dy = -24 * dot(e, cam.u);
        ctx.strokeStyle = "#555555"; ctx.fillStyle = "#555555";
        ctx.beginPath(); ctx.moveTo(o[0], o[1]); ctx.lineTo(o[0] + dx, o[1] + dy); ctx.stroke();
        ctx.fillText(name, o[0] + 1.3 * dx, o[1] + 1.3 * dy + 4);
      });
      const label = seq.labels.length ? seq.labels[frame] : "frame " + (frame + 1);
      clock.textContent = label + "   (" + (frame + 1) + " / " + seq.frames.length + ")";
      slider.value = String(frame);
    }
    function selectSequence(i) {
      seq = DATA.seqs[Math.max(0, Math.min(DATA.seqs.length - 1, i))];
      seqSel.value = String(DATA.seqs.indexOf(seq));
      slider.max = String(seq.frames.length - 1);
      frame = 0; last = null;
      clockTime = seq.times ? seq.times[0] : 0;
      speedSel.innerHTML = "";
      if (seq.times) {
        const duration = seq.times[seq.times.length - 1] - seq.times[0];
        const auto = duration > 0 ? duration / 6 : 1;  // the whole run in about 6 s
        speedSel.add(new Option("auto (x" + auto.toPrecision(2) + ")", String(auto)));
        for (const v of speeds) speedSel.add(new Option("x" + v, String(v)));
        $("speedLabel").style.display = "";
      } else {
        $("speedLabel").style.display = "none";
      }
      fit();
      draw();
    }
    function tick(now) {
      if (playing && seq.frames.length > 1) {
        if (last !== null) {
          const dt = (now - last) / 1000;
          if (seq.times) {
            clockTime += dt * Number(speedSel.value);
            if (clockTime > seq.times[seq.times.length - 1]) clockTime = seq.times[0];
          } else {
            clockTime += dt * (seq.periodic ? 16 : 2);  // frames per second
          }
        }
        last = now;
        let k;
        if (seq.times) {
          let lo = 0, hi = seq.times.length - 1;
          while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (seq.times[mid] <= clockTime) lo = mid; else hi = mid - 1; }
          k = lo;
        } else {
          k = Math.floor(clockTime) % seq.frames.length;
        }
        if (k !== frame) { frame = k; draw(); }
      }
      window.requestAnimationFrame(tick);
    }
    // Mouse: drag rotates, shift-drag pans, the wheel zooms about the centre of the canvas.
    let dragging = null;
    canvas.addEventListener("mousedown", (ev) => { dragging = { x: ev.clientX, y: ev.clientY, pan: ev.shiftKey }; ev.preventDefault(); });
    window.addEventListener("mousemove", (ev) => {
      if (!dragging) return;
      const dx = ev.clientX - dragging.x, dy = ev.clientY - dragging.y;
      dragging.x = ev.clientX; dragging.y = ev.clientY;
      if (dragging.pan) { panX += dx; panY += dy; }
      else { az -= 0.5 * dx; el = Math.max(-90, Math.min(90, el + 0.5 * dy)); }
      draw();
    });
    window.addEventListener("mouseup", () => { dragging = null; });
    canvas.addEventListener("wheel", (ev) => {
      const k = Math.exp(-0.0015 * ev.deltaY);
      scale *= k; panX *= k; panY *= k;
      ev.preventDefault();
      draw();
    }, { passive: false });
    play.addEventListener("click", () => { playing = !playing; last = null; play.textContent = playing ? "pause" : "play"; });
    slider.addEventListener("input", () => {
      playing = false; play.textContent = "play";
      frame = Number(slider.value);
      clockTime = seq.times ? seq.times[frame] : frame;
      draw();
    });
    seqSel.addEventListener("change", () => selectSequence(Number(seqSel.value)));
    for (const b of document.querySelectorAll("button[data-view]")) b.addEventListener("click", () => setView(b.dataset.view));
    $("fit").addEventListener("click", () => { fit(); draw(); });
    for (const id of ["numbers", "solids", "fileColors", "reference"]) $(id).addEventListener("change", draw);
    $("magnify").addEventListener("change", () => { fit(); draw(); });
    if ("magnify" in hash) $("magnify").value = hash.magnify;

    const v0 = VIEWS[hash.view] || VIEWS[DATA.view];
    az = v0[0]; el = v0[1];
    selectSequence("seq" in hash ? Number(hash.seq) : 0);
    if ("frame" in hash) { frame = Math.max(0, Math.min(seq.frames.length - 1, Number(hash.frame))); draw(); }
    if (!playing) play.textContent = "play";
    window.requestAnimationFrame(tick);
    if ("drag" in hash) {  // a scripted drag through the page's own handlers
      const d = hash.drag.split(",").map(Number), r = canvas.getBoundingClientRect();
      const x0 = r.left + W / 2, y0 = r.top + H / 2;
      canvas.dispatchEvent(new MouseEvent("mousedown", { clientX: x0, clientY: y0, bubbles: true }));
      window.dispatchEvent(new MouseEvent("mousemove", { clientX: x0 + d[0], clientY: y0 + d[1], bubbles: true }));
      window.dispatchEvent(new MouseEvent("mouseup", { clientX: x0 + d[0], clientY: y0 + d[1], bubbles: true }));
      document.title = "ok az=" + az.toFixed(1) + " el=" + el.toFixed(1);
    } else {
      document.title = "ok";
    }
  } catch (e) {
    document.title = "error: " + e.message;
  }
})();
</script>
</body></html>
)HTML";

std::vector<size_t> thinned(size_t n, int maxFrames) {
  const size_t maxF = static_cast<size_t>(std::max(2, maxFrames));
  std::vector<size_t> pick;
  if (n <= maxF) {
    for (size_t k = 0; k < n; ++k) pick.push_back(k);
  } else {
    for (size_t j = 0; j < maxF; ++j)
      pick.push_back(static_cast<size_t>(std::llround(double(j) * double(n - 1) / double(maxF - 1))));
  }
  return pick;
}
// Appends the numbers, comma-separated, after a comma when `comma`. Piecewise: `"," + std::string`
// chains inside `+=` trip GCC 12's false -Wrestrict (tools/README.md).
void appendNumbers(std::string& s, bool comma, std::initializer_list<double> values, int digits) {
  for (double v : values) {
    if (comma) s += ',';
    s += shortNumber(v, digits);
    comma = true;
  }
}

}  // namespace

AnimationSequence modeSequence(const core::Model& model, const std::string& name, const Eigen::VectorXd& x,
                               const Eigen::VectorXd& dx, int frames) {
  AnimationSequence s;
  s.name = name;
  s.periodic = true;
  const Eigen::VectorXd shape = scaledShape(model, x, dx) - x;
  frames = std::max(4, frames);
  for (int k = 0; k < frames; ++k) {
    const double phase = 2 * M_PI * k / frames;
    s.x.push_back(x + std::sin(phase) * shape);
    s.labels.push_back(name + ", phase " + std::to_string(static_cast<int>(std::lround(phase * 180 / M_PI))) +
                       "\u00b0");
  }
  return s;
}

std::string renderHtmlPage(const core::Model& model, const std::vector<AnimationSequence>& sequences,
                           const AnimationOptions& opt) {
  size_t total = 0;
  for (const auto& s : sequences) total += s.x.size();
  if (total == 0) throw std::invalid_argument("HTML page: no configurations to show");
  const MechanismGeometry g(model);
  const View view = resolveView(opt.view, g);

  // Elements, nodes (the first point of each position node).
  std::vector<int> nodePoint(model.nodes.size(), -1);
  for (int i = 0; i < g.numPoints(); ++i)
    if (g.pointNodes()[i] >= 0 && nodePoint[g.pointNodes()[i]] < 0) nodePoint[g.pointNodes()[i]] = i;
  std::vector<const DrawnElement*> joints, framed;
  Point3 axisProbe;
  std::string d = "{\"title\":" + jsonString(opt.title) + ",\"view\":\"" + viewName(view) + "\"";
  d += ",\"numbers\":" + std::string(opt.numbers ? "true" : "false");
  d += ",\"size\":" + shortNumber(modelSize(model, model.x0), 8);
  d += ",\"elements\":[";
  bool first = true;
  for (const DrawnElement& e : g.elements()) {
    const core::ElementEntry& el = model.elements[e.element];
    const auto look = model.appearance.find(el.label);
    const bool axis = g.jointAxis(e, model.x0, axisProbe);
    if (axis) joints.push_back(&e);
    if (e.framed) framed.push_back(&e);
    d += std::string(first ? "" : ",") + "{\"label\":" + std::to_string(el.label) +
         ",\"type\":" + jsonString(el.type->keyword) +
         ",\"joint\":" + (e.shape == DrawnShape::Joint ? "true" : "false") + ",\"axis\":" + (axis ? "true" : "false") +
         ",\"first\":" + std::to_string(e.firstPoint) + ",\"n\":" + std::to_string(e.numPoints) +
         ",\"framed\":" + (e.framed ? "true" : "false") +
         ",\"color\":" + jsonString(roleColor(elementRole(model, e.element)));
    if (look != model.appearance.end() && look->second.hasColor)
      d += ",\"file\":" + jsonString(hexColor(look->second.color));
    if (look != model.appearance.end() && look->second.opacity < 1)
      d += ",\"opacity\":" + shortNumber(look->second.opacity, 4);
    if (e.section.kind != DrawnSection::Kind::Line)
      d += ",\"sec\":[" + std::string(e.section.kind == DrawnSection::Kind::Rectangle ? "1" : "2") + "," +
           shortNumber(e.section.width, 8) + "," + shortNumber(e.section.thickness, 8) + "]";
    d += "}";
    first = false;
  }
  d += "],\"nodes\":[";
  first = true;
  for (size_t n = 0; n < model.nodes.size(); ++n) {
    if (nodePoint[n] < 0) continue;
    const std::string role = nodeRole(model, static_cast<int>(n));
    const char* colour = role == "input"  ? "#CC79A7"
                         : role == "DOF"  ? "#D55E00"
                         : role == "free" ? "#444444"
                                          : "#000000";
    d += std::string(first ? "" : ",") + "{\"label\":" + std::to_string(model.nodes[n].label) +
         ",\"point\":" + std::to_string(nodePoint[n]) +
         ",\"fixed\":" + (role == "fixed" || role == "partly fixed" ? "true" : "false") + ",\"color\":\"" + colour +
         "\"}";
    first = false;
  }
  {  // the initial configuration's points: the reference of the displacement magnification
    std::vector<Point3> ref;
    g.points(model.x0, ref);
    d += "],\"ref\":[";
    for (size_t i = 0; i < ref.size(); ++i) appendNumbers(d, i > 0, {ref[i].x, ref[i].y, ref[i].z}, 7);
  }
  d += "],\"legend\":[[\"rigid\",\"#444444\"],[\"flexible "
       "(DOF)\",\"#0072B2\"],[\"released\",\"#009E73\"],[\"input\",\"#CC79A7\"]]";

  d += ",\"seqs\":[";
  bool firstSeq = true;
  std::vector<Point3> p3, ys, zs;
  for (size_t si = 0; si < sequences.size(); ++si) {
    const AnimationSequence& s = sequences[si];
    if (s.x.empty()) continue;
    if (!s.times.empty() && s.times.size() != s.x.size())
      throw std::invalid_argument("HTML page: sequence '" + s.name + "' has " + std::to_string(s.times.size()) +
                                  " times for " + std::to_string(s.x.size()) + " frames");
    const std::vector<size_t> pick = thinned(s.x.size(), opt.maxFrames);
    std::string frames, axes, jaxes, times, labels;
    std::vector<std::vector<Point3>> pts;
    for (size_t j = 0; j < pick.size(); ++j) {
      const size_t k = pick[j];
      const auto where = [&]() {
        return s.times.empty() ? "frame " + std::to_string(k + 1) + " of '" + s.name + "'"
                               : "t = " + shortNumber(s.times[k], 10);
      };
      if (s.x[k].size() != model.nx) throw std::invalid_argument("HTML page: x has the wrong size at " + where());
      g.points(s.x[k], p3);
      for (const Point3& q : p3)
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
          throw std::invalid_argument("HTML page: a position is not finite at " + where());
      pts.push_back(p3);
      frames += j ? ",\n[" : "[";
      for (size_t i = 0; i < p3.size(); ++i) appendNumbers(frames, i > 0, {p3[i].x, p3[i].y, p3[i].z}, 7);
      frames += "]";
      g.sectionAxes(s.x[k], ys, zs);
      axes += j ? ",[" : "[";
      bool firstAxis = true;
      for (const DrawnElement* e : framed)
        for (int i = e->firstPoint; i < e->firstPoint + e->numPoints; ++i) {
          appendNumbers(axes, !firstAxis, {ys[i].x, ys[i].y, ys[i].z, zs[i].x, zs[i].y, zs[i].z}, 5);
          firstAxis = false;
        }
      axes += "]";
      jaxes += j ? ",[" : "[";
      for (size_t i = 0; i < joints.size(); ++i) {
        Point3 a;
        g.jointAxis(*joints[i], s.x[k], a);
        appendNumbers(jaxes, i > 0, {a.x, a.y, a.z}, 5);
      }
      jaxes += "]";
      if (!s.times.empty()) appendNumbers(times, j > 0, {s.times[k]}, 10);
      if (!s.labels.empty()) {
        if (j) labels += ',';
        labels += jsonString(k < s.labels.size() ? s.labels[k] : "");
      }
    }
    // The trace follows the position node that travels most (timed sequences).
    int trace = -1;
    double longest = 0.0;
    for (int p : nodePoint) {
      if (p < 0) continue;
      double len = 0.0;
      for (size_t k = 1; k < pts.size(); ++k)
        len += std::hypot(pts[k][p].x - pts[k - 1][p].x, pts[k][p].y - pts[k - 1][p].y, pts[k][p].z - pts[k - 1][p].z);
      if (len > longest) longest = len, trace = p;
    }
    d += std::string(firstSeq ? "" : ",") + "{\"name\":" + jsonString(s.name) +
         ",\"periodic\":" + (s.periodic ? "true" : "false") + ",\"trace\":" + std::to_string(trace) +
         ",\"times\":" + (s.times.empty() ? "null" : "[" + times + "]") + ",\"labels\":[" + labels + "]" +
         ",\"frames\":[\n" + frames + "],\"axes\":[" + axes + "],\"jaxes\":[" + jaxes + "]}";
    firstSeq = false;
  }
  d += "]}";

  std::string views = "{";
  for (View v : {View::Isometric, View::XY, View::XZ, View::YZ}) {
    const Axonometry a = axonometry(v);
    views += std::string(views.size() > 1 ? "," : "") + viewName(v) + ":[" + shortNumber(a.azimuth, 8) + "," +
             shortNumber(a.elevation, 8) + "]";
  }
  views += "}";
  std::string page = kPage;
  page.replace(page.find("@VIEWS@"), 7, views);
  const size_t at = page.find("@DATA@");
  page.replace(at, 6, d);
  return page;
}

std::string renderHtmlAnimation(const core::Model& model, const core::Trajectory& traj, const AnimationOptions& opt) {
  if (traj.time.empty() || traj.states.size() != traj.time.size())
    throw std::invalid_argument("animation: the trajectory has no output times");
  AnimationSequence s;
  s.name = "motion";
  for (size_t k = 0; k < traj.time.size(); ++k) {
    if (traj.states[k].x.size() != model.nx)
      throw std::invalid_argument("animation: x has the wrong size at t = " + shortNumber(traj.time[k], 10));
    s.x.push_back(traj.states[k].x);
    s.times.push_back(traj.time[k]);
    s.labels.push_back("t = " + shortNumber(traj.time[k], 6) + " s");
  }
  return renderHtmlPage(model, {s}, opt);
}

void writeHtmlPage(const std::string& path, const core::Model& model, const std::vector<AnimationSequence>& sequences,
                   const AnimationOptions& options) {
  writeTextFile(path, renderHtmlPage(model, sequences, options));
}

void writeHtmlAnimation(const std::string& path, const core::Model& model, const core::Trajectory& traj,
                        const AnimationOptions& options) {
  writeTextFile(path, renderHtmlAnimation(model, traj, options));
}

}  // namespace flexmb::io
