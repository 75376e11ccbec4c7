// e-puck Conquest web UI: Map, Steer, Statistics.
//
// The server pushes one snapshot, then frames of changes (see
// phone-sim/src/serve/api.rs); this file keeps a copy of the model, draws
// it, and sends commands back over the same WebSocket. No framework, no
// network beyond this server: the page works offline on a phone.
"use strict";

const COLORS = ["#1f6feb", "#d9480f", "#2b8a3e", "#ae3ec9", "#e8a200", "#0c8599", "#c2255c", "#5c7cfa"];
const HEADINGS = [[0, 1], [1, 0], [0, -1], [-1, 0]]; // N E S W: (dx, dy), y north
const $ = (id) => document.getElementById(id);

// ---- the model (a copy of the server's) --------------------------------
const model = {
  connected: false,
  run: null, status: "connecting", t: 0, rate: 4,
  nodes: new Map(),      // "x,y" -> {x, y, arms, visits}
  frontier: [],
  robots: [],
  trails: [],
  stats: {}, coverage: [], log: [], result: null, choices: null,
};
const ui = { selected: null, autoFit: true, view: { s: 40, ox: 0, oy: 0 }, pointers: new Map(), tilt: null };

const key = (x, y) => x + "," + y;

function applySnapshot(s) {
  model.run = s.run; model.status = s.status; model.t = s.t_ms; model.rate = s.rate;
  model.nodes = new Map();
  for (const n of s.nodes) setNode(n);
  model.frontier = s.frontier;
  model.robots = s.robots;
  model.trails = s.trails;
  model.stats = s.stats; model.coverage = s.coverage; model.log = s.log;
  model.result = s.result; model.choices = s.choices;
  if (ui.selected !== null && ui.selected >= model.robots.length) ui.selected = null;
  fillChoices();
  ui.autoFit = true;
  render();
}

function applyFrame(f) {
  model.t = f.t_ms;
  if (f.status) model.status = f.status;
  for (const n of f.nodes) setNode(n);
  if (f.frontier) model.frontier = f.frontier;
  const before = model.robots;
  model.robots = f.robots;
  announceLinkChanges(before, f.robots);
  for (const [id, x, y] of f.trail_add) {
    while (model.trails.length <= id) model.trails.push([]);
    model.trails[id].push([x, y]);
  }
  model.stats = f.stats;
  for (const c of f.coverage_add) model.coverage.push(c);
  for (const l of f.log_add) model.log.push(l);
  if (model.log.length > 400) model.log.splice(0, model.log.length - 400);
  model.result = f.result;
  render();
}

function setNode([x, y, arms, visits]) {
  model.nodes.set(key(x, y), { x, y, arms, visits });
}

function announceLinkChanges(before, after) {
  const lost = after.filter((r) => !r.link_up && r.failed).map((r) => r.id);
  const wasLost = before.filter((r) => !r.link_up && r.failed).map((r) => r.id);
  if (lost.length) {
    showBanner("Link lost: robot " + lost.join(", ") + " (the team plans around it; waiting for it to come back)", "warn", "robots");
  } else if (wasLost.length) {
    showBanner("Link back: robot " + wasLost.join(", "), "info", "robots", 4000);
  }
}

// ---- the connection ----------------------------------------------------
let socket = null;
let retryMs = 500;

function connect() {
  const proto = location.protocol === "https:" ? "wss:" : "ws:";
  socket = new WebSocket(proto + "//" + location.host + "/ws");
  socket.onopen = () => {
    model.connected = true; retryMs = 500;
    hideBanner("socket");
  };
  socket.onmessage = (ev) => {
    let msg;
    try { msg = JSON.parse(ev.data); } catch (e) { return; }
    if (msg.type === "snapshot") applySnapshot(msg);
    else if (msg.type === "frame") applyFrame(msg);
    else if (msg.type === "error") showBanner(msg.message, "info", "error", 5000);
  };
  socket.onclose = () => {
    model.connected = false;
    showBanner("Connection to the server lost — reconnecting…", "warn", "socket");
    render();
    setTimeout(connect, retryMs);
    retryMs = Math.min(retryMs * 2, 5000);
  };
}

function send(cmd) {
  if (socket && socket.readyState === WebSocket.OPEN) {
    socket.send(JSON.stringify(cmd));
    return true;
  }
  showBanner("Not connected: command not sent", "warn", "error", 3000);
  return false;
}

let bannerOwner = null, bannerTimer = null;
function showBanner(text, kind, owner, ms) {
  const b = $("banner");
  b.textContent = text; b.className = "banner" + (kind === "info" ? " info" : "");
  b.hidden = false; bannerOwner = owner;
  clearTimeout(bannerTimer);
  if (ms) bannerTimer = setTimeout(() => hideBanner(owner), ms);
}
function hideBanner(owner) {
  if (bannerOwner === owner) { $("banner").hidden = true; bannerOwner = null; }
}

// ---- controls ----------------------------------------------------------
function fillChoices() {
  const c = model.choices;
  if (!c || !model.run) return;
  const field = $("field");
  const names = c.fields.map((f) => f.name);
  if (field.dataset.names !== names.join("\n")) {
    field.innerHTML = "";
    for (const f of c.fields) {
      const o = document.createElement("option");
      o.value = f.name; o.textContent = f.name + " (" + f.nodes + " nodes, " + f.starts + " starts)";
      field.appendChild(o);
    }
    field.dataset.names = names.join("\n");
  }
  field.value = model.run.field;
  const strat = $("strategy");
  if (strat.options.length !== c.strategies.length) {
    strat.innerHTML = "";
    for (const s of c.strategies) {
      const o = document.createElement("option"); o.value = s; o.textContent = s; strat.appendChild(o);
    }
  }
  strat.value = model.run.strategy;
  $("robots").value = model.run.robots;
  $("seed").value = model.run.seed;
  $("rate").value = String(model.rate);
  const sim = model.run.mode === "sim";
  for (const id of ["field", "robots", "strategy", "seed", "btn-start", "rate", "btn-cut"]) $(id).disabled = !sim;
}

function wireControls() {
  for (const b of document.querySelectorAll("nav button")) {
    b.addEventListener("click", () => setView(b.dataset.view));
  }
  $("btn-menu").addEventListener("click", () => {
    const on = document.body.classList.toggle("show-controls");
    $("btn-menu").setAttribute("aria-expanded", String(on));
    requestAnimationFrame(render);
  });
  $("btn-start").addEventListener("click", () => send({
    type: "start", field: $("field").value, robots: Number($("robots").value),
    strategy: $("strategy").value, seed: Number($("seed").value),
  }));
  $("btn-pause").addEventListener("click", () => send({ type: model.status === "paused" ? "resume" : "pause" }));
  $("btn-stop").addEventListener("click", () => send({ type: "stop" }));
  $("rate").addEventListener("change", () => send({ type: "rate", x: Number($("rate").value) }));
  $("btn-fit").addEventListener("click", () => { ui.autoFit = true; render(); });
  $("trails").addEventListener("change", render);
  $("import").addEventListener("change", importField);
  $("btn-manual").addEventListener("click", () => {
    const r = selectedRobot();
    if (r) send({ type: "manual", robot: r.id, on: !r.manual });
  });
  $("btn-fwd").addEventListener("click", () => steer("fwd"));
  $("btn-left").addEventListener("click", () => steer("left"));
  $("btn-right").addEventListener("click", () => steer("right"));
  $("btn-back").addEventListener("click", () => steer("back"));
  $("speed").addEventListener("input", () => { $("speed-out").textContent = $("speed").value; });
  $("speed").addEventListener("change", () => {
    const r = selectedRobot();
    if (r) send({ type: "speed", robot: r.id, steps_per_s: Number($("speed").value) });
  });
  $("btn-cut").addEventListener("click", () => {
    const r = selectedRobot();
    if (r) send({ type: "cut_link", robot: r.id, seconds: 10 });
  });
  $("tilt").addEventListener("change", toggleTilt);
  document.addEventListener("keydown", (e) => {
    if (e.target && (e.target.tagName === "INPUT" || e.target.tagName === "SELECT")) return;
    const k = { ArrowUp: "fwd", ArrowLeft: "left", ArrowRight: "right", ArrowDown: "back" }[e.key];
    if (k && selectedRobot() && selectedRobot().manual) { e.preventDefault(); steer(k); }
  });
}

async function importField(e) {
  const file = e.target.files && e.target.files[0];
  if (!file) return;
  const body = await file.arrayBuffer();
  const res = await fetch("/api/import?name=" + encodeURIComponent(file.name), { method: "POST", body });
  const data = await res.json().catch(() => ({ error: "bad answer" }));
  if (!res.ok) showBanner("Import failed: " + data.error, "warn", "error", 8000);
  else showBanner("Imported " + data.name + ": choose it and press Start", "info", "error", 5000);
  e.target.value = "";
}

function setView(v) {
  document.body.dataset.view = v;
  for (const b of document.querySelectorAll("nav button")) b.setAttribute("aria-selected", String(b.dataset.view === v));
  requestAnimationFrame(render);
}

function selectedRobot() {
  return ui.selected === null ? null : model.robots.find((r) => r.id === ui.selected) || null;
}

// Whether `r` can drive straight on: it stands on a node with an arm ahead.
function canDrive(r) {
  if (!r.node || Math.abs(r.x - r.node[0]) > 1e-6 || Math.abs(r.y - r.node[1]) > 1e-6) return false;
  const n = model.nodes.get(key(r.node[0], r.node[1]));
  return !!n && (n.arms & (1 << r.heading)) !== 0;
}

function steer(what) {
  const r = selectedRobot();
  if (!r || !r.manual) return;
  if (what === "fwd") { if (canDrive(r)) send({ type: "move", robot: r.id }); }
  else send({ type: "turn", robot: r.id, turn: what });
}

function toggleTilt() {
  if (!$("tilt").checked) { ui.tilt = null; return; }
  const start = () => {
    ui.tilt = { last: 0 };
    window.addEventListener("deviceorientation", onTilt);
  };
  if (typeof DeviceOrientationEvent !== "undefined" && DeviceOrientationEvent.requestPermission) {
    DeviceOrientationEvent.requestPermission().then((p) => p === "granted" ? start() : ($("tilt").checked = false));
  } else start();
}

// Tilt forward to drive, sideways to turn; one order per second at most.
function onTilt(e) {
  if (!ui.tilt || e.beta === null) return;
  const now = Date.now();
  if (now - ui.tilt.last < 1000) return;
  let what = null;
  if (e.beta < -20) what = "fwd";
  else if (e.gamma < -25) what = "left";
  else if (e.gamma > 25) what = "right";
  if (what) { ui.tilt.last = now; steer(what); }
}

// ---- the map -----------------------------------------------------------
const canvas = $("map");
const ctx = canvas.getContext("2d");

function fit() {
  const w = canvas.clientWidth, h = canvas.clientHeight;
  let xs = [], ys = [];
  for (const n of model.nodes.values()) { xs.push(n.x); ys.push(n.y); }
  for (const r of model.robots) { xs.push(r.x); ys.push(r.y); }
  if (!xs.length && model.run) {
    const [bx, by, bw, bh] = model.run.bounds; xs = [bx, bx + bw - 1]; ys = [by, by + bh - 1];
  }
  if (!xs.length) return;
  // At least 8 nodes across, so that a fresh map is not blown up.
  const cx = (Math.min(...xs) + Math.max(...xs)) / 2, cy = (Math.min(...ys) + Math.max(...ys)) / 2;
  const spanx = Math.max(8, Math.max(...xs) - Math.min(...xs) + 2);
  const spany = Math.max(8, Math.max(...ys) - Math.min(...ys) + 2);
  const minx = cx - spanx / 2, maxx = cx + spanx / 2, miny = cy - spany / 2, maxy = cy + spany / 2;
  const s = Math.max(2, Math.min(w / (maxx - minx), h / (maxy - miny), 80));
  ui.view.s = s;
  ui.view.ox = w / 2 - ((minx + maxx) / 2) * s;
  ui.view.oy = h / 2 + ((miny + maxy) / 2) * s;
}

const sx = (x) => ui.view.ox + x * ui.view.s;
const sy = (y) => ui.view.oy - y * ui.view.s;
const wx = (px) => (px - ui.view.ox) / ui.view.s;
const wy = (py) => (ui.view.oy - py) / ui.view.s;

function drawMap() {
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (!w || !h) return;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
  }
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, w, h);
  if (ui.autoFit) fit();
  const s = ui.view.s;
  // Squares: stronger green with every visit; deduced nodes grey.
  for (const n of model.nodes.values()) {
    ctx.fillStyle = n.visits === 0 ? "#e4e7eb" : visitColor(n.visits);
    ctx.fillRect(sx(n.x) - s / 2 + 0.5, sy(n.y) - s / 2 + 0.5, s - 1, s - 1);
  }
  // Frontier: dashed orange squares.
  ctx.strokeStyle = "#e8590c"; ctx.lineWidth = Math.max(1, s / 16);
  ctx.setLineDash([Math.max(2, s / 8), Math.max(2, s / 8)]);
  for (const [x, y] of model.frontier) ctx.strokeRect(sx(x) - s * 0.35, sy(y) - s * 0.35, s * 0.7, s * 0.7);
  ctx.setLineDash([]);
  // Glyphs: the node's arms, drawn to the square's edge.
  ctx.strokeStyle = "#1d232b"; ctx.lineCap = "round"; ctx.lineWidth = Math.max(1.5, s / 9);
  for (const n of model.nodes.values()) {
    const cx = sx(n.x), cy = sy(n.y);
    ctx.beginPath();
    for (let h = 0; h < 4; h++) {
      if (n.arms & (1 << h)) {
        ctx.moveTo(cx, cy);
        ctx.lineTo(cx + HEADINGS[h][0] * s / 2, cy - HEADINGS[h][1] * s / 2);
      }
    }
    ctx.stroke();
    if (n.arms === 0) { ctx.fillStyle = "#1d232b"; ctx.fillRect(cx - 2, cy - 2, 4, 4); }
  }
  if ($("trails").checked) {
    ctx.lineWidth = Math.max(1.5, s / 12); ctx.globalAlpha = 0.45;
    model.trails.forEach((t, i) => {
      if (t.length < 2) return;
      ctx.strokeStyle = COLORS[i % COLORS.length];
      const off = (i - (model.trails.length - 1) / 2) * Math.min(3, s / 20);
      ctx.beginPath();
      t.forEach(([x, y], j) => (j ? ctx.lineTo : ctx.moveTo).call(ctx, sx(x) + off, sy(y) + off));
      ctx.stroke();
    });
    ctx.globalAlpha = 1;
  }
  for (const r of model.robots) drawRobot(r, s);
}

function visitColor(v) {
  const k = Math.min(v, 5) - 1; // 0..4
  const light = [207, 232, 213], dark = [47, 125, 70];
  const c = light.map((l, i) => Math.round(l + (dark[i] - l) * (k / 4)));
  return "rgb(" + c.join(",") + ")";
}

function drawRobot(r, s) {
  const color = r.failed ? "#868e96" : COLORS[r.id % COLORS.length];
  const cx = sx(r.x), cy = sy(r.y), rad = Math.max(6, s * 0.3);
  if (r.target) {
    ctx.strokeStyle = color; ctx.lineWidth = 1.5; ctx.setLineDash([4, 4]);
    ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(sx(r.target[0]), sy(r.target[1])); ctx.stroke();
    ctx.setLineDash([]);
    const tx = sx(r.target[0]), ty = sy(r.target[1]), q = Math.max(4, s * 0.18);
    ctx.beginPath(); ctx.moveTo(tx - q, ty - q); ctx.lineTo(tx + q, ty + q);
    ctx.moveTo(tx + q, ty - q); ctx.lineTo(tx - q, ty + q); ctx.stroke();
  }
  if (r.id === ui.selected) {
    ctx.strokeStyle = "#10161d"; ctx.lineWidth = 3;
    ctx.beginPath(); ctx.arc(cx, cy, rad + 5, 0, Math.PI * 2); ctx.stroke();
  }
  ctx.fillStyle = color;
  ctx.beginPath(); ctx.arc(cx, cy, rad, 0, Math.PI * 2); ctx.fill();
  // Heading: a white wedge pointing the way it faces.
  const [dx, dy] = HEADINGS[r.heading % 4];
  ctx.fillStyle = "#fff";
  ctx.beginPath();
  ctx.moveTo(cx + dx * rad * 0.9, cy - dy * rad * 0.9);
  ctx.lineTo(cx - dy * rad * 0.45 - dx * rad * 0.2, cy - dx * rad * 0.45 + dy * rad * 0.2);
  ctx.lineTo(cx + dy * rad * 0.45 - dx * rad * 0.2, cy + dx * rad * 0.45 + dy * rad * 0.2);
  ctx.closePath(); ctx.fill();
  ctx.fillStyle = "#10161d"; ctx.font = "bold " + Math.max(10, Math.round(rad * 0.9)) + "px system-ui";
  ctx.textAlign = "left"; ctx.textBaseline = "bottom";
  ctx.fillText(String(r.id) + (r.manual ? " (manual)" : "") + (r.failed && !r.link_up ? " (link lost)" : ""),
    cx + rad * 0.8, cy - rad * 0.6);
}

function wireMap() {
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    zoomAt(e.offsetX, e.offsetY, Math.exp(-e.deltaY * 0.0015));
  }, { passive: false });
  canvas.addEventListener("pointerdown", (e) => {
    canvas.setPointerCapture(e.pointerId);
    ui.pointers.set(e.pointerId, { x: e.offsetX, y: e.offsetY, x0: e.offsetX, y0: e.offsetY });
  });
  canvas.addEventListener("pointermove", (e) => {
    const p = ui.pointers.get(e.pointerId);
    if (!p) return;
    if (ui.pointers.size === 1) {
      ui.view.ox += e.offsetX - p.x; ui.view.oy += e.offsetY - p.y;
      if (Math.hypot(e.offsetX - p.x0, e.offsetY - p.y0) > 4) ui.autoFit = false;
    } else if (ui.pointers.size === 2) {
      const [a, b] = [...ui.pointers.values()];
      const before = Math.hypot(a.x - b.x, a.y - b.y);
      p.x = e.offsetX; p.y = e.offsetY;
      const [c, d] = [...ui.pointers.values()];
      const after = Math.hypot(c.x - d.x, c.y - d.y);
      if (before > 0) zoomAt((c.x + d.x) / 2, (c.y + d.y) / 2, after / before);
      drawMap();
      return;
    }
    p.x = e.offsetX; p.y = e.offsetY;
    drawMap();
  });
  const up = (e) => {
    const p = ui.pointers.get(e.pointerId);
    ui.pointers.delete(e.pointerId);
    if (p && Math.hypot(e.offsetX - p.x0, e.offsetY - p.y0) <= 4) pick(e.offsetX, e.offsetY);
  };
  canvas.addEventListener("pointerup", up);
  canvas.addEventListener("pointercancel", (e) => ui.pointers.delete(e.pointerId));
  window.addEventListener("resize", () => render());
}

function zoomAt(px, py, f) {
  ui.autoFit = false;
  const x = wx(px), y = wy(py);
  ui.view.s = Math.max(2, Math.min(300, ui.view.s * f));
  ui.view.ox = px - x * ui.view.s;
  ui.view.oy = py + y * ui.view.s;
  drawMap();
}

// A tap selects the nearest robot within half a node.
function pick(px, py) {
  const x = wx(px), y = wy(py);
  let best = null, bd = 0.6;
  for (const r of model.robots) {
    const d = Math.hypot(r.x - x, r.y - y);
    if (d < bd) { bd = d; best = r; }
  }
  if (best) { ui.selected = best.id; render(); }
}

// ---- the panels --------------------------------------------------------
function render() {
  const st = model.connected ? model.status : "offline";
  $("status").textContent = st;
  $("status").dataset.status = st;
  $("clock").textContent = (model.t / 1000).toFixed(1) + " s";
  $("btn-pause").textContent = model.status === "paused" ? "Resume" : "Pause";
  $("btn-start").textContent = model.status === "ready" ? "Start" : "Restart";
  drawMap();
  renderSteer();
  renderStats();
}

function renderSteer() {
  const list = $("robot-list");
  const sig = model.robots.map((r) => [r.id, r.manual, r.link_up && !r.failed, r.id === ui.selected].join()).join(";");
  if (list.dataset.sig !== sig) {
    list.innerHTML = "";
    for (const r of model.robots) {
      const b = document.createElement("button");
      b.dataset.robot = r.id;
      b.setAttribute("aria-pressed", String(r.id === ui.selected));
      b.innerHTML = '<i class="dot" style="background:' + COLORS[r.id % COLORS.length] + '"></i>robot ' + r.id +
        (r.manual ? " (manual)" : "") + (r.failed && !r.link_up ? ' <span class="badge">link lost</span>' : "");
      b.addEventListener("click", () => { ui.selected = r.id; render(); });
      list.appendChild(b);
    }
    list.dataset.sig = sig;
  }
  const r = selectedRobot();
  const manual = !!(r && r.manual);
  $("btn-manual").disabled = !r;
  $("btn-manual").textContent = manual ? "Hand back" : "Take control";
  $("btn-fwd").disabled = !manual || !canDrive(r);
  for (const id of ["btn-left", "btn-right", "btn-back"]) $(id).disabled = !manual;
  $("btn-cut").disabled = !r || !model.run || model.run.mode !== "sim";
  $("steer-info").textContent = r
    ? "robot " + r.id + ": " + r.state + (r.node ? " at (" + r.node[0] + ", " + r.node[1] + ") facing " + "NESW"[r.heading] : "") +
      (r.failed && !r.link_up ? ", link lost" : "")
    : "choose a robot (list or tap on the map)";
  if (r && document.activeElement !== $("speed")) { $("speed").value = r.speed; $("speed-out").textContent = r.speed; }
}

function renderStats() {
  const s = model.stats || {};
  const total = model.run && model.run.total_nodes;
  $("stat-runtime").textContent = (model.t / 1000).toFixed(1) + " s";
  $("stat-known").textContent = (s.known || 0) + (total ? " / " + total : "");
  $("stat-coverage").textContent = total ? Math.round((100 * (s.known || 0)) / total) + " %" : "–";
  $("stat-frontier").textContent = s.frontier || 0;
  $("stat-messages").textContent = s.received || 0;
  $("stat-relayed").textContent = s.relayed || 0;
  $("stat-errors").textContent = s.link_errors || 0;
  $("stat-retx").textContent = s.retransmissions || 0;
  $("stat-losses").textContent = s.link_losses || 0;
  const res = model.result;
  $("stat-result").textContent = res
    ? res.makespan_s.toFixed(1) + " s" + (res.lower_bound_s ? " / " + res.lower_bound_s.toFixed(1) + " s = " +
      (res.makespan_s / res.lower_bound_s).toFixed(2) + "×" : "") + (res.complete ? " ✓ complete" : " (incomplete)")
    : (model.run && model.run.lower_bound_s ? "bound " + model.run.lower_bound_s.toFixed(1) + " s" : "running");
  const body = $("robot-table").tBodies[0];
  body.innerHTML = "";
  for (const r of model.robots) {
    const tr = document.createElement("tr");
    tr.dataset.robot = r.id;
    const ratio = r.driven ? (r.explored / r.driven).toFixed(2) : "–";
    const at = r.node ? "(" + r.node[0] + ", " + r.node[1] + ") " + "NESW"[r.heading] : "–";
    const cells = ["robot " + r.id, r.state + (r.manual ? " (manual)" : ""), r.link_up ? "up" : "lost", at,
      r.explored, r.driven, ratio, r.revisits, r.collisions, r.messages];
    for (const c of cells) { const td = document.createElement("td"); td.textContent = c; tr.appendChild(td); }
    tr.firstChild.style.color = COLORS[r.id % COLORS.length];
    body.appendChild(tr);
  }
  const log = $("log");
  if (log.childElementCount !== model.log.length || log.dataset.last !== model.log[model.log.length - 1]) {
    log.innerHTML = "";
    for (const l of model.log.slice(-200)) { const li = document.createElement("li"); li.textContent = l; log.appendChild(li); }
    log.dataset.last = model.log[model.log.length - 1] || "";
    log.scrollTop = log.scrollHeight;
  }
  if (document.body.dataset.view === "stats") drawCoverage();
}

function drawCoverage() {
  const c = $("coverage"), g = c.getContext("2d");
  const dpr = window.devicePixelRatio || 1, w = c.clientWidth, h = c.clientHeight;
  if (!w || !h) return;
  c.width = Math.round(w * dpr); c.height = Math.round(h * dpr);
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.clearRect(0, 0, w, h);
  const pad = { l: 44, r: 12, t: 10, b: 26 };
  const total = (model.run && model.run.total_nodes) || Math.max(1, ...model.coverage.map((p) => p[1]));
  const tmax = Math.max(1000, model.t, ...model.coverage.map((p) => p[0]));
  const X = (t) => pad.l + (t / tmax) * (w - pad.l - pad.r);
  const Y = (k) => h - pad.b - (k / total) * (h - pad.t - pad.b);
  g.strokeStyle = "#d7dbe0"; g.fillStyle = "#67707c"; g.font = "11px system-ui"; g.lineWidth = 1;
  for (let i = 0; i <= 4; i++) {
    const k = (total * i) / 4;
    g.beginPath(); g.moveTo(pad.l, Y(k)); g.lineTo(w - pad.r, Y(k)); g.stroke();
    g.textAlign = "right"; g.textBaseline = "middle"; g.fillText(Math.round(k), pad.l - 4, Y(k));
  }
  g.textAlign = "center"; g.textBaseline = "top";
  for (let i = 0; i <= 4; i++) g.fillText(((tmax * i) / 4000).toFixed(0) + " s", X((tmax * i) / 4), h - pad.b + 6);
  if (model.result && model.result.lower_bound_s) {
    const xb = X(model.result.lower_bound_s * 1000);
    g.strokeStyle = "#e8590c"; g.setLineDash([4, 4]);
    g.beginPath(); g.moveTo(xb, pad.t); g.lineTo(xb, h - pad.b); g.stroke(); g.setLineDash([]);
  }
  g.strokeStyle = "#1f6feb"; g.lineWidth = 2; g.beginPath();
  g.moveTo(X(0), Y(0));
  for (const [t, k] of model.coverage) g.lineTo(X(t), Y(k));
  if (model.coverage.length) g.lineTo(X(model.t), Y(model.coverage[model.coverage.length - 1][1]));
  g.stroke();
}

// For tests and curious users: the page's copy of the model.
window.conquest = { model, ui, send };

wireControls();
wireMap();
connect();
