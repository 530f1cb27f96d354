// btnav's live view: draws the messages the server sends (see viz/live/messages.py)
// on one canvas and sends the user's commands back. Plain JS, no library.
"use strict";

const S = {
  static: null, map: null, mapImage: null, costmaps: {}, costmapImages: {},
  tree: [], frame: null, frames: 0, mode: "live", tool: null, drag: null,
  replay: null, playing: null,
};
window.btnav = S; // for tests and the curious

const canvas = document.getElementById("map");
const ctx = canvas.getContext("2d");
const $ = (id) => document.getElementById(id);
let ws = null;

function send(command) {
  if (ws && ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(command));
}

function connect() {
  ws = new WebSocket(`ws://${location.host}/ws`);
  ws.onopen = () => { $("connection").textContent = "connected"; send({ cmd: "costmap", which: $("costmap").value }); };
  ws.onclose = () => { $("connection").textContent = "disconnected"; setTimeout(connect, 1000); };
  ws.onmessage = (event) => receive(JSON.parse(event.data));
}

function bytes(b64) {
  const raw = atob(b64);
  const out = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
  return out;
}

// A grid as an offscreen canvas, row 0 (the origin) at the bottom.
function gridImage(msg, colour) {
  const data = bytes(msg.data);
  const image = document.createElement("canvas");
  image.width = msg.w; image.height = msg.h;
  const g = image.getContext("2d");
  const pixels = g.createImageData(msg.w, msg.h);
  for (let row = 0; row < msg.h; row++) {
    for (let col = 0; col < msg.w; col++) {
      const rgba = colour(data[row * msg.w + col]);
      const at = ((msg.h - 1 - row) * msg.w + col) * 4;
      pixels.data[at] = rgba[0]; pixels.data[at + 1] = rgba[1];
      pixels.data[at + 2] = rgba[2]; pixels.data[at + 3] = rgba[3];
    }
  }
  g.putImageData(pixels, 0, 0);
  return image;
}

function occupancyColour(slam) {
  return (byte) => {
    const v = byte > 127 ? byte - 256 : byte; // int8
    if (v < 0) return slam ? [0, 0, 0, 0] : [205, 205, 205, 255];
    const grey = 254 - Math.floor((Math.min(v, 100) * 254) / 100);
    return [grey, grey, grey, 255];
  };
}

function costColour(cost) {
  if (cost === 0 || cost === 255) return [0, 0, 0, 0];
  if (cost === 254) return [160, 0, 160, 200];
  if (cost === 253) return [40, 170, 220, 170];
  return [106, 81, 163, Math.round(30 + (cost / 252) * 140)];
}

function receive(msg) {
  if (msg.type === "static") {
    S.static = msg;
    $("mission").textContent = msg.mission;
  } else if (msg.type === "map") {
    S.map = msg;
    S.mapImage = gridImage(msg, occupancyColour(S.static && S.static.slam));
  } else if (msg.type === "costmap") {
    S.costmaps[msg.which] = msg;
    S.costmapImages[msg.which] = gridImage(msg, costColour);
  } else if (msg.type === "tree") {
    S.tree = msg.nodes;
    const box = $("tree");
    box.innerHTML = "";
    msg.nodes.forEach(([name, type, depth], i) => {
      const row = document.createElement("div");
      row.id = `node-${i}`;
      row.className = "st-I";
      row.style.marginLeft = `${depth * 12}px`;
      const short = name.split(".").pop();
      row.textContent = short;
      if (type !== short) { const t = document.createElement("small"); t.textContent = ` ${type}`; row.appendChild(t); }
      box.appendChild(row);
    });
  } else if (msg.type === "replay") {
    S.mode = "replay";
    S.replay = msg;
    document.body.className = "replay";
    $("slider").max = String(msg.count - 1);
  } else if (msg.type === "frame") {
    S.frame = msg;
    S.frames += 1;
    status(msg);
    requestAnimationFrame(draw);
  }
}

function status(f) {
  $("simtime").textContent = `t = ${f.t.toFixed(2)} s`;
  $("rtf").textContent = f.live ? `RTF ${f.rtf.toFixed(2)} (speed ${f.speed === 0 ? "max" : f.speed + "x"})` : "replay";
  $("actions").textContent = f.actions.join(", ") + (f.waypoint ? `  waypoint ${f.waypoint[0]}/${f.waypoint[1]}` : "");
  $("result").textContent = f.result ? `result: ${f.result}` : "";
  $("pause").textContent = f.paused ? "Resume" : "Pause";
  $("pause").classList.toggle("on", !!f.paused);
  document.querySelectorAll(".speed").forEach((b) => b.classList.toggle("on", f.live && Number(b.dataset.speed) === f.speed));
  for (let i = 0; i < f.bt.length; i++) {
    const row = document.getElementById(`node-${i}`);
    if (row) row.className = `st-${f.bt[i]}`;
  }
  if (S.mode === "replay" && f.index !== undefined) $("slider").value = String(f.index);
}

// -- drawing ----------------------------------------------------------------------

let view = { scale: 1, x0: 0, y0: 0, height: 0 };

function fit() {
  const rect = canvas.getBoundingClientRect();
  canvas.width = Math.max(rect.width, 50); canvas.height = Math.max(rect.height, 50);
  if (!S.static) return;
  const [x0, y0, x1, y1] = S.static.bounds;
  const margin = 0.03 * Math.max(x1 - x0, y1 - y0);
  const scale = Math.min(canvas.width / (x1 - x0 + 2 * margin), canvas.height / (y1 - y0 + 2 * margin));
  const padX = (canvas.width - (x1 - x0) * scale) / 2, padY = (canvas.height - (y1 - y0) * scale) / 2;
  view = { scale, x0: x0 - padX / scale, y0: y0 - padY / scale, height: canvas.height };
}
const px = (x, y) => [(x - view.x0) * view.scale, view.height - (y - view.y0) * view.scale];
const world = (u, v) => [u / view.scale + view.x0, (view.height - v) / view.scale + view.y0];
S.toCanvas = px; // world -> canvas pixels, for tests

function path(flat, close) {
  ctx.beginPath();
  for (let i = 0; i + 1 < flat.length; i += 2) {
    const [u, v] = px(flat[i], flat[i + 1]);
    if (i === 0) ctx.moveTo(u, v); else ctx.lineTo(u, v);
  }
  if (close) ctx.closePath();
}

function dots(flat, colour, size) {
  ctx.fillStyle = colour;
  for (let i = 0; i + 1 < flat.length; i += 2) {
    const [u, v] = px(flat[i], flat[i + 1]);
    ctx.fillRect(u - size / 2, v - size / 2, size, size);
  }
}

function line(flat, colour, width, dash) {
  if (!flat || flat.length < 4) return;
  ctx.strokeStyle = colour; ctx.lineWidth = width; ctx.setLineDash(dash || []);
  path(flat, false); ctx.stroke(); ctx.setLineDash([]);
}

function grid(msg, image, pose) {
  // the grid's cells in its frame, placed by `pose` (its frame in the map frame)
  const [px0, py0] = px(pose[0], pose[1]);
  ctx.save();
  ctx.translate(px0, py0);
  ctx.rotate(-pose[2]);
  ctx.imageSmoothingEnabled = false;
  const s = view.scale, w = msg.w * msg.res * s, h = msg.h * msg.res * s;
  ctx.drawImage(image, msg.origin[0] * s, -msg.origin[1] * s - h, w, h);
  ctx.restore();
}

function arrow(x, y, yaw, colour, length) {
  const [u, v] = px(x, y);
  const du = Math.cos(yaw) * length, dv = -Math.sin(yaw) * length;
  ctx.strokeStyle = colour; ctx.lineWidth = 3;
  ctx.beginPath(); ctx.moveTo(u, v); ctx.lineTo(u + du, v + dv); ctx.stroke();
  ctx.beginPath(); ctx.arc(u, v, 4, 0, 2 * Math.PI); ctx.fillStyle = colour; ctx.fill();
}

function star(x, y, colour) {
  const [u, v] = px(x, y);
  ctx.fillStyle = colour; ctx.beginPath();
  for (let i = 0; i < 10; i++) {
    const r = i % 2 ? 3.5 : 9, a = -Math.PI / 2 + (i * Math.PI) / 5;
    ctx.lineTo(u + r * Math.cos(a), v + r * Math.sin(a));
  }
  ctx.closePath(); ctx.fill();
}

function draw() {
  fit();
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const st = S.static, f = S.frame;
  if (!st) return;
  const [x0, y0, x1, y1] = st.bounds;
  const [a, b] = px(x0, y1), [c, d] = px(x1, y0);
  ctx.fillStyle = "#f7f7f2"; ctx.fillRect(a, b, c - a, d - b);
  if (!S.mapImage || st.slam) {
    ctx.fillStyle = st.slam ? "rgba(120,120,120,0.3)" : "#555";
    st.polygons.forEach((p) => { path(p, true); ctx.fill(); });
    st.circles.forEach(([cx, cy, r]) => { const [u, v] = px(cx, cy); ctx.beginPath(); ctx.arc(u, v, r * view.scale, 0, 2 * Math.PI); ctx.fill(); });
  }
  if (S.mapImage) grid(S.map, S.mapImage, [0, 0, 0]);
  const which = $("costmap").value;
  if (S.costmapImages[which]) grid(S.costmaps[which], S.costmapImages[which], S.costmaps[which].pose);
  if (!f) return;
  f.goals.forEach(([gx, gy]) => star(gx, gy, "#2ca02c"));
  ctx.fillStyle = "#ff7f0e";
  f.movers.forEach((m) => { path(m, true); ctx.fill(); });
  line(f.plan, "#2ca02c", 2, [8, 4]);
  if (f.particles) dots(f.particles, "#7e3fbf", 2);
  line(f.local_plan, "#e377c2", 3);
  f.drawings.forEach((dr) => {
    if (dr.kind === "points") dots(dr.points, dr.color, 3);
    else { ctx.strokeStyle = dr.color; ctx.lineWidth = 2; path(dr.points, dr.kind === "polygon"); ctx.stroke(); }
  });
  dots(f.scan, "#d62728", 3);
  const [rx, ry, ryaw] = f.robot;
  const fp = st.footprint, c0 = Math.cos(ryaw), s0 = Math.sin(ryaw), placed = [];
  for (let i = 0; i + 1 < fp.length; i += 2) placed.push(rx + c0 * fp[i] - s0 * fp[i + 1], ry + s0 * fp[i] + c0 * fp[i + 1]);
  ctx.fillStyle = "rgba(31,95,191,0.6)"; ctx.strokeStyle = "#0b2f6b"; ctx.lineWidth = 1.5;
  path(placed, true); ctx.fill(); ctx.stroke();
  arrow(rx, ry, ryaw, "#0b2f6b", 18);
  if (S.drag) arrow(S.drag.x, S.drag.y, S.drag.yaw, S.tool === "goal" ? "#2ca02c" : "#17becf", 40);
}

// -- controls ---------------------------------------------------------------------

$("pause").onclick = () => send({ cmd: S.frame && S.frame.paused ? "resume" : "pause" });
$("step").onclick = () => send({ cmd: "step" });
document.querySelectorAll(".speed").forEach((b) => { b.onclick = () => send({ cmd: "speed", value: Number(b.dataset.speed) }); });
$("costmap").onchange = () => { send({ cmd: "costmap", which: $("costmap").value }); requestAnimationFrame(draw); };
document.querySelectorAll(".tool").forEach((b) => {
  b.onclick = () => {
    S.tool = S.tool === b.dataset.tool ? null : b.dataset.tool;
    document.querySelectorAll(".tool").forEach((o) => o.classList.toggle("on", o.dataset.tool === S.tool));
    canvas.classList.toggle("tool", !!S.tool);
  };
});
canvas.addEventListener("mousedown", (e) => {
  if (!S.tool) return;
  const [x, y] = world(e.offsetX, e.offsetY);
  S.drag = { x, y, yaw: 0 };
});
canvas.addEventListener("mousemove", (e) => {
  if (!S.drag) return;
  const [x, y] = world(e.offsetX, e.offsetY);
  if (Math.hypot(x - S.drag.x, y - S.drag.y) > 1e-3) S.drag.yaw = Math.atan2(y - S.drag.y, x - S.drag.x);
  requestAnimationFrame(draw);
});
canvas.addEventListener("mouseup", () => {
  if (!S.drag) return;
  send({ cmd: S.tool, pose: [S.drag.x, S.drag.y, S.drag.yaw] });
  S.drag = null; S.tool = null;
  document.querySelectorAll(".tool").forEach((o) => o.classList.remove("on"));
  canvas.classList.remove("tool");
});
$("slider").oninput = () => send({ cmd: "seek", index: Number($("slider").value) });
$("play").onclick = () => {
  if (S.playing) { clearInterval(S.playing); S.playing = null; $("play").textContent = "Play"; return; }
  $("play").textContent = "Stop";
  const period = S.replay ? 1000 / S.replay.rate : 200;
  S.playing = setInterval(() => {
    const next = Number($("slider").value) + 1;
    if (next >= S.replay.count) { $("play").click(); return; }
    $("slider").value = String(next);
    send({ cmd: "seek", index: next });
  }, period);
};
window.addEventListener("resize", () => requestAnimationFrame(draw));
document.body.className = "live";
connect();
