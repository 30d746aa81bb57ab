// The dashboard page: everything on it is generated from the API (services, parameters, topics,
// actions), so a service added to the registry appears here with no page change. The status,
// the plots and the results read the topics, so they are current whoever changed the state
// (this page, the 3D view, curl, the CLI, a node).
"use strict";

const $ = (tag, attrs = {}, ...children) => {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "text") el.textContent = v;
    else if (k.startsWith("on")) el.addEventListener(k.slice(2), v);
    else el.setAttribute(k, v);
  }
  for (const c of children) el.append(c);
  return el;
};
const byId = (id) => document.getElementById(id);
// A text or class written only when it changes: the status is rewritten at each of its topics'
// messages, and an unchanged write still has the browser lay the line out and paint it again.
const setText = (el, text) => { if (el.textContent !== text) el.textContent = text; };
const setClass = (el, name) => { if (el.className !== name) el.className = name; };
// A path of the lab ("/services") as a URL relative to this page, so that the page works wherever it
// is served: at / on a laptop, or under a prefix behind a JupyterHub (/user/NAME/hri-lab/).
const here = (path) => new URL(path.replace(/^\//, ""), document.baseURI).href;
const socketUrl = (path) => here(path).replace(/^http/, "ws");
// body: an object (sent as JSON), or a ready JSON text ({json: "..."}: numbers exactly as typed);
// raw: body is a YAML text
const api = async (method, path, body, raw) => {
  const init = { method, headers: {} };
  // a POST with nothing to send sends the empty request, {}: a body-less POST through JupyterHub's
  // proxy arrives typed as a form (tornado's HTTP client), which the lab refuses (app/security.py)
  if (body === undefined && method === "POST") body = {};
  if (body !== undefined) {
    if (raw) init.body = body;  // a YAML text (/params/load)
    else init.body = typeof body === "object" && "json" in body ? body.json : JSON.stringify(body);
    init.headers["content-type"] = raw ? "application/yaml" : "application/json";
  }
  const response = await fetch(here(path), init);
  const text = await response.text();
  let data;
  try { data = JSON.parse(text); } catch { data = text; }
  return { status: response.status, data, text };  // text: numbers exact (JSON.parse rounds int64)
};
const show = (value) => (typeof value === "string" ? value : JSON.stringify(value, null, 1));
// A topic's messages at `rate` Hz until close(); a stream the server closed (a restart) opens again.
const stream = (name, rate, onMessage) => {
  let ws, closed = false;
  const open = () => {
    ws = new WebSocket(socketUrl(`/topics${name}/stream?rate=${rate}`));
    ws.onmessage = (e) => onMessage(JSON.parse(e.data));
    ws.onclose = () => { if (!closed) setTimeout(open, 2000); };
  };
  open();
  return { close: () => { closed = true; ws.close(); } };
};
// 3-4 significant digits, no exponent for everyday magnitudes
const num = (x, digits = 4) => (typeof x !== "number" ? String(x) : x === 0 ? "0" : Math.abs(x) >= 1e-3 && Math.abs(x) < 1e5 ? String(Number(x.toPrecision(digits))) : x.toExponential(2));
const stampSeconds = (header) => header.stamp.sec + header.stamp.nanosec * 1e-9;

function refusal(data) {
  if (data && Array.isArray(data.detail)) {
    return data.detail.map((e) => `${e.loc.slice(1).join(".") || "request"}: ${e.msg}`).join("; ");
  }
  if (data && data.reason) return data.reason;
  if (data && data.message) return data.message;
  if (data && data.detail) return data.detail;
  return show(data);
}

// --- request forms from pydantic JSON schemas ---------------------------------------------------
const JSON_NUMBER = /^-?(0|[1-9]\d*)(\.\d+)?([eE][+-]?\d+)?$/;
function kindOf(prop) { return prop.type || (prop.anyOf && prop.anyOf[0].type) || "string"; }
function hint(name, prop) {
  const kind = kindOf(prop);
  if (kind === "array") {
    const lo = prop.minItems, hi = prop.maxItems, item = (prop.items && prop.items.type) === "integer" ? "integers" : "numbers";
    const count = lo !== undefined && lo === hi ? `${lo} ${item}` : lo !== undefined && hi !== undefined ? `${lo} to ${hi} ${item}` : item;
    return `${count}, comma-separated`;
  }
  if (kind === "integer") return prop.maximum > 2 ** 53 ? "int64" : "integer";
  if (kind === "number") return prop.minimum !== undefined && prop.maximum !== undefined ? `${prop.minimum} to ${prop.maximum}` : "float64";
  return kind;
}
// The fields of a nested message field ({"x": ..., "y": ...}; [{...}] for an array of them), or null.
function nestedFields(schema, prop) {
  const ref = prop.$ref || (prop.items && prop.items.$ref);
  const def = ref && schema.$defs && schema.$defs[ref.split("/").pop()];
  if (!def) return null;
  const inner = `{${Object.keys(def.properties || {}).map((f) => `"${f}": ...`).join(", ")}}`;
  return prop.$ref ? inner : `[${inner}, ...]`;
}
// A form, one input per field; its body is JSON text built from what was typed, so an int64 such
// as 9223372036854775807 reaches the server exactly (a JS number would round it).
function schemaForm(schema, submitLabel, onSubmit) {
  const props = (schema && schema.properties) || {};
  const inputs = {};
  const form = $("form", { onsubmit: (e) => { e.preventDefault(); onSubmit({ json: collect() }); } });
  for (const [name, prop] of Object.entries(props)) {
    // a nested message (a node's own .srv: app/ros/interface_models.py) is typed as JSON, its fields named
    const nested = nestedFields(schema, prop);
    const kind = nested ? "json" : kindOf(prop);
    const placeholder = nested ? `${nested} (JSON)` : hint(name, prop);
    const input = kind === "boolean" ? $("input", { type: "checkbox", name }) : $("input", { type: "text", name, placeholder });
    if ((kind === "array" && prop.minItems >= 4) || kind === "json") input.classList.add("wide");
    if (prop.default !== undefined && kind !== "boolean") input.value = prop.default;
    inputs[name] = { input, kind };
    form.append($("label", {}, `${name} `, input));
  }
  let open = null;  // a type the lab does not know (a node's own): the fields as one JSON object
  if (!Object.keys(props).length && schema && schema.additionalProperties) {
    open = $("input", { type: "text", name: "json", class: "wide", placeholder: '{"field": value} (JSON)' });
    form.append($("label", {}, "JSON ", open));
  }
  form.append($("button", { type: "submit", text: submitLabel }));
  const literal = (text) => (JSON_NUMBER.test(text) ? text : JSON.stringify(text));  // not a number: sent as text, the server names the field
  function collect() {
    if (open) return open.value.trim() || "{}";
    const parts = [];
    for (const [name, { input, kind }] of Object.entries(inputs)) {
      const v = input.value.trim();
      let value;
      if (kind === "boolean") value = String(input.checked);
      else if (v === "") continue;
      else if (kind === "json") value = v;  // the server names a field that is wrong
      else if (kind === "integer" || kind === "number") value = literal(v);
      else if (kind === "array") value = `[${v.replace(/^\[|\]$/g, "").split(",").map((x) => literal(x.trim())).join(", ")}]`;
      else value = JSON.stringify(v);
      parts.push(`${JSON.stringify(name)}: ${value}`);
    }
    return `{${parts.join(", ")}}`;
  }
  return form;
}

// --- services, parameters, topics, actions ------------------------------------------------------
// the registry's services, kept in step with GET /services every 2 s: a node's service comes and
// goes with its node, and a node that serves a declared name with its own type (its own .srv) shows
// that type's text and form. One update at a time (as the actions'); a shown item is left alone
// (what is typed into it stays) unless its service's type changed.
const shownServices = new Map();  // name -> { item, type }
let servicesUpdate = null;
function renderServices() {
  if (!servicesUpdate) servicesUpdate = updateServices().finally(() => { servicesUpdate = null; });
  return servicesUpdate;
}
async function updateServices() {
  const root = byId("services");
  const list = (await api("GET", "/services")).data;
  if (!Array.isArray(list)) return;
  const types = new Map(list.map((s) => [s.name, s.type]));
  let changed = false;
  for (const [name, shown] of shownServices) {
    if (types.get(name) !== shown.type) { shown.item.remove(); shownServices.delete(name); changed = true; }
  }
  const fresh = list.filter(({ name }) => !shownServices.has(name));
  const infos = await Promise.all(fresh.map(({ name }) => api("GET", `/services${name}`)));
  for (const { status, data: info } of infos) {
    if (status !== 200 || shownServices.has(info.name)) continue;
    shownServices.set(info.name, { item: serviceItem(info), type: info.type });
    changed = true;
  }
  if (!changed) return;
  let cursor = root.firstChild;  // in the registry's order, moving only what is not in its place
  for (const { name } of list) {
    const shown = shownServices.get(name);
    if (!shown) continue;
    if (shown.item !== cursor) root.insertBefore(shown.item, cursor);
    cursor = shown.item.nextSibling;
  }
}
function serviceItem(info) {
  const name = info.name;
  const out = $("pre", { class: "response" });
  const form = schemaForm(info.request_schema, "call", async (body) => {
    const r = await api("POST", `/services${name}`, body);
    out.className = r.status === 200 ? "response ok" : "response refused";
    out.textContent = r.status === 200 ? r.text : `${r.status}: ${refusal(r.data)}`;
  });
  return $("div", { class: "item service", "data-name": name },
    $("h3", {}, name, " ", $("span", { class: "type", text: `[${info.type}]` })),
    $("p", { class: "description", text: info.description }),
    $("pre", { class: "srv", text: info.srv }), form, out);
}

async function renderParams() {
  const root = byId("params");
  const list = (await api("GET", "/params")).data;
  const described = await Promise.all(list.map((p) => api("GET", `/params/${p.node}/${p.name}/describe`)));
  let node = null;
  list.forEach((p, i) => {
    const d = described[i].data || {};
    if (p.node !== node) { node = p.node; root.append($("h3", { text: `/${node}` })); }
    const input = $("input", { type: "text", value: show(p.value) });
    const result = $("span");
    const set = async () => {
      let value = input.value.trim();
      if (p.type === "string") value = String(value);
      else { try { value = JSON.parse(value); } catch { /* a word stays a string: the server says why */ } }
      const r = await api("PUT", `/params/${p.node}/${p.name}`, { value });
      result.className = r.data.successful ? "ok" : "refused";
      result.textContent = r.data.successful ? "Set parameter successful" : `Setting parameter failed: ${r.data.reason}`;
    };
    const range = d.min_value !== undefined ? ` [${d.min_value}, ${d.max_value}]` : d.choices ? ` (${d.choices.join(", ")})` : "";
    root.append($("div", { class: "param", "data-name": `${p.node}/${p.name}` },
      $("span", { title: p.type, text: `${p.name} (${p.type})` }), input,
      $("span", {}, $("button", { text: "set", onclick: set }), " ", result),
      $("span", { class: "description", text: `${d.description || ""}${range}${d.read_only ? " · read-only" : ""}` })));
    if (d.read_only) { input.disabled = true; root.lastChild.querySelector("button").disabled = true; }
  });
}

// Units of message fields by name (SI, as the messages are).
const UNITS = [
  [/wrench\.force|tangential_force|normal_force|f_n_m(in|ax)/, "N"], [/wrench\.torque/, "Nm"],
  [/^linear/, "m/s"], [/^angular/, "rad/s"], [/^position\.\d/, "rad"], [/^velocity\.\d/, "rad/s"],
  [/pose\.position|centre_of_pressure|^slip/, "m"], [/duration/, "s"], [/stamp$/, "s"],
];
function formatMessage(message) {
  const lines = [];
  const walk = (value, path) => {
    if (path === "header") { lines.push(`stamp: ${num(stampSeconds(value), 6)} s${value.frame_id ? `  frame: ${value.frame_id}` : ""}`); return; }
    if (value && typeof value === "object" && !Array.isArray(value)) { for (const [k, v] of Object.entries(value)) walk(v, path ? `${path}.${k}` : k); return; }
    const unit = (UNITS.find(([re]) => re.test(path)) || [null, ""])[1];
    if (Array.isArray(value)) {
      const unitOf = (i) => (UNITS.find(([re]) => re.test(`${path}.${i}`)) || [null, unit])[1];
      lines.push(`${path}: [${value.map((x) => num(x)).join(", ")}]${value.length && typeof value[0] === "number" ? ` ${unitOf(0)}` : ""}`);
      return;
    }
    lines.push(`${path}: ${typeof value === "number" ? num(value) : value === "" ? "''" : value}${typeof value === "number" && unit ? ` ${unit}` : ""}`);
  };
  walk(message, "");
  return lines.join("\n");
}

// Every topic's newest message, streamed only while the tab is shown: a hidden tab's streams cost
// the lab and the browser CPU for nothing on screen (docs/performance.md, "The dashboard").
async function renderTopics() {
  const root = byId("topics");
  const raw = byId("topics-raw");
  const list = (await api("GET", "/topics")).data;
  const follow = [];  // per topic: () => its stream, opened
  for (const { name, type } of list) {
    const out = $("pre", { class: "message" });
    root.append($("div", { class: "item topic", "data-name": name }, $("h3", {}, name, " ", $("span", { class: "type", text: `[${type}]` })), out));
    let last = null;
    const draw = () => { if (last) out.textContent = raw.checked ? show(last) : formatMessage(last); };
    raw.addEventListener("change", draw);
    follow.push(() => stream(name, 2, (m) => { last = m; draw(); }));
  }
  let open = [];
  const shown = () => {
    if (!root.hidden && !open.length) open = follow.map((start) => start());
    if (root.hidden) { open.forEach((s) => s.close()); open = []; }
  };
  document.addEventListener("tab-shown", shown);
  shown();
}

// One block per goal: its own progress bar and log; a refusal goes to its own line, never into
// another goal's output. The goal's stream (WebSocket) sends its feedback and its end; a stream that
// closes before the end (a busy server, a dropped connection) is followed up over HTTP (long-poll
// from the feedback already shown), so no update is lost and none is shown twice.
const GOAL_ENDS = ["succeeded", "aborted", "preempted", "rejected"];
function goalBlock(name, goalId, onResult) {
  const bar = $("progress", { max: "1", value: "0", hidden: "" });
  const label = $("span", { class: "goal-status", text: "pending" });
  const log = $("pre", { class: "feedback" });
  const block = $("div", { class: "goal", "data-goal": goalId }, $("div", {}, `goal ${goalId.slice(0, 8)} `, label, " ", bar), log);
  let seen = 0, ended = false;
  const feedback = (fb) => {
    seen += 1;
    const fraction = "progress" in fb ? fb.progress : "of" in fb && fb.of > 0 ? fb.trial / fb.of : null;
    if (fraction !== null) { bar.hidden = false; bar.value = fraction; bar.title = `${Math.round(fraction * 100)} %`; }
    if (!("progress" in fb)) log.textContent += `feedback: ${Object.entries(fb).map(([k, v]) => `${k}=${typeof v === "number" ? num(v) : v}`).join(" ")}\n`;
  };
  const end = (m) => {
    if (ended) return;
    ended = true;
    label.textContent = m.status;
    label.className = `goal-status ${m.status === "succeeded" ? "ok" : "refused"}`;
    if (m.status === "succeeded") { bar.hidden = false; bar.value = 1; }
    log.textContent += `${m.status}: ${m.message || ""}\n${Object.entries(m.result || {}).map(([k, v]) => (typeof v === "string" && v.includes("\n") ? `${k}:\n${v}` : `${k}: ${JSON.stringify(v)}`)).join("\n")}\n`;
    onResult(m);
  };
  const follow = async () => {
    while (!ended) {
      let r;
      try { r = await api("GET", `/actions${name}/goals/${goalId}?after=${seen}&wait=10`); } catch { await new Promise((ok) => setTimeout(ok, 2000)); continue; }
      if (r.status === 404) { end({ status: "aborted", message: refusal(r.data) }); return; }  // its node took it away
      if (r.status !== 200) { await new Promise((ok) => setTimeout(ok, 2000)); continue; }
      r.data.feedback.forEach(feedback);
      if (GOAL_ENDS.includes(r.data.status)) end(r.data); else label.textContent = r.data.status;
    }
  };
  const ws = new WebSocket(socketUrl(`/actions${name}/goals/${goalId}/stream`));
  label.textContent = "active";
  ws.onmessage = (e) => {
    const m = JSON.parse(e.data);
    if (m.feedback) feedback(m.feedback); else end(m);
  };
  ws.onclose = () => { if (!ended) follow(); };
  return block;
}

// the lab's actions and those nodes provide: kept in step with GET /actions (a node's action comes
// and goes with its node)
const shownActions = new Map();  // name -> its item
// One update at a time: runs that overlapped (the 2 s timer while a slow one still waits) could
// let an older list, fetched before a node advertised its action, remove the newer item (and the
// goal running in it) that a later run had made.
let actionsUpdate = null;
function renderActions() {
  if (!actionsUpdate) actionsUpdate = updateActions().finally(() => { actionsUpdate = null; });
  return actionsUpdate;
}
async function updateActions() {
  const root = byId("actions");
  const list = (await api("GET", "/actions")).data;
  if (!Array.isArray(list)) return;
  const names = new Set(list.map((a) => a.name));
  for (const [name, item] of shownActions) if (!names.has(name) && item) { item.remove(); shownActions.delete(name); }
  for (const { name, type } of list) {
    if (shownActions.has(name)) continue;
    shownActions.set(name, null);
    const info = (await api("GET", `/actions${name}`)).data;
    const goals = $("div", { class: "goals" });
    const refusalLine = $("p", { class: "refusal refused", hidden: "" });
    let goalId = null;
    const cancel = $("button", { text: "cancel", type: "button", onclick: () => goalId && api("POST", `/actions${name}/goals/${goalId}/cancel`) });
    const form = schemaForm(info.goal_schema, "send goal", async (body) => {
      const r = await api("POST", `/actions${name}/goals`, body);
      if (r.status !== 202) { refusalLine.hidden = false; refusalLine.textContent = `${r.status} ${r.data.status || "refused"}: ${refusal(r.data)}`; return; }
      refusalLine.hidden = true;
      goalId = r.data.goal_id;
      goals.prepend(goalBlock(name, goalId, (m) => showActionResult(name, m)));
      while (goals.children.length > 3) goals.lastChild.remove();
    });
    form.append(cancel);
    const item = $("div", { class: "item action", "data-name": name },
      $("h3", {}, name, " ", $("span", { class: "type", text: `[${type}]` })),
      $("p", { class: "description", text: info.description }),
      $("pre", { text: info.definition }), form, refusalLine, goals);
    shownActions.set(name, item);
    root.append(item);
  }
}

// --- results ----------------------------------------------------------------------------------
function showActionResult(name, m) {
  if (!m.result || !("table" in m.result)) return;
  const ok = name === "/compare_controllers"
    ? m.result.controllers.map((c, i) => `${c} ${m.result.successes[i]}/${m.result.trials[i]}`).join(", ")
    : `${m.result.successes}/${m.result.trials} succeeded`;
  const box = $("div", { class: `result ${m.status === "succeeded" ? "" : "refused"}`, "data-action": name },
    $("b", { text: `${name} ${m.status}: ` }), ok, $("pre", { class: "table", text: m.result.table }));
  if (m.result.figures && m.result.figures.length) box.append(figureStrip(m.result.figures));
  byId("action-results").prepend(box);
  while (byId("action-results").children.length > 2) byId("action-results").lastChild.remove();
}

// The goal's figures (PNG URLs, the summary first) as thumbnails; a click opens the figure full
// size, as SVG (saved next to each PNG).
function figureStrip(urls) {
  const strip = $("div", { class: "figures" });
  for (const png of urls) {
    const name = png.split("/").pop().replace(/\.png$/, "");
    strip.append($("a", { href: here(png.replace(/\.png$/, ".svg")), target: "_blank", rel: "noopener", title: `${name} (full size)` },
      $("img", { src: here(png), alt: name })));
  }
  return strip;
}

function showTrial(t) {
  const el = byId("trial-result");
  const shown = JSON.stringify(t);
  if (el.dataset.shown === shown) return;  // the same result again (4 a second): nothing to draw
  el.dataset.shown = shown;
  if (t.state === "none") { el.className = "result"; el.textContent = "No trial yet: start lifting while the person holds the box, or run a scripted participant."; return; }
  const figures = `time ${t.duration.toFixed(2)} s · f_n ${t.f_n_min.toFixed(2)}..${t.f_n_max.toFixed(2)} N · max |f_t|/(mu f_n) ${t.max_friction_ratio.toFixed(2)} · slip ${(t.slip * 1000).toFixed(1)} mm`;
  const head = { running: "trial running", succeeded: "SUCCESS", failed: "FAILED", abandoned: "no result" }[t.state] || t.state;
  el.className = `result trial-${t.state}`;
  el.dataset.state = t.state;
  el.textContent = "";
  el.append($("b", { text: `${head}` }), ` (${t.participant}) · ${figures}`);
  if (t.reason) el.append($("div", { class: "reason", text: t.reason }));
}

// --- status ---------------------------------------------------------------------------------
const state = { lifting: null, contact: null, controller: "…", alpha: 0.5 };
// the person's hold on the box: while they grasp it (before the lift) the grasp holds it, whatever
// the palm's contact points do; after they let go, the palm holds it by friction alone
function personContact(l, c) {
  if (!c.human_contact) return "no";
  if (l && l.human_phase === "grasping") return "holds it (grasp)";
  return c.human_slipping ? "palm slipping" : "palm holds";
}
function renderStatus() {
  const l = state.lifting, c = state.contact;
  if (l) {
    const on = byId("st-lifting");
    setText(on, l.started ? `ON, band [${num(l.f_n_min)}, ${num(l.f_n_max)}] N` : "off");
    setClass(on, l.started ? "on" : "off");
    setText(byId("st-person"), l.human_phase);
    const error = byId("st-error");
    error.hidden = !l.error;
    if (l.error) {
      const [first, ...rest] = l.error.split("\n");
      setText(byId("st-error-reason"), first);
      byId("st-error-trace").hidden = rest.length === 0;
      setText(byId("st-error-trace"), rest.join("\n"));
    }
  }
  if (c) {
    const fn = byId("st-fn");
    const where = !l || !l.started ? "" : c.normal_force < l.f_n_min ? "below the band" : c.normal_force > l.f_n_max ? "above the band" : "in the band";
    setText(fn, `${c.normal_force.toFixed(1)} N${where ? ` (${where})` : ""}`);
    setClass(fn, where === "in the band" ? "on" : where ? "warn" : "");
    setText(byId("st-contact"), `robot ${c.robot_contact ? (c.robot_slipping ? "slipping" : "yes") : "no"}, person ${personContact(l, c)}, |f_t|/(mu f_n) ${c.friction_ratio.toFixed(2)}`);
  }
  setText(byId("st-controller"), state.controller);
}

async function pollSlow() {
  try {
    const h = (await api("GET", "/health")).data;
    setText(byId("health"), h.loop_alive ? `simulation ${h.rate_hz.toFixed(0)} Hz, t = ${h.sim_time.toFixed(1)} s` : "simulation stopped");
    const [controller, alpha] = await Promise.all([api("GET", "/params/cooperative_lifting/controller"), api("GET", "/params/cooperative_lifting/alpha")]);
    state.controller = controller.data.value;
    state.alpha = alpha.data.value;
    renderStatus();
  } catch { byId("health").textContent = "server unreachable"; }
}

async function command(path, body) {
  const r = await api("POST", path, body);
  const msg = byId("ctl-message");
  msg.className = r.status === 200 ? "ok" : "refused";
  msg.textContent = r.status === 200 ? `${path.split("/").pop()}: ${r.data.message ?? show(r.data)}` : `${path.split("/").pop()}: ${refusal(r.data)}`;
  return r;
}

function bindControls() {
  const force = () => ({ json: `{"force": ${JSON_NUMBER.test(byId("ctl-force").value.trim()) ? byId("ctl-force").value.trim() : JSON.stringify(byId("ctl-force").value)}}` });
  byId("ctl-start").onclick = () => command("/services/start_cooperative_lifting", force());
  byId("ctl-stop").onclick = () => command("/services/stop_cooperative_lifting");
  byId("ctl-reset").onclick = () => command("/services/reset_simulation");
  byId("ctl-recover").onclick = () => command("/services/error_recovery");
  byId("ctl-participant-run").onclick = async () => {
    const r = await api("PUT", "/params/human/profile", { value: byId("ctl-participant").value });
    if (!r.data.successful) { byId("ctl-message").textContent = r.data.reason; return; }
    if ((await command("/services/reset_simulation")).status === 200) await command("/services/start_cooperative_lifting", force());
  };
  api("GET", "/params/human/profile/describe").then(({ data }) => {
    for (const choice of data.choices || []) byId("ctl-participant").append($("option", { text: choice, value: choice }));
    api("GET", "/params/human/profile").then((r) => { byId("ctl-participant").value = r.data.value; });
  });
  // teleop: buttons and keys (w/s/a/d/q) while the pad has the focus
  const jog = async (key) => {
    const r = await api("POST", "/teleop/key", { key });
    byId("teleop-out").className = r.data.successful ? "ok" : "refused";
    byId("teleop-out").textContent = r.data.successful ? `${key}: twist ${r.data.twist.map((x) => num(x, 3)).join(", ")}` : `${key}: ${refusal(r.data)}`;
  };
  for (const b of document.querySelectorAll("#teleop-pad button")) b.onclick = () => jog(b.dataset.key);
  byId("teleop-pad").addEventListener("keydown", (e) => { if ("wsadq".includes(e.key) && e.key.length === 1) { e.preventDefault(); jog(e.key); } });
}

// --- live plots (uPlot) -------------------------------------------------------------------------
const WINDOW_S = 30, RATE_HZ = 20;
const plots = { paused: false, charts: [], buffers: {} };
function makeChart(id, title, series, scales, axes, columns) {
  const el = byId(id);
  const chart = new uPlot({
    title, width: el.clientWidth || 600, height: 170, series: [{ label: "t (s)", value: (u, v) => (v == null ? "--" : v.toFixed(2)) }, ...series],
    scales: { x: { time: false }, ...scales }, axes, legend: { live: true },
  }, columns.map(() => []), el);
  const buffer = columns.map(() => []);
  plots.charts.push({ chart, buffer });
  return buffer;
}
// the twist plot's two axes share their zero line (each symmetric about 0): |w| on the right is
// drawn above it, never read as a negative speed on the left
const symmetric = (u, min, max) => { const m = Math.max(Math.abs(min ?? 0), Math.abs(max ?? 0), 1e-3); return [-m, m]; };
const TWIST_SCALES = { y: { range: symmetric }, w: { range: symmetric } };
function buildPlots() {
  const value = (digits) => (u, v) => (v == null ? "--" : v.toFixed(digits));
  const contact = makeChart("plot-contact", "Contact: f_n with the band, friction ratio with its cone margin", [
    { label: "f_n (N)", stroke: "#d62728", width: 2, scale: "N", value: value(2) },
    { label: "f_n_min (N)", stroke: "#888", dash: [5, 5], scale: "N", value: value(1) },
    { label: "f_n_max (N)", stroke: "#888", dash: [5, 5], scale: "N", value: value(1) },
    { label: "|f_t|/(mu f_n)", stroke: "#9467bd", width: 2, scale: "ratio", value: value(2) },
    { label: "margin alpha", stroke: "#9467bd", dash: [3, 3], scale: "ratio", value: value(2) },
  ], { N: { auto: true }, ratio: { range: [0, 1.5] } }, [{}, { scale: "N", label: "force (N)" }, { scale: "ratio", side: 1, label: "|f_t| / (mu f_n)", grid: { show: false } }], [0, 1, 2, 3, 4, 5]);
  const wrench = makeChart("plot-wrench", "F_ext (EE frame, as measured)", [
    { label: "f_x (N)", stroke: "#1f77b4", value: value(2) }, { label: "f_y (N)", stroke: "#2ca02c", value: value(2) },
    { label: "f_z (N)", stroke: "#d62728", value: value(2) },
  ], {}, [{}, { label: "force (N)" }], [0, 1, 2, 3]);
  const twist = makeChart("plot-twist", "Commanded twist (base frame)", [
    { label: "v_x (m/s)", stroke: "#1f77b4", value: value(3) }, { label: "v_y (m/s)", stroke: "#2ca02c", value: value(3) },
    { label: "v_z (m/s)", stroke: "#d62728", value: value(3) }, { label: "|w| (rad/s)", stroke: "#ff7f0e", scale: "w", value: value(3) },
  ], TWIST_SCALES, [{}, { label: "v (m/s)" }, {
    scale: "w", side: 1, label: "|w| (rad/s), right axis", stroke: "#ff7f0e", grid: { show: false },
    values: (u, splits) => splits.map((v) => (v < 0 ? "" : v.toFixed(2))),  // |w| is never negative: no ticks below 0
  }], [0, 1, 2, 3, 4]);
  const latest = { lifting: null, wrench: null, twist: null };
  stream("/lifting_state", 10, (m) => { latest.lifting = m; state.lifting = m; });  // shown with the plots' next drawing
  stream("/franka_state_controller/F_ext", RATE_HZ, (m) => { latest.wrench = m; });
  stream("/cartesian_velocity_controller/command", RATE_HZ, (m) => { latest.twist = m; });
  stream("/trial", 4, showTrial);
  stream("/contact_state", RATE_HZ, (m) => {  // one sample per contact message, with the newest of the others
    state.contact = m;
    const t = stampSeconds(m.header);
    const l = latest.lifting || { f_n_min: 0, f_n_max: 0, started: false };
    const push = (buffer, row) => {
      if (buffer[0].length && t < buffer[0][buffer[0].length - 1]) buffer.forEach((col) => col.splice(0));  // reset: time went back
      row.forEach((v, i) => buffer[i].push(v));
      while (buffer[0].length && buffer[0][0] < t - WINDOW_S) buffer.forEach((col) => col.shift());
    };
    push(contact, [t, m.normal_force, l.started ? l.f_n_min : null, l.started ? l.f_n_max : null, m.friction_ratio, state.alpha]);
    if (latest.wrench) { const f = latest.wrench.wrench.force; push(wrench, [t, f.x, f.y, f.z]); }
    if (latest.twist) { const v = latest.twist.linear, w = latest.twist.angular; push(twist, [t, v.x, v.y, v.z, Math.hypot(w.x, w.y, w.z)]); }
  });
  byId("plot-pause").onclick = () => { plots.paused = !plots.paused; byId("plot-pause").textContent = plots.paused ? "Resume" : "Pause"; };
  // One drawing every 200 ms holds the status line and the plots: each change of the page is a frame
  // the browser paints (in software where there is no GPU), and the status redrawn with every message
  // too (10 a second) made up to three frames of one (docs/performance.md, "The dashboard").
  const draw = () => {
    renderStatus();
    if (!plots.paused) {
      for (const { chart, buffer } of plots.charts) {
        chart.setData(buffer.map((col) => col.slice()));
        if (chart.cursor.left == null || chart.cursor.left < 0) chart.setLegend({ idx: buffer[0].length - 1 });  // legend: the newest values
      }
    }
    setTimeout(draw, 200);
  };
  draw();
  window.addEventListener("resize", () => { for (const { chart } of plots.charts) chart.setSize({ width: chart.root.parentElement.clientWidth, height: 170 }); });
}

// --- the 3D view ----------------------------------------------------------------------------------
// Where WebGL is software-rendered (SwiftShader, llvmpipe), the view would take the page's main
// thread: it is then not embedded by default (a button embeds it, a link opens it in a window).
function softwareWebGL() {
  try {
    const gl = document.createElement("canvas").getContext("webgl");
    if (!gl) return "no WebGL";
    const info = gl.getExtension("WEBGL_debug_renderer_info");
    const renderer = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    return /swiftshader|llvmpipe|software|softpipe/i.test(renderer) ? renderer : null;
  } catch { return "no WebGL"; }
}
async function renderView() {
  const info = (await api("GET", "/view")).data;
  const frame = byId("view"), off = byId("view-off");
  if (!info.url) { off.hidden = false; byId("view-off-reason").textContent = "The 3D view is off (server started with --view none)."; byId("view-embed").hidden = true; byId("view-window").hidden = true; return; }
  // The view on the other name of this machine (127.0.0.1 <-> localhost): another site, so the
  // browser gives it a process of its own (site isolation) and its rendering never blocks this page.
  // Behind a JupyterHub the view comes through this page's own server (info.relay: only its port is proxied).
  const url = new URL(info.relay ? here(info.relay) : info.url);
  const loopback = { "127.0.0.1": "localhost", localhost: "127.0.0.1" };
  if (!info.relay && url.hostname === location.hostname && loopback[url.hostname]) url.hostname = loopback[url.hostname];
  byId("view-window").href = url;
  const embed = () => { off.hidden = true; frame.hidden = false; frame.src = url; };
  byId("view-embed").onclick = embed;
  const software = new URLSearchParams(location.search).get("view") === "embed" ? null : softwareWebGL();
  if (software) {
    off.hidden = false;
    byId("view-off-reason").textContent = `WebGL is software-rendered here (${software}): the 3D view is not embedded, so this page stays responsive.`;
  } else embed();
}

// --- console: /rosout (GET /log, polled), filtered by node and level ------------------------------
const LOG_ORDER = ["DEBUG", "INFO", "WARN", "ERROR", "FATAL"];
const CONSOLE_MAX = 500;  // lines kept on the page
function renderConsole() {
  const lines = [];  // {stamp, level, node, msg}
  const nodes = new Set();
  const body = byId("console-lines").querySelector("tbody");
  const nodeSelect = byId("console-node"), levelSelect = byId("console-level");
  const visible = (line) => (!nodeSelect.value || line.node === nodeSelect.value)
    && LOG_ORDER.indexOf(line.level) >= LOG_ORDER.indexOf(levelSelect.value);
  const row = (line) => $("tr", { class: `log-${line.level.toLowerCase()}` },
    $("td", { text: new Date(line.stamp * 1000).toLocaleTimeString() }), $("td", { text: line.level }),
    $("td", { text: line.node }), $("td", { text: line.msg }));
  const redraw = () => body.replaceChildren(...lines.filter(visible).map(row));
  const add = (line) => {
    lines.push(line);
    if (lines.length > CONSOLE_MAX) lines.shift();
    if (!nodes.has(line.node)) { nodes.add(line.node); nodeSelect.append($("option", { text: line.node, value: line.node })); }
    if (visible(line)) {
      body.append(row(line));
      while (body.children.length > CONSOLE_MAX) body.firstChild.remove();
    }
  };
  nodeSelect.onchange = levelSelect.onchange = redraw;
  byId("console-clear").onclick = () => { lines.length = 0; redraw(); };
  let seen = 0;  // the newest line's seq: the console asks for what came after it
  let polling = false;
  const poll = async () => {
    if (polling) return;  // one request at a time: a slow answer never doubles the lines
    polling = true;
    try {
      const { data } = await api("GET", `/log?after_seq=${seen}`);
      if (Array.isArray(data)) for (const line of data) if (line.seq > seen) { add(line); seen = line.seq; }
    } finally { polling = false; }
  };
  poll();
  setInterval(poll, 1000);
}

// the camera (GET /camera/image.jpg while "live" is on: the lab renders while it is asked) and
// the windows programs open with cv2.imshow (GET /camera/windows), each a figure with its newest image
function refreshing(img, url, pause, keepGoing) {
  const next = () => { if (keepGoing()) img.src = here(`${url()}${url().includes("?") ? "&" : "?"}t=${Date.now()}`); };
  img.onload = () => setTimeout(next, pause);
  img.onerror = () => setTimeout(next, 1000);
  next();
}

function renderCamera() {
  const live = byId("camera-live"), figure = byId("camera-figure"), img = byId("camera-image");
  live.addEventListener("change", () => {
    figure.hidden = !live.checked;
    if (live.checked) refreshing(img, () => "/camera/image.jpg?quality=80", 30, () => live.checked);
  });
  const shown = new Map();  // window id -> figure
  const poll = async () => {
    const { data } = await api("GET", "/camera/windows");
    if (!Array.isArray(data)) return;
    const ids = new Set(data.map((w) => w.id));
    for (const [id, fig] of shown) if (!ids.has(id)) { fig.remove(); shown.delete(id); }
    for (const w of data) {
      if (shown.has(w.id)) continue;
      const img = $("img", { alt: `window ${w.name}`, width: 320, height: 240, "data-window": w.name });
      const fig = $("figure", { class: "window" }, img, $("figcaption", { text: `cv2.imshow: ${w.name}` }));
      byId("camera-images").append(fig);
      shown.set(w.id, fig);
      refreshing(img, () => `/camera/windows/${encodeURIComponent(w.id)}.jpg`, 60, () => shown.get(w.id) === fig);
    }
  };
  poll();
  setInterval(poll, 1000);
}

for (const button of document.querySelectorAll("nav button")) {
  button.addEventListener("click", () => {
    for (const b of document.querySelectorAll("nav button")) b.classList.toggle("active", b === button);
    for (const tab of document.querySelectorAll(".tab")) tab.hidden = tab.id !== button.dataset.tab;
    document.dispatchEvent(new Event("tab-shown"));
  });
}
renderView();
bindControls();
buildPlots();
renderServices();
renderParams();
renderTopics();
renderActions();
renderConsole();
renderCamera();
pollSlow();
setInterval(pollSlow, 2000);
setInterval(renderActions, 2000);
setInterval(renderServices, 2000);
