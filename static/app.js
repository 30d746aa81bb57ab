// The dashboard page: everything on it is generated from the API (services, parameters, topics,
// actions), so a service added to the registry appears here with no page change.
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
const api = async (method, path, body, raw) => {
  const init = { method, headers: {} };
  if (body !== undefined) {
    init.body = raw ? body : JSON.stringify(body);
    init.headers["content-type"] = raw ? "application/yaml" : "application/json";
  }
  const response = await fetch(path, init);
  const text = await response.text();
  let data;
  try { data = JSON.parse(text); } catch { data = text; }
  return { status: response.status, data };
};
const show = (value) => (typeof value === "string" ? value : JSON.stringify(value, null, 1));
// An action result field by field; a text of several lines (a table) as it is.
const showResult = (result) => Object.entries(result || {})
  .map(([k, v]) => (typeof v === "string" && v.includes("\n") ? `${k}:\n${v}` : `${k}: ${JSON.stringify(v)}`)).join("\n");

// A request form from a pydantic JSON schema: one input per field, typed from the schema.
function schemaForm(schema, submitLabel, onSubmit) {
  const props = (schema && schema.properties) || {};
  const inputs = {};
  const form = $("form", { onsubmit: (e) => { e.preventDefault(); onSubmit(collect()); } });
  for (const [name, prop] of Object.entries(props)) {
    const kind = prop.type || (prop.anyOf && prop.anyOf[0].type) || "string";
    const input = kind === "boolean" ? $("input", { type: "checkbox", name }) : $("input", { type: "text", name, placeholder: kind === "array" ? "1, 2, 3" : kind });
    if (prop.default !== undefined && kind !== "boolean") input.value = prop.default;
    inputs[name] = { input, kind };
    form.append($("label", {}, `${name} `, input));
  }
  form.append($("button", { type: "submit", text: submitLabel }));
  function collect() {
    const body = {};
    for (const [name, { input, kind }] of Object.entries(inputs)) {
      const v = input.value.trim();
      if (kind === "boolean") body[name] = input.checked;
      else if (v === "") continue;
      else if (kind === "integer" || kind === "number") body[name] = Number(v);
      else if (kind === "array") body[name] = v.split(",").map((x) => Number(x.trim()));
      else body[name] = v;
    }
    return body;
  }
  return form;
}

function refusal(data) {
  if (data && Array.isArray(data.detail)) {
    return data.detail.map((e) => `${e.loc.slice(1).join(".") || "request"}: ${e.msg}`).join("; ");
  }
  if (data && data.reason) return data.reason;
  if (data && data.detail) return data.detail;
  return show(data);
}

async function renderServices() {
  const root = document.getElementById("services");
  const list = (await api("GET", "/services")).data;
  for (const { name } of list) {
    const info = (await api("GET", `/services${name}`)).data;
    const out = $("pre", { class: "response" });
    const form = schemaForm(info.request_schema, "call", async (body) => {
      const r = await api("POST", `/services${name}`, body);
      out.className = r.status === 200 ? "response ok" : "response refused";
      out.textContent = r.status === 200 ? show(r.data) : `${r.status}: ${refusal(r.data)}`;
    });
    root.append($("div", { class: "item service", "data-name": name },
      $("h3", {}, name, " ", $("span", { class: "type", text: `[${info.type}]` })),
      $("pre", { class: "srv", text: info.srv }), form, out));
  }
}

async function renderParams() {
  const root = document.getElementById("params");
  const list = (await api("GET", "/params")).data;
  let node = null;
  for (const p of list) {
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
    root.append($("div", { class: "param", "data-name": `${p.node}/${p.name}` },
      $("span", { title: p.type, text: `${p.name} (${p.type})` }), input,
      $("span", {}, $("button", { text: "set", onclick: set }), " ", result)));
  }
}

async function renderTopics() {
  const root = document.getElementById("topics");
  const list = (await api("GET", "/topics")).data;
  for (const { name, type } of list) {
    const out = $("pre", { class: "message" });
    root.append($("div", { class: "item topic", "data-name": name }, $("h3", {}, name, " ", $("span", { class: "type", text: `[${type}]` })), out));
    const ws = new WebSocket(`${location.origin.replace("http", "ws")}/topics${name}/stream?rate=2`);
    ws.onmessage = (e) => { out.textContent = show(JSON.parse(e.data)); };
  }
}

async function renderActions() {
  const root = document.getElementById("actions");
  const list = (await api("GET", "/actions")).data;
  for (const { name, type } of list) {
    const info = (await api("GET", `/actions${name}`)).data;
    const out = $("pre", { class: "feedback" });
    let goalId = null;
    const cancel = $("button", { text: "cancel", onclick: () => goalId && api("POST", `/actions${name}/goals/${goalId}/cancel`) });
    const form = schemaForm(info.goal_schema, "send goal", async (body) => {
      const r = await api("POST", `/actions${name}/goals`, body);
      if (r.status !== 202) { out.className = "feedback refused"; out.textContent = `${r.status}: ${r.data.message || refusal(r.data)}`; return; }
      goalId = r.data.goal_id;
      out.className = "feedback";
      out.textContent = `goal ${goalId}: ${r.data.status}\n`;
      const ws = new WebSocket(`${location.origin.replace("http", "ws")}/actions${name}/goals/${goalId}/stream`);
      ws.onmessage = (e) => {
        const m = JSON.parse(e.data);
        out.textContent += m.feedback ? `feedback: ${JSON.stringify(m.feedback)}\n` : `${m.status}: ${m.message || ""}\n${showResult(m.result)}\n`;
      };
    });
    root.append($("div", { class: "item action", "data-name": name },
      $("h3", {}, name, " ", $("span", { class: "type", text: `[${type}]` })),
      $("pre", { text: info.definition }), form, cancel, out));
  }
}

async function renderView() {
  const info = (await api("GET", "/view")).data;
  if (!info.url) { document.getElementById("view").hidden = true; document.getElementById("view-missing").hidden = false; return; }
  document.getElementById("view").src = info.url;
}

async function renderHealth() {
  const h = (await api("GET", "/health")).data;
  document.getElementById("health").textContent = h.loop_alive ? `simulation ${h.rate_hz.toFixed(0)} Hz, t = ${h.sim_time.toFixed(1)} s` : "simulation stopped";
}

for (const button of document.querySelectorAll("nav button")) {
  button.addEventListener("click", () => {
    for (const b of document.querySelectorAll("nav button")) b.classList.toggle("active", b === button);
    for (const tab of document.querySelectorAll(".tab")) tab.hidden = tab.id !== button.dataset.tab;
  });
}
renderView();
renderServices();
renderParams();
renderTopics();
renderActions();
renderHealth();
setInterval(renderHealth, 2000);
