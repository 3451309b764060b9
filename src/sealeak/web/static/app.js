// sealeak web app: the four pages. Plain JavaScript, no build step; Plotly.js draws the plots.
"use strict";

const $ = (sel, el = document) => el.querySelector(sel);
const $$ = (sel, el = document) => Array.from(el.querySelectorAll(sel));

class ApiError extends Error {
  constructor(status, body) {
    super(body && body.error ? body.error : `request failed (${status})`);
    this.status = status;
    this.field = body && body.field ? body.field : "";
  }
}

async function api(method, url, body) {
  const opts = { method, headers: {} };
  if (body instanceof FormData) opts.body = body;
  else if (body !== undefined) { opts.body = JSON.stringify(body); opts.headers["Content-Type"] = "application/json"; }
  const r = await fetch(url, opts);
  const type = r.headers.get("Content-Type") || "";
  const data = type.includes("json") ? await r.json() : await r.text();
  if (!r.ok) throw new ApiError(r.status, data);
  return data;
}

function showMessage(text, kind = "bad") {
  const m = $("#message");
  if (!m) return;
  m.className = `banner ${kind}`;
  m.textContent = text || "";
}

function esc(s) {
  return String(s).replace(/[&<>"']/g, c => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" }[c]));
}

function fmt(x, digits = 4) {
  if (x === null || x === undefined || x === "") return "—";
  if (typeof x === "boolean") return x ? "yes" : "no";
  if (typeof x !== "number") return String(x);
  if (x === 0) return "0";
  const a = Math.abs(x);
  return (a >= 1e-3 && a < 1e5) ? String(Number(x.toPrecision(digits))) : x.toExponential(digits - 1);
}

function markNav() {
  const page = document.body.dataset.page;
  $$("header nav a").forEach(a => a.classList.toggle("active", a.getAttribute("href") === `/${page}`));
}

function setCaseName(state) {
  const el = $("#case-name");
  if (el) el.textContent = state && state.toml ? `case: ${state.name}` : "no case yet";
  const up = $("#uploads");
  if (up && state && state.uploads) up.textContent = state.uploads.length ? state.uploads.join(", ") : "none";
}

// ---------------------------------------------------------------- the case form (Case and Prediction pages)
const Form = {
  schema: null, fields: {}, extra: {}, timer: null, onResult: null, predict: false,

  async init(predict, onResult) {
    this.predict = predict;
    this.onResult = onResult;
    const form = await api("GET", "/api/form");
    this.schema = form.sections;
    this.examples = form.examples;
    const state = await api("GET", `/api/case?predict=${predict ? 1 : 0}`);
    this.render(state);
    this.apply(state);
    return state;
  },

  hint(f) {
    if (f.kind === "quantity") return `${f.dimension}${f.example ? `, e.g. ${f.example}` : ""}`;
    if (f.kind === "choice") return `one of: ${f.choices.join(", ")}`;
    if (f.kind === "bool") return "true or false";
    if (f.kind === "file") return "name of a file uploaded on the Surface page";
    if (f.kind === "files") return 'uploaded file names, e.g. ["a.txt", "b.txt"]';
    if (f.kind === "integer") return `a whole number${f.example ? `, e.g. ${f.example}` : ""}`;
    if (f.kind === "number") return `a number${f.example ? `, e.g. ${f.example}` : ""}`;
    if (f.kind === "list") return `a list${f.example ? `, e.g. ${f.example}` : ""}`;
    return f.example ? `e.g. ${f.example}` : "text";
  },

  render(state) {
    const form = $("#case-form");
    form.innerHTML = "";
    const fields = state.fields || {};
    const known = new Set();
    for (const sec of this.schema) {
      const det = document.createElement("details");
      det.className = "section";
      det.dataset.section = sec.section || "top";
      const given = sec.fields.filter(f => fields[f.name] !== undefined).length;
      det.open = given > 0 && (!this.predict || ["conditions", "surface", "theory", "fluid"].includes(sec.section));
      const sum = document.createElement("summary");
      sum.innerHTML = `${sec.section ? `[${sec.section}]` : "title and description"} <span class="count">${given ? `${given} set` : "not used"}</span>`;
      det.appendChild(sum);
      for (const f of sec.fields) {
        known.add(f.name);
        det.appendChild(this.field(f, fields[f.name]));
      }
      form.appendChild(det);
    }
    const extra = Object.keys(fields).filter(k => !known.has(k));
    if (extra.length) {
      const det = document.createElement("details");
      det.className = "section"; det.open = true; det.dataset.section = "other";
      det.innerHTML = "<summary>keys that are not case-file keys <span class=\"count\">clear them to remove them</span></summary>";
      for (const name of extra) det.appendChild(this.field({ name, key: name, kind: "text", choices: [], example: "" }, fields[name]));
      form.appendChild(det);
    }
    this.surfaceModel();
    form.oninput = () => this.changed();
    form.onchange = ev => { if (ev.target.name === "surface.model") this.surfaceModel(); this.changed(); };
  },

  // the [surface] keys of the other models are hidden while empty (each model reads its own keys)
  surfaceModel() {
    const model = ($('#case-form [name="surface.model"]') || {}).value || "";
    for (const sec of this.schema) for (const f of sec.fields) {
      if (!f.models || !f.models.length) continue;
      const box = $(`#case-form [data-field="${CSS.escape(f.name)}"]`);
      const empty = !$("input, select", box).value;
      box.classList.toggle("other-model", empty && !!model && !f.models.includes(model));
    }
  },

  field(f, value) {
    const div = document.createElement("div");
    div.className = "field";
    div.dataset.field = f.name;
    const id = `f-${f.name.replace(/\./g, "-")}`;
    const label = document.createElement("label");
    label.htmlFor = id;
    label.textContent = f.key;
    label.title = f.name;
    div.appendChild(label);
    let input;
    if (f.kind === "choice" || f.kind === "bool") {
      input = document.createElement("select");
      const choices = f.kind === "bool" ? ["true", "false"] : f.choices;
      for (const c of ["", ...choices]) {
        const o = document.createElement("option");
        o.value = c; o.textContent = c === "" ? "(default)" : c;
        input.appendChild(o);
      }
      if (value !== undefined && !choices.includes(value)) {  // a value the list lacks: kept, so that it is checked
        const o = document.createElement("option"); o.value = value; o.textContent = value; input.appendChild(o);
      }
    } else {
      input = document.createElement("input");
      input.type = "text";
      input.placeholder = f.example || "";
    }
    input.id = id;
    input.name = f.name;
    input.value = value === undefined ? "" : value;
    div.appendChild(input);
    const hint = document.createElement("div");
    hint.className = "hint";
    hint.textContent = this.hint(f);
    div.appendChild(hint);
    const err = document.createElement("div");
    err.className = "err";
    div.appendChild(err);
    return div;
  },

  values() {
    const out = {};
    for (const el of $$("#case-form [name]")) if (el.value.trim() !== "") out[el.name] = el.value;
    return out;
  },

  changed() {
    clearTimeout(this.timer);
    const status = $("#status");
    if (status) status.textContent = "checking…";
    this.timer = setTimeout(() => this.submit(), 350);
  },

  async submit() {
    const seq = (this.seq = (this.seq || 0) + 1);
    try {
      const state = await api("PUT", "/api/case/fields", { fields: this.values(), predict: this.predict });
      if (seq === this.seq) this.apply(state);
    } catch (e) {
      if (seq === this.seq) showMessage(e.message);
    }
  },

  apply(state) {
    setCaseName(state);
    $$("#case-form .err").forEach(e => { e.textContent = ""; });
    $$("#case-form .invalid").forEach(e => e.classList.remove("invalid"));
    const status = $("#status");
    if (!state.toml) {
      if (status) status.textContent = "no case yet: choose an example or upload a case file";
      showMessage("");
      return;
    }
    if (state.error) {
      const box = state.error.field ? $(`#case-form [data-field="${CSS.escape(state.error.field)}"]`) : null;
      if (box) {
        $(".err", box).textContent = state.error.message;
        $("input, select", box).classList.add("invalid");
        const det = box.closest("details"); if (det) det.open = true;
        showMessage("");
      } else {
        showMessage(state.error.message);
      }
      if (status) status.textContent = "the case has an error (below)";
    } else {
      showMessage("");
      if (status) status.textContent = state.valid ? "the case is valid" : "";
    }
    if (this.onResult) this.onResult(state);
  },
};

// ---------------------------------------------------------------- Case page
async function pageCase() {
  // the controls answer from the start; the form and the list of examples arrive with Form.init
  const sel = $("#example");
  $("#load-example").addEventListener("click", async () => {
    try {
      const state = await api("POST", "/api/case/example", { name: sel.value });
      Form.render(state); Form.apply(state);
    } catch (e) { showMessage(e.message); }
  });
  $("#data-files").addEventListener("change", async ev => {
    if (!ev.target.files.length) return;
    const body = new FormData();
    for (const f of ev.target.files) body.append("files", f);
    try {
      await api("POST", "/api/uploads", body);
      Form.apply(await api("GET", "/api/case"));  // checked again: the case may name what just arrived
    } catch (e) { showMessage(e.message); }
  });
  $("#case-file").addEventListener("change", async ev => {
    const file = ev.target.files[0];
    if (!file) return;
    const body = new FormData();
    body.append("file", file);
    try {
      const state = await api("POST", "/api/case/upload", body);
      if (!Form.schema) await Form.ready;
      Form.render(state); Form.apply(state);
    } catch (e) { showMessage(e.message); }
  });
  Form.ready = Form.init(false, null);
  await Form.ready;
  for (const ex of Form.examples) {
    const o = document.createElement("option");
    o.value = ex.name; o.textContent = `${ex.name} — ${ex.description}`;
    sel.appendChild(o);
  }
}

// ---------------------------------------------------------------- Prediction page
const LAYOUT = {
  margin: { l: 70, r: 20, t: 40, b: 95 }, font: { size: 12 }, hovermode: "x",
  legend: { orientation: "h", x: 0, y: -0.32, yanchor: "top" }, paper_bgcolor: "#fff", plot_bgcolor: "#fff",
};
const CONFIG = { responsive: true, displaylogo: false, toImageButtonOptions: { format: "png", scale: 2 } };

function axis(title, log) {
  return { title: { text: title }, type: log ? "log" : "linear", exponentformat: "power", gridcolor: "#e6e9ef", zeroline: false };
}

// a log axis over the top ``decades`` of the data (a leak rate or a gap that vanishes would stretch it over 40 decades)
function topDecades(traces, decades) {
  let max = 0;
  for (const t of traces) for (const v of t.y) if (v > max) max = v;
  return max > 0 ? [Math.log10(max) - decades, Math.log10(max) + 0.3] : undefined;
}

function plot(id, traces, title, x, y) {
  const el = document.getElementById(id);
  if (!el || typeof Plotly === "undefined") return;
  Plotly.react(el, traces, { ...LAYOUT, title: { text: title, font: { size: 14 } }, xaxis: x, yaxis: y }, CONFIG);
}

function line(x, y, name, extra = {}) {
  // hover: both values to 4 significant digits (tiny ones such as leak rates in m³/s with an exponent)
  return { x, y, name, type: "scatter", mode: "lines", hovertemplate: "%{x:.4~g}, %{y:.4~e}<extra>%{fullData.name}</extra>", ...extra };
}

function drawPrediction(pred) {
  const doc = pred.json;
  const rows = doc.results;
  const first = rows[0] || {};
  const lr = $("#leak-rate");
  // a gas: the pV throughput in mbar·l/s (the leak-test unit) and in Pa·m³/s; a liquid: m³/s and ml/min
  const gas = first.leak_rate_mbar_l_s !== undefined;
  const shown = gas ? first.leak_rate_mbar_l_s : first.leak_rate;
  const si = gas ? first.leak_rate_pv : first.leak_rate;
  $("#leak-rate-what").textContent = gas ? "Gas leak rate Q_pV" : "Leak rate Q";
  lr.textContent = fmt(shown, 5);
  lr.dataset.si = si === null || si === undefined ? "" : String(si);
  $("#leak-rate-unit").textContent = gas ? "mbar·l/s" : "m³/s";
  // the same leak in the other unit: ml/min for a liquid (the command line's table; 1 m³/s = 6e7 ml/min), Pa·m³/s for a gas
  $("#leak-rate-ml").textContent = typeof si !== "number" ? ""
    : gas ? `= ${fmt(si, 4)} Pa·m³/s` : `= ${fmt(si * 6e7, 4)} ml/min`;
  const x0 = first.squeeze_pressure !== undefined ? `P0 = ${fmt(first.squeeze_pressure / 1e3)} kPa`
    : first.compression !== undefined ? `compression ${fmt(100 * first.compression)} %`
      : first.profile_scale !== undefined ? `profile scale ${fmt(first.profile_scale)}` : "";
  $("#first-pressure").textContent = (first.variant ? `${first.variant}, ` : "") + x0;
  const em = gas ? first.leak_rate_mbar_l_s_effective_medium : first.leak_rate_effective_medium;
  const emSi = gas ? first.leak_rate_pv_effective_medium : first.leak_rate_effective_medium;
  $("#leak-rate-em-line").hidden = em === undefined;
  if (em !== undefined) { $("#leak-rate-em").textContent = `${fmt(em, 5)} ${gas ? "mbar·l/s" : "m³/s"}`; $("#leak-rate-em").dataset.si = String(emSi); }
  const notes = [...doc.warnings, ...doc.messages];
  $("#warnings").hidden = !notes.length;
  $("#notes-count").textContent = `${notes.length} note${notes.length === 1 ? "" : "s"} on the validity of the results`;
  $("#notes").innerHTML = notes.map(n => `<li>${esc(n)}</li>`).join("");

  // the table: every record, every unit-declared column
  const keys = Object.keys(doc.units).filter(k => k !== "validity");
  if (rows.some(r => r.variant)) keys.unshift("variant");
  const head = `<thead><tr>${keys.map(k => `<th>${esc(k)}${doc.units[k] && doc.units[k] !== "1" ? ` (${doc.units[k]})` : ""}</th>`).join("")}</tr></thead>`;
  const body = rows.map(r => `<tr>${keys.map(k => `<td data-key="${esc(k)}" data-si="${esc(r[k] ?? "")}">${esc(fmt(r[k], 5))}</td>`).join("")}</tr>`).join("");
  $("#results-table").innerHTML = head + `<tbody>${body}</tbody>`;

  const p = pred.plots;
  const leak = [];
  const units = new Set(p.leak.map(c => c.unit));  // a study of liquids and gases: each curve names its unit
  for (const c of p.leak) {
    const tag = (p.leak.length > 1 ? `${c.label}: ` : "") + (units.size > 1 ? `(${c.unit}) ` : "");
    leak.push(line(c.squeeze_pressure, c.leak_rate, `${tag}critical junction`, { mode: "lines+markers", marker: { size: 4 } }));
    if (c.leak_rate_effective_medium) leak.push(line(c.squeeze_pressure, c.leak_rate_effective_medium, `${tag}effective medium`, { mode: "lines+markers", marker: { size: 4 }, line: { dash: "dash" } }));
  }
  const xname = p.leak[0] ? p.leak[0].x : "squeeze_pressure";
  const xunit = p.leak[0] && p.leak[0].x_unit && p.leak[0].x_unit !== "1" ? ` (${p.leak[0].x_unit})` : "";
  plot("plot-leak", leak, "Leak rate", axis(xname === "squeeze_pressure" ? "squeeze pressure P0 (Pa)" : xname + xunit, true),
    { ...axis(units.size > 1 ? "leak rate (the unit of each curve in its legend)"
      : p.leak[0] && p.leak[0].gas ? "gas leak rate Q_pV (mbar·l/s)" : "leak rate Q (m³/s)", true), range: topDecades(leak, 8) });
  plot("plot-psd", p.spectra.map(s => line(s.q, s.C, s.label)), "Power spectrum C(q)", axis("wavevector q (1/m)", true), axis("C(q) (m⁴)", true));
  plot("plot-area", p.sets.map(s => line(s.zeta, s.area, s.label)), "Contact area A(ζ)/A0", axis("magnification ζ", true), axis("A(ζ)/A0", false));
  const gaps = p.sets.map(s => line(s.zeta_gap, s.mean_gap.map(v => v === null ? null : v * 1e6), s.label));
  plot("plot-gap", gaps, "Mean separation ū(ζ)", axis("magnification ζ", true), { ...axis("ū(ζ) (µm)", true), range: topDecades(gaps, 4) });
  plot("plot-gaps", p.gaps.density.map((d, i) => line(p.gaps.u.map(v => v * 1e6), d, p.gaps.labels[i])), "Gap distribution u·P(u)",
    axis("gap u (µm)", true), axis("u·P(u)", false));
}

async function pagePrediction() {
  const both = $("#both-theories");
  await Form.init(true, state => {
    const model = $('#case-form [name="theory.model"]');
    if (model) both.checked = model.value === "both";
    if (state.prediction) drawPrediction(state.prediction);
    // while the case has an error the results shown are those of the last valid case: greyed out
    $("#results").classList.toggle("stale", !!state.error);
  });
  both.addEventListener("change", () => {
    const model = $('#case-form [name="theory.model"]');
    if (!model) return;
    model.value = both.checked ? "both" : "";
    Form.changed();
  });
}

// ---------------------------------------------------------------- Surface page
async function pageSurface() {
  const state = await api("GET", "/api/case");
  setCaseName(state);
  let names = [];
  let options = {};
  $("#analyze").addEventListener("click", async () => {
    const form = $("#surface-form");
    const files = $("#topo-files").files;
    $$("#surface-form .err").forEach(e => { e.textContent = ""; });
    $$("#surface-form .invalid").forEach(e => e.classList.remove("invalid"));
    showMessage("");
    if (!files.length) { showMessage("choose one or more topography files first"); return; }
    const body = new FormData(form);
    $("#analyze").disabled = true;
    $("#analyze").textContent = "Analyzing…";
    try {
      const an = await api("POST", "/api/surface/analyze", body);
      names = Array.from(files).map(f => f.name);
      options = {};
      for (const [k, v] of body.entries()) if (typeof v === "string" && v.trim() !== "") options[k] = k === "periodic" ? true : v;
      drawSurface(an);
      $("#use-surface").disabled = !an.psd;
    } catch (e) {
      const m = /(--[a-z-]+)/.exec(e.message);  // the option the message names, e.g. "give --height-unit"
      const box = m ? $(`#surface-form [data-field="${m[1]}"]`) : null;
      if (box) { $(".err", box).textContent = e.message; $("input", box).classList.add("invalid"); } else showMessage(e.message);
    } finally {
      $("#analyze").disabled = false;
      $("#analyze").textContent = "Analyze";
    }
  });
  $("#use-surface").addEventListener("click", async () => {
    try {
      const st = await api("PUT", "/api/case/surface", { files: names, options });
      setCaseName(st);
      const used = $("#used");
      used.textContent = st.valid ? `The case's surface is now the measured topography (${names.join(", ")}).`
        : `The case's surface is now the measured topography; the case reports: ${st.error.message}`;
      used.className = st.valid ? "banner ok" : "banner bad";
    } catch (e) { showMessage(e.message); }
  });
}

function drawSurface(an) {
  $("#surface-results").hidden = false;
  const st = an.statistics;
  const h = $("#h-rms");
  h.textContent = fmt(st.h_rms * 1e6, 4);
  h.dataset.si = String(st.h_rms);
  const rows = [["h_rms", "µm", 1e6], ["slope_rms", "1", 1], ["curvature_rms", "1/mm", 1e-3], ["area_ratio", "1", 1],
    ["skewness", "1", 1], ["kurtosis", "1", 1]];
  const cell = (v, s) => (v === null || v === undefined ? "—" : fmt(v * s, 4));
  $("#stats").innerHTML = "<thead><tr><th>quantity</th><th>unit</th><th>from heights</th><th>from C(q)</th></tr></thead><tbody>" +
    rows.map(([k, u, s]) => `<tr><td>${k}</td><td>${u}</td><td data-key="${k}">${cell(st[k], s)}</td><td>${cell(st[`spectrum_${k}`], s)}</td></tr>`).join("") + "</tbody>";
  const fit = an.fit;
  $("#fit").innerHTML = fit ? `<table class="data"><tbody>
    <tr><td>Hurst exponent H</td><td>${fmt(fit.hurst)} ± ${fmt(fit.hurst_err, 2)}</td></tr>
    <tr><td>roll-off q_r (1/m)</td><td>${fmt(fit.q_rolloff)} ± ${fmt(fit.q_rolloff_err, 2)}${fit.rolloff_resolved ? "" : " (not resolved)"}</td></tr>
    <tr><td>C0 (m⁴)</td><td>${fmt(fit.C0)} ± ${fmt(fit.C0_err, 2)}</td></tr>
    <tr><td>h_rms of the fit (µm)</td><td>${fmt(fit.h_rms * 1e6)} ± ${fmt(fit.h_rms_err * 1e6, 2)}</td></tr>
    <tr><td>χ²/dof</td><td>${fmt(fit.chi2_red)}</td></tr></tbody></table>${fit.warning ? `<p class="err">${esc(fit.warning)}</p>` : ""}`
    : `<p class="muted">no fit${an.psd_problem ? `: ${esc(an.psd_problem)}` : ""}</p>`;
  $("#surface-notes").textContent = [...an.warnings, ...an.notes].join(" · ");
  const traces = [];
  if (an.psd) traces.push(line(an.psd.q, an.psd.C, an.sources.length > 1 ? "stitched C(q)" : "C(q)", { line: { width: 2.5 } }));
  const shapes = an.sources.filter(s => s.reliable_range && s.reliable_range[0]).map(s => ({
    type: "rect", xref: "x", yref: "paper", x0: s.reliable_range[0], x1: s.reliable_range[1], y0: 0, y1: 1,
    fillcolor: "rgba(31,95,191,0.07)", line: { width: 0 },
  }));
  if (fit && an.psd) {
    const q = an.psd.q;
    const C = q.map(v => fit.C0 * (v <= fit.q_rolloff ? 1 : Math.pow(v / fit.q_rolloff, -2 * (1 + fit.hurst))));
    traces.push(line(q, C, `self-affine fit, H = ${fmt(fit.hurst, 3)}`, { line: { dash: "dot" } }));
  }
  const el = document.getElementById("plot-psd");
  Plotly.react(el, traces, { ...LAYOUT, title: { text: "C(q) (shaded: the reliable range of each file)", font: { size: 14 } },
    xaxis: axis("wavevector q (1/m)", true), yaxis: axis("C(q) (m⁴)", true), shapes }, CONFIG);
}

// ---------------------------------------------------------------- Simulation page
async function pageSimulation() {
  const state = await api("GET", "/api/case");
  setCaseName(state);
  if (!state.toml) showMessage("no case yet: choose an example or upload a case file on the Case page");
  $("#start-sim").addEventListener("click", async () => {
    const body = {};
    for (const k of ["grid", "realizations", "seed", "workers"]) body[k] = $(`#sim-${k}`).value.trim();
    showMessage("");
    try { await api("POST", "/api/jobs", body); } catch (e) { showMessage(e.message); }
    refreshJobs();
  });
  refreshJobs();
}

let shownJob = null;
let pollTimer = null;

async function refreshJobs() {
  clearTimeout(pollTimer);
  let jobs = [];
  try { jobs = await api("GET", "/api/jobs"); } catch (e) { showMessage(e.message); }
  const tbody = $("#jobs tbody");
  tbody.innerHTML = jobs.map(j => {
    const pct = j.total ? Math.round(100 * j.done / j.total) : 0;
    const opts = Object.entries(j.options).map(([k, v]) => `${k} ${v}`).join(", ") || "the case's";
    const action = ["starting", "running"].includes(j.state) ? `<button class="secondary cancel" data-id="${j.id}">Cancel</button>`
      : j.state === "done" ? `<button class="secondary show" data-id="${j.id}">Show result</button>` : "";
    return `<tr data-job="${j.id}"><td>${j.id}</td><td>${esc(j.title)}</td><td>${esc(opts)}</td>
      <td class="state state-${j.state}">${j.state}${j.message && j.state !== "cancelled" ? `: ${esc(j.message)}` : ""}</td>
      <td><span class="progress"><div style="width:${pct}%"></div></span> ${j.total ? `${j.done}/${j.total} tasks` : ""}</td>
      <td>${j.elapsed} s</td><td>${action}</td></tr>`;
  }).join("") || '<tr><td colspan="7" class="muted">no simulation yet</td></tr>';
  $$("#jobs .cancel").forEach(b => b.addEventListener("click", async () => {
    try { await api("POST", `/api/jobs/${b.dataset.id}/cancel`); } catch (e) { showMessage(e.message); }
    refreshJobs();
  }));
  $$("#jobs .show").forEach(b => b.addEventListener("click", () => showJob(jobs.find(j => j.id === b.dataset.id))));
  const latestDone = jobs.find(j => j.state === "done");
  if (latestDone && shownJob === null) showJob(latestDone);
  if (jobs.some(j => ["starting", "running"].includes(j.state))) pollTimer = setTimeout(refreshJobs, 1000);
}

async function showJob(job) {
  shownJob = job.id;
  $("#job-result").hidden = false;
  $("#job-result-title").textContent = `Result of job ${job.id} (${job.title})`;
  $("#job-json").href = `/api/jobs/${job.id}/result.json`;
  $("#job-table").textContent = await api("GET", `/api/jobs/${job.id}/table.txt`);
  $("#job-figures").innerHTML = job.figures.map(f => `<img alt="${esc(f)}" src="/api/jobs/${job.id}/figures/${encodeURIComponent(f)}">`).join("");
}

// ----------------------------------------------------------------
const PAGES = { case: pageCase, prediction: pagePrediction, surface: pageSurface, simulation: pageSimulation };
document.addEventListener("DOMContentLoaded", () => {
  markNav();
  const run = PAGES[document.body.dataset.page];
  // data-ready: the page has loaded what it shows (the browser tests wait for it)
  if (run) run().catch(e => showMessage(e.message)).finally(() => { document.body.dataset.ready = "1"; });
});
