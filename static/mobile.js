// The mobile world's page (served at / by `hri-lab serve --world mobile`): a top view of the
// arena (the base where it truly is, the scan's points, the odometry's trail), a polar plot of
// /scan and the teleop (POST /mobile/drive, sent again every 100 ms while a key is held: the base's
// watchdog stops it 0.5 s after the last one). It reads the topics over HTTP (GET /topics/NAME).
"use strict";

const state = { arena: null, scan: null, pose: null, odom: null, wall: null, trail: [], held: null };

// a path of the lab as a URL relative to this page: served at / or under a JupyterHub's prefix
const here = (path) => new URL(path.replace(/^\//, ""), document.baseURI).href;

async function get(path) {
  const response = await fetch(here(path));
  if (!response.ok) throw new Error(`${path}: ${response.status}`);
  return response.json();
}

async function post(path, body) {
  const response = await fetch(here(path), {
    method: "POST",
    headers: { "content-type": "application/json" },
    body: JSON.stringify(body || {}),
  });
  const answer = await response.json().catch(() => ({}));
  document.getElementById("f-error").textContent = response.ok ? "" : `${path}: ${JSON.stringify(answer.detail || answer)}`;
  return answer;
}

function yawOf(q) {
  return 2 * Math.atan2(q.z, q.w);
}

function drawArena() {
  const canvas = document.getElementById("arena");
  const ctx = canvas.getContext("2d");
  const a = state.arena;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!a) return;
  const [hx, hy] = a.half_size_xy;
  const scale = (canvas.width - 20) / (2 * Math.max(hx, hy));
  const px = (x) => canvas.width / 2 + x * scale;
  const py = (y) => canvas.height / 2 - y * scale;
  ctx.strokeStyle = "#888";
  ctx.lineWidth = 4;
  ctx.strokeRect(px(-hx), py(hy), 2 * hx * scale, 2 * hy * scale);
  ctx.fillStyle = "#e6a03c";
  for (const o of a.obstacles) {
    ctx.save();
    ctx.translate(px(o.center_xy[0]), py(o.center_xy[1]));
    ctx.rotate(-o.yaw);
    ctx.beginPath();
    if (o.shape === "cylinder") ctx.arc(0, 0, o.size[0] * scale, 0, 2 * Math.PI);
    else ctx.rect(-o.size[0] * scale, -o.size[1] * scale, 2 * o.size[0] * scale, 2 * o.size[1] * scale);
    ctx.fill();
    ctx.restore();
  }
  if (state.trail.length > 1) {
    ctx.strokeStyle = "#2878dc";
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    state.trail.forEach(([x, y], i) => (i ? ctx.lineTo(px(x), py(y)) : ctx.moveTo(px(x), py(y))));
    ctx.stroke();
  }
  const pose = state.pose;
  if (!pose) return;
  if (state.scan) {
    const s = state.scan;
    const [ox, oy] = a.scan_offset_xy;
    const sx = pose.x + Math.cos(pose.theta) * ox - Math.sin(pose.theta) * oy;
    const sy = pose.y + Math.sin(pose.theta) * ox + Math.cos(pose.theta) * oy;
    ctx.fillStyle = "#dc1e1e";
    s.ranges.forEach((r, i) => {
      if (r === null || !isFinite(r)) return;
      const angle = pose.theta + s.angle_min + i * s.angle_increment;
      ctx.fillRect(px(sx + r * Math.cos(angle)) - 1.5, py(sy + r * Math.sin(angle)) - 1.5, 3, 3);
    });
  }
  ctx.fillStyle = state.wall && state.wall.contact ? "#e62828" : "#3c3c46";
  ctx.beginPath();
  ctx.arc(px(pose.x), py(pose.y), a.footprint_radius * scale, 0, 2 * Math.PI);
  ctx.fill();
  ctx.strokeStyle = "#fff";
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(px(pose.x), py(pose.y));
  ctx.lineTo(px(pose.x + a.footprint_radius * Math.cos(pose.theta)), py(pose.y + a.footprint_radius * Math.sin(pose.theta)));
  ctx.stroke();
}

function drawPolar() {
  const canvas = document.getElementById("polar");
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const s = state.scan;
  const c = canvas.width / 2;
  const max = s ? s.range_max : 3.5;
  const scale = (c - 10) / max;
  ctx.strokeStyle = "#ddd";
  for (let ring = 1; ring <= max; ring += 1) {
    ctx.beginPath();
    ctx.arc(c, c, ring * scale, 0, 2 * Math.PI);
    ctx.stroke();
  }
  if (!s) return;
  ctx.fillStyle = "#dc1e1e";
  s.ranges.forEach((r, i) => {
    if (r === null || !isFinite(r)) return;
    const angle = s.angle_min + i * s.angle_increment; // 0 ahead (up), counter-clockwise
    ctx.fillRect(c - r * scale * Math.sin(angle) - 1.5, c - r * scale * Math.cos(angle) - 1.5, 3, 3);
  });
  ctx.fillStyle = "#3c3c46";
  ctx.beginPath();
  ctx.moveTo(c, c - 8);
  ctx.lineTo(c - 5, c + 5);
  ctx.lineTo(c + 5, c + 5);
  ctx.fill();
}

function showFigures() {
  const { pose, odom, wall } = state;
  if (pose) document.getElementById("f-pose").textContent = `x ${pose.x.toFixed(2)} y ${pose.y.toFixed(2)} m`;
  if (odom) {
    const t = odom.twist.twist;
    document.getElementById("f-twist").textContent = `v ${t.linear.x.toFixed(2)} m/s, w ${t.angular.z.toFixed(2)} rad/s`;
  }
  if (wall) {
    document.getElementById("f-obstacle").textContent = `obstacle ${wall.distance.toFixed(2)} m`;
    document.getElementById("f-circuit").textContent = `around it ${Math.abs(wall.circuit_deg).toFixed(0)} deg`;
    showTrial(wall);
  }
}

// The wall-following trial as the grader judges it (/wall_following): PASS or FAIL with the
// monitor's reason once it is done; running with its clock before (the clock starts at the first
// command).
function showTrial(wall) {
  const el = document.getElementById("f-trial");
  const state = !wall.done ? (wall.elapsed > 0 ? "running" : "none") : wall.passed ? "succeeded" : "failed";
  const head = { none: "no trial yet", running: "trial running", succeeded: "PASS", failed: "FAIL" }[state];
  const said = `${head} ${wall.verdict}`;
  if (el.dataset.state === state && el.dataset.said === said) return;
  el.className = `result trial-${state}`;
  el.dataset.state = state;
  el.dataset.said = said;
  el.textContent = "";
  const bold = document.createElement("b");
  bold.textContent = head;
  el.append(bold, state === "none" ? ": its clock starts at the first command" : ` · ${wall.elapsed.toFixed(1)} s`);
  if (wall.verdict) {
    const reason = document.createElement("div");
    reason.textContent = wall.verdict;
    el.append(reason);
  }
}

// The simulated time and the loop's rate, as the lifting page's header shows them (GET /health).
async function pollHealth() {
  try {
    const h = await get("/health");
    document.getElementById("health").textContent = h.loop_alive ? `simulation ${h.rate_hz.toFixed(0)} Hz, t = ${h.sim_time.toFixed(1)} s` : "simulation stopped";
  } catch (error) {
    document.getElementById("health").textContent = `no answer: ${error.message}`;
  }
}

async function poll() {
  try {
    const [pose, odom, wall] = await Promise.all([get("/topics/ground_truth_pose"), get("/topics/odom"), get("/topics/wall_following")]);
    state.pose = pose;
    state.odom = odom;
    state.wall = wall;
    const p = odom.pose.pose.position;
    const last = state.trail[state.trail.length - 1];
    if (!last || Math.hypot(p.x - last[0], p.y - last[1]) > 0.01) state.trail.push([p.x, p.y]);
    if (state.trail.length > 3000) state.trail.shift();
    showFigures();
    drawArena();
  } catch (error) {
    document.getElementById("health").textContent = `no answer: ${error.message}`;
  }
}

async function pollScan() {
  try {
    state.scan = await get("/topics/scan");
    drawPolar();
  } catch (error) {
    /* shown by poll() */
  }
}

const KEYS = { w: [1, 0], s: [-1, 0], a: [0, 1], d: [0, -1], x: [0, 0] };

function twistOf(key) {
  const [linear, angular] = KEYS[key];
  return {
    linear_x: linear * Number(document.getElementById("speed").value),
    angular_z: angular * Number(document.getElementById("turn").value),
  };
}

function press(key) {
  if (!(key in KEYS)) return;
  state.held = key === "x" ? null : key;
  post("/mobile/drive", twistOf(key));
}

function release() {
  if (state.held !== null) post("/mobile/drive", { linear_x: 0, angular_z: 0 });
  state.held = null;
}

async function start() {
  state.arena = await get("/mobile/arena");
  const view = await get("/view").catch(() => ({ url: null }));
  if (view.url) {
    const link = document.getElementById("view-link");
    link.href = view.relay ? here(view.relay) : view.url;  // behind a JupyterHub: through this server
    link.hidden = false;
  }
  document.querySelectorAll("[data-key]").forEach((button) => {
    button.addEventListener("pointerdown", () => press(button.dataset.key));
    button.addEventListener("pointerup", release);
    button.addEventListener("pointerleave", release);
  });
  document.addEventListener("keydown", (event) => {
    if (event.target.tagName !== "INPUT" && !event.repeat) press(event.key.toLowerCase());
  });
  document.addEventListener("keyup", (event) => {
    if (event.key.toLowerCase() === state.held) release();
  });
  document.getElementById("reset").addEventListener("click", () => {
    state.trail = [];
    post("/mobile/reset");
  });
  setInterval(() => state.held && post("/mobile/drive", twistOf(state.held)), 100);
  setInterval(poll, 100);
  setInterval(pollScan, 200);
  pollHealth();
  setInterval(pollHealth, 1000);
}

start();
