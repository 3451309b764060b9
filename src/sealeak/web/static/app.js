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

async function api(method, url, body, signal) {
  const opts = { method, headers: {}, signal };
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

// a long title cut for a legend or a column head (the whole of it on hover)
function short(text, n = 40) {
  const t = String(text);
  return t.length > n ? `${t.slice(0, n - 1)}…` : t;
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
  document.body.dataset.caseName = state && state.toml ? state.name : "";
  const up = $("#uploads");
  if (up && state && state.uploads) {
    // each file under the name it is stored (and named in the case) by, with the name it was uploaded as
    const names = state.upload_names || {};
    up.textContent = state.uploads.length ? state.uploads.map(n => names[n] && names[n] !== n ? `${n} (uploaded as ${names[n]})` : n).join(", ") : "none";
  }
}

// ---------------------------------------------------------------- display units (one place: every conversion goes through here)
// The factors come from the server (sealeak.io.units); a value shown = value in SI / factor. The choice is kept in the browser.
const Units = {
  table: null,
  chosen: JSON.parse(localStorage.getItem("sealeak.units") || "{}"),
  DEFAULT: { pressure: "kPa", length: "µm", volume_flow: "m³/s", throughput: "mbar·l/s" },
  // the unit of a JSON column (its records' unit string) → the dimension it is shown in
  OF: { "Pa": "pressure", "m": "length", "m^3/s": "volume_flow", "Pa*m^3/s": "throughput" },

  init(table) { this.table = table; },
  unit(dim) {
    const list = (this.table || {})[dim] || [];
    const name = this.chosen[dim] || this.DEFAULT[dim];
    return list.find(u => u.name === name) || list[0] || { name: "", factor: 1 };
  },
  choose(dim, name) { this.chosen[dim] = name; localStorage.setItem("sealeak.units", JSON.stringify(this.chosen)); },
  // the factor of ``dim``'s chosen unit; a gas's sccm depends on its temperature: taken from the records' own column
  factor(dim, rows) {
    const u = this.unit(dim);
    if (u.column && rows) {
      const r = rows.find(x => typeof x[u.column] === "number" && x[u.column] > 0 && typeof x.leak_rate_pv === "number");
      if (r) return r.leak_rate_pv / r[u.column];
    }
    return u.factor;
  },
  show(si, dim, rows) { return typeof si === "number" ? si / this.factor(dim, rows) : si; },
  name(dim) { return this.unit(dim).name; },
};

// ---------------------------------------------------------------- the case form (Case and Prediction pages)
const Form = {
  schema: null, fields: {}, extra: {}, timer: null, onResult: null, predict: false,

  async init(predict, onResult) {
    this.predict = predict;
    this.onResult = onResult;
    const form = await api("GET", "/api/form");
    this.schema = form.sections;
    this.examples = form.examples;
    Units.init(form.units);
    const state = await api("GET", `/api/case?predict=${predict ? 1 : 0}`);
    this.render(state);
    this.apply(state);
    return state;
  },

  // the key's meaning and what it takes; beside the results (Prediction page) only what it takes, the meaning on hover and Help
  hint(f) {
    const what = this.kindHint(f);
    return f.help && !this.predict ? `${f.help} — ${what}` : what;
  },

  kindHint(f) {
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
    label.title = f.help ? `${f.name}: ${f.help}` : f.name;
    const text = document.createElement("span");
    text.className = "label-text";
    text.textContent = f.label || f.key;
    const key = document.createElement("code");
    key.textContent = f.key;
    label.append(text, " ", key);
    if (f.anchor) {  // the key on the Help page (which names the documentation's section)
      const more = document.createElement("a");
      more.className = "doc-link"; more.href = `/help#${encodeURIComponent(f.name)}`; more.target = "_blank";
      more.textContent = "?"; more.title = `${f.name}: what it means, in the reference (docs/case-files.md#${f.anchor})`;
      label.append(" ", more);
    }
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

  // one request at a time: a newer edit aborts the request of the older one (its answer would be stale)
  async send(method, url, body) {
    if (this.pending) this.pending.abort();
    const ctl = (this.pending = new AbortController());
    document.body.classList.add("busy");
    try {
      return await api(method, url, body, ctl.signal);
    } finally {
      if (this.pending === ctl) { this.pending = null; document.body.classList.remove("busy"); }
    }
  },

  async submit() {
    try {
      this.apply(await this.send("PUT", "/api/case/fields", { fields: this.values(), predict: this.predict }));
    } catch (e) {
      if (e.name !== "AbortError") showMessage(e.message);
    }
  },

  apply(state) {
    setCaseName(state);
    Editor.show(state);
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

// ---------------------------------------------------------------- the TOML editor (Case page), in step with the form
const Editor = {
  timer: null,
  el() { return $("#toml-editor"); },

  // the case's TOML, unless the user is typing in the editor (the form's edits arrive here with their comments kept)
  show(state) {
    const ed = this.el();
    if (!ed || document.activeElement === ed || this.held) return;
    ed.value = state.toml || "";
    this.error(null);
  },

  init() {
    const ed = this.el();
    if (!ed) return;
    ed.addEventListener("input", () => {
      clearTimeout(this.timer);
      const status = $("#status");
      if (status) status.textContent = "checking…";
      this.timer = setTimeout(() => this.submit(), 500);
    });
  },

  async submit() {
    const ed = this.el();
    try {
      const body = { toml: ed.value, predict: Form.predict };
      if (this.held) body.name = this.held;  // an uploaded file fixed here becomes the case, under its name
      const state = await Form.send("PUT", "/api/case/toml", body);
      if (state.rejected) {  // not TOML: the case (and the form) stay as they were
        this.error(state.rejected);
        const st = $("#status");
        if (st) st.textContent = "the TOML has an error (under the editor); the form keeps the last valid case";
        return;
      }
      this.held = null;
      this.error(null);
      Form.render(state); Form.apply(state);
    } catch (e) {
      if (e.name !== "AbortError") showMessage(e.message);
    }
  },

  // text that is not TOML: shown in the editor with the message, the line and a caret under the column; the case is unchanged
  hold(text, err, name) {
    const ed = this.el();
    if (!ed) return;
    ed.value = text;
    this.held = name;  // the form's answers do not overwrite it until it is fixed
    this.error(err);
    const lh = parseFloat(getComputedStyle(ed).lineHeight) || 16;  // the error's line in view
    ed.scrollTop = Math.max(0, (err.line - 4) * lh);
  },

  error(e) {
    const box = $("#toml-error"), ed = this.el();
    if (!box || !ed) return;
    ed.classList.toggle("invalid", !!e);
    if (!e) { box.hidden = true; box.textContent = ""; return; }
    const text = ed.value.split("\n")[e.line - 1] ?? "";
    const gutter = `${e.line} | `;
    // "case.toml: malformed TOML: Unclosed array (at line 3, column 5)" → "line 3, column 5: Unclosed array"
    const why = e.message.replace(/^.*?malformed TOML: /, "").replace(/ \(at line \d+, column \d+\)$/, "");
    box.hidden = false;
    box.textContent = `line ${e.line}, column ${e.column}: ${why}\n${gutter}${text}\n${" ".repeat(gutter.length + Math.max(0, e.column - 1))}^`;
  },
};

// ---------------------------------------------------------------- Case page
async function pageCase() {
  // the controls answer from the start; the form and the list of examples arrive with Form.init
  const sel = $("#example");
  Editor.init();
  $("#load-example").addEventListener("click", async () => {
    if (!sel.value) { showMessage("Choose an example to load."); return; }
    try {
      const state = await api("POST", "/api/case/example", { name: sel.value });
      Editor.held = null;
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
      if (state.rejected) {
        // not TOML: the form keeps the current case; the file goes into the editor, its error marked, to be fixed there
        Editor.hold(await file.text(), state.rejected, file.name);
        showMessage(`${state.rejected.message}. Not loaded: the form keeps the current case; fix the file in the TOML editor.`);
        return;
      }
      Editor.held = null;
      Form.render(state); Form.apply(state);
      // the list of examples no longer names the case in the form: it names the file
      let uploaded = sel.querySelector('option[value=""]');
      if (!uploaded) { uploaded = document.createElement("option"); uploaded.value = ""; sel.prepend(uploaded); }
      uploaded.textContent = `${file.name} (uploaded: the case in the form)`;
      sel.value = "";
    } catch (e) { showMessage(e.message); }
  });
  Form.ready = Form.init(false, null);
  await Form.ready;
  for (const ex of Form.examples) {
    const o = document.createElement("option");
    o.value = ex.name; o.textContent = `${ex.name} — ${ex.description}`;
    sel.appendChild(o);
  }
  // the list names the case in the form (it showed the first example whatever case the session held)
  const name = document.body.dataset.caseName || "";
  const shown = Form.examples.find(ex => `${ex.name}.toml` === name);
  if (shown) sel.value = shown.name;
  else if (name) {
    const o = document.createElement("option");
    o.value = ""; o.textContent = `${name} (the case in the form)`;
    sel.prepend(o);
    sel.value = "";
  }
}

// ---------------------------------------------------------------- Help page: every key, its label, meaning and what it takes
async function pageHelp() {
  const form = await api("GET", "/api/form");
  const out = $("#help");
  for (const sec of form.sections) {
    const h = document.createElement("h2");
    const anchor = sec.fields[0] ? sec.fields[0].anchor : "";
    h.textContent = sec.section ? `[${sec.section}]` : "Top level";
    h.id = `section-${sec.section || "top"}`;
    const where = document.createElement("span");
    where.className = "muted doc-ref";
    where.textContent = ` docs/case-files.md#${anchor}`;
    h.appendChild(where);
    out.appendChild(h);
    const table = document.createElement("table");
    table.className = "data help";
    table.innerHTML = "<thead><tr><th>key</th><th>label</th><th>meaning</th><th>takes</th></tr></thead>";
    const body = document.createElement("tbody");
    for (const f of sec.fields) {
      const tr = document.createElement("tr");
      tr.id = f.name;
      for (const [text, code] of [[f.name, true], [f.label, false], [f.help, false], [Form.kindHint(f), false]]) {
        const td = document.createElement("td");
        if (code) { const c = document.createElement("code"); c.textContent = text; td.appendChild(c); } else td.textContent = text;
        tr.appendChild(td);
      }
      body.appendChild(tr);
    }
    table.appendChild(body);
    out.appendChild(table);
  }
  if (location.hash) {
    const row = document.getElementById(decodeURIComponent(location.hash.slice(1)));
    if (row) { row.classList.add("target"); row.scrollIntoView({ block: "center" }); }
  }
}

// ---------------------------------------------------------------- Prediction page
const LAYOUT = {
  margin: { l: 70, r: 20, t: 40, b: 62 }, font: { size: 12 }, hovermode: "x",
  legend: { orientation: "h", x: 0, yanchor: "top", tracegroupgap: 0 }, paper_bgcolor: "#fff", plot_bgcolor: "#fff",
};
// a plot's area (px) between its title and its x axis; the legend goes LEGEND.below px under that axis (its ticks and
// title above it), in rows of LEGEND.row px (Plotly's entry of a 12 px font, 19 px)
const AREA = 250;
const LEGEND = { below: 62, row: 20, symbol: 45, font: '12px "Open Sans", verdana, arial, sans-serif' };
const CONFIG = { responsive: true, displaylogo: false, toImageButtonOptions: { format: "png", scale: 2 } };

function axis(title, log) {
  return { title: { text: title }, type: log ? "log" : "linear", exponentformat: "power", gridcolor: "#e6e9ef", zeroline: false };
}

// an axis range fitted to the data: log axes over at most ``decades`` below the largest value (a leak rate or a gap
// that vanishes would stretch it over 40 decades), a margin of 5 % of the span (linear) or 0.15 decades (log)
function fitRange(values, log, decades = 8) {
  const v = values.filter(x => typeof x === "number" && isFinite(x) && (!log || x > 0));
  if (!v.length) return undefined;
  if (log) {
    const hi = Math.log10(Math.max(...v)), lo = Math.max(Math.log10(Math.min(...v)), hi - decades);
    const pad = Math.max(0.15, (hi - lo) * 0.04);
    return [lo - pad, hi + pad];
  }
  const hi = Math.max(...v), lo = Math.min(...v), pad = (hi - lo) * 0.05 || Math.abs(hi) * 0.05 || 1;
  return [lo - pad, hi + pad];
}

let textMeasure = null;

// the width (px) of a legend entry's text, as Plotly draws it
function textWidth(text) {
  textMeasure = textMeasure || document.createElement("canvas").getContext("2d");
  textMeasure.font = LEGEND.font;
  return textMeasure.measureText(String(text)).width;
}

// the height, bottom margin and legend of a plot whose legend sits under its x-axis title, never on it: Plotly lays out
// a legend of several rows in columns as wide as its widest entry, so the rows follow from the entries' text widths
// and the plot's width; the figure grows by them, its plotting area (``area`` px) stays
function legendRoom(el, traces, margin, area) {
  const names = traces.filter(t => t.showlegend !== false && t.name).map(t => t.name);
  if (names.length < 2) return { height: margin.t + area + margin.b, margin, legend: LAYOUT.legend };
  const entry = Math.ceil(Math.max(...names.map(textWidth))) + LEGEND.symbol;
  const perRow = Math.max(1, Math.floor((el.clientWidth - margin.l - margin.r) / entry));
  const tall = Math.ceil(names.length / perRow) * LEGEND.row + 12;
  const b = LEGEND.below + tall;
  return { height: margin.t + area + b, margin: { ...margin, b },
    legend: { ...LAYOUT.legend, y: -LEGEND.below / area, maxheight: tall + 10 } };
}

// a Plotly plot in the element ``id``: ``x``, ``y`` its axes, ``extra`` more of its layout (more axes, shapes, a margin)
function plot(id, traces, title, x, y, extra = {}, area = AREA) {
  const el = document.getElementById(id);
  if (!el || typeof Plotly === "undefined") return;
  const room = legendRoom(el, traces, { ...LAYOUT.margin, ...extra.margin }, area);
  el.style.height = `${room.height}px`;  // CSSOM, not a style attribute (the pages' CSP)
  // as wide as its cell is now: a width Plotly took from an earlier layout drew the plot past its cell, under the next
  const width = el.clientWidth || undefined;
  Plotly.react(el, traces, { ...LAYOUT, title: { text: title, font: { size: 14 } }, xaxis: x, yaxis: y, ...extra, ...room,
    width }, CONFIG);
}

function line(x, y, name, extra = {}) {
  // hover: both values to 4 significant digits (tiny ones such as leak rates in m³/s with an exponent)
  return { x, y, name, type: "scatter", mode: "lines", hovertemplate: "%{x:.4~g}, %{y:.4~e}<extra>%{fullData.name}</extra>", ...extra };
}

// the x of a leak curve as shown: a squeeze pressure in the chosen unit, a compression in %, a profile scale as it is
const X_AXES = {
  squeeze_pressure: { dim: "pressure", title: () => `squeeze pressure P0 (${Units.name("pressure")})`, log: true },
  compression: { percent: true, title: () => "compression ε (%)", log: false },
  profile_scale: { title: () => "profile scale", log: false },
};

function showX(c) {
  const ax = X_AXES[c.x] || X_AXES.profile_scale;
  return c.squeeze_pressure.map(v => v === null ? null : ax.percent ? 100 * v : ax.dim ? Units.show(v, ax.dim) : v);
}

// a leak curve's values in SI (m³/s; a gas: Pa·m³/s from the records' mbar·l/s)
function leakSI(c, values) {
  const mbar = c.gas ? Units.table.throughput.find(u => u.name === "mbar·l/s").factor : 1;
  return values ? values.map(v => v === null ? null : v * mbar) : null;
}

let lastPrediction = null;

function drawPrediction(pred) {
  lastPrediction = pred;
  const doc = pred.json;
  const rows = doc.results;
  const first = rows[0] || {};
  const lr = $("#leak-rate");
  // a gas: the pV throughput (leak-test units: mbar·l/s, Pa·m³/s, sccm); a liquid: a volume flow (m³/s, ml/min, ...)
  const gas = first.leak_rate_pv !== undefined;
  const dim = gas ? "throughput" : "volume_flow";
  const si = gas ? first.leak_rate_pv : first.leak_rate;
  $("#leak-rate-what").textContent = gas ? "Gas leak rate Q_pV" : "Leak rate Q";
  lr.textContent = typeof si === "number" ? fmt(Units.show(si, dim, rows), 5) : "sealed";
  lr.dataset.si = si === null || si === undefined ? "" : String(si);
  $("#leak-rate-unit").textContent = typeof si === "number" ? Units.name(dim) : "";
  // the same leak in a second unit: ml/min for a liquid (1 m³/s = 6e7 ml/min) unless chosen, the SI unit otherwise
  const other = gas ? (Units.name(dim) === "Pa·m³/s" ? "mbar·l/s" : "Pa·m³/s") : (Units.name(dim) === "ml/min" ? "m³/s" : "ml/min");
  const otherUnit = Units.table[dim].find(u => u.name === other);
  $("#leak-rate-ml").textContent = typeof si !== "number" ? "" : `= ${fmt(si / otherUnit.factor, 4)} ${other}`;
  const x0 = first.squeeze_pressure !== undefined ? `P0 = ${fmt(Units.show(first.squeeze_pressure, "pressure"))} ${Units.name("pressure")}`
    : first.compression !== undefined ? `compression ${fmt(100 * first.compression)} %`
      : first.profile_scale !== undefined ? `profile scale ${fmt(first.profile_scale)}` : "";
  $("#first-pressure").textContent = (first.variant ? `${first.variant}, ` : "") + x0;
  const emSi = gas ? first.leak_rate_pv_effective_medium : first.leak_rate_effective_medium;
  $("#leak-rate-em-line").hidden = emSi === undefined;
  if (emSi !== undefined) {
    $("#leak-rate-em").textContent = typeof emSi === "number" ? `${fmt(Units.show(emSi, dim, rows), 5)} ${Units.name(dim)}` : "sealed";
    $("#leak-rate-em").dataset.si = String(emSi);
  }
  // with conditions.max_leak_rate: the passing loads and the answers of the seal over its life, as predict words them
  const answers = (doc.uncertainty && doc.uncertainty.answers) || [];
  $("#answers").hidden = !answers.length;
  $("#answers").innerHTML = answers.map(a => `<li>${esc(a)}</li>`).join("");
  const notes = [...doc.warnings, ...doc.messages];
  $("#warnings").hidden = !notes.length;
  $("#notes-count").textContent = `${notes.length} note${notes.length === 1 ? "" : "s"} on the validity of the results`;
  $("#notes").innerHTML = notes.map(n => `<li>${esc(n)}</li>`).join("");

  // the table: every record, every unit-declared column, in the chosen units (data-si: the record's own value)
  const keys = Object.keys(doc.units).filter(k => k !== "validity");
  if (rows.some(r => r.variant)) keys.unshift("variant");
  const unitOf = k => k === "compression" ? "%" : Units.OF[doc.units[k]] ? Units.name(Units.OF[doc.units[k]])
    : doc.units[k] && doc.units[k] !== "1" ? doc.units[k] : "";
  const cell = (k, v) => k === "compression" && typeof v === "number" ? 100 * v : Units.OF[doc.units[k]] ? Units.show(v, Units.OF[doc.units[k]], rows) : v;
  const head = `<thead><tr>${keys.map(k => `<th>${esc(k)}${unitOf(k) ? ` (${esc(unitOf(k))})` : ""}</th>`).join("")}</tr></thead>`;
  const body = rows.map(r => `<tr class="${r.valid === false ? "invalid-row" : ""}">${keys.map(k => `<td data-key="${esc(k)}" data-si="${esc(r[k] ?? "")}">${esc(fmt(cell(k, r[k]), 5))}</td>`).join("")}</tr>`).join("");
  $("#results-table").innerHTML = head + `<tbody>${body}</tbody>`;
  drawPlots(pred);
}

// the colours of the cases whose uncertain inputs draw a band (the band filled, the curves in the same colour)
const BAND_RGB = ["31,119,180", "255,127,14", "44,160,44", "214,39,40", "148,103,189"];
// the colours of the other leak curves, one per curve in turn (given, not left to Plotly, so that the markers of a
// curve's sealed points and points below the axis take its colour): one counter for the live curves and the pinned ones
function curveColours() { let next = 0; return () => COLORS[next++ % COLORS.length]; }

// the leak-rate curves of a prediction (and the pinned ones, dotted): sealed points at the axis' foot, invalid ones crossed;
// with uncertain inputs the 5–95 % band of the samples and their median (bands: the traces whose sealed values, 0, go to the foot)
function leakCurves(p, rows, tagAll, style = {}, colour = curveColours()) {
  const traces = [], marks = [], bands = [];
  const kinds = new Set(p.leak.map(c => c.gas));
  p.leak.forEach((c, k) => {
    const tag = (tagAll || p.leak.length > 1 ? `${c.label}: ` : "") + (kinds.size > 1 ? `(${Units.name(c.gas ? "throughput" : "volume_flow")}) ` : "");
    const dim = c.gas ? "throughput" : "volume_flow";
    const x = showX(c);
    const show = v => v === null ? null : Units.show(v, dim, rows);
    const rgb = c.band ? BAND_RGB[k % BAND_RGB.length] : null;
    if (c.band) {
      const [lo, med, hi] = ["p05", "p50", "p95"].map(q => leakSI(c, c.band[q]).map(show));
      const edge = { line: { width: 0.5, color: `rgba(${rgb},0.5)` } };
      bands.push(line(x, lo, `${tag}5th percentile of the samples`, { showlegend: false, ...edge }));
      bands.push(line(x, hi, `${tag}5–95 % of ${c.band.samples} samples`, { fill: "tonexty", fillcolor: `rgba(${rgb},0.18)`, ...edge }));
      bands.push(line(x, med, `${tag}median of the samples`, { line: { dash: "dot", width: 2, color: `rgb(${rgb})` } }));
      traces.push(...bands.slice(-3));
      // a percentile taken from samples outside the theory, circled (a band trace: at the axis' foot where it is below it)
      [["p50_outside", med, "median", 10, 2], ["p05_outside", lo, "5th percentile", 6, 1.5], ["p95_outside", hi, "95th percentile", 6, 1.5]]
        .forEach(([flag, ys, what, size, width]) => {
          const at = (c.band[flag] || []).map((o, i) => o && ys[i] > 0 ? i : -1).filter(i => i >= 0);
          if (!at.length) return;
          bands.push({ x: at.map(i => x[i]), y: at.map(i => ys[i]), type: "scatter", mode: "markers",
            name: `${tag}${what} from samples outside the theory`, hovertemplate: "%{x:.4~g}, %{y:.4~e}<extra>%{fullData.name}</extra>",
            marker: { symbol: "circle-open", size, color: `rgb(${rgb})`, line: { width } } });
          traces.push(bands[bands.length - 1]);
        });
    }
    const cj = leakSI(c, c.leak_rate).map(show);
    const cjName = `${tag}critical junction${c.band ? " (nominal inputs)" : ""}`, cjColour = rgb ? `rgb(${rgb})` : colour();
    traces.push(line(x, cj, cjName, { mode: "lines+markers", marker: { size: 5, color: cjColour },
      ...style, line: { color: cjColour, ...(style.line || {}) } }));
    marks.push({ x, y: cj, valid: c.valid || [], colour: cjColour, name: cjName });
    const em = leakSI(c, c.leak_rate_effective_medium);
    if (em) {
      const emName = `${tag}effective medium`, emColour = colour(), y = em.map(show);
      traces.push(line(x, y, emName, { mode: "lines+markers", marker: { size: 5, color: emColour },
        ...style, line: { dash: "dash", color: emColour, ...(style.line || {}) } }));
      marks.push({ x, y, valid: c.valid_effective_medium || [], colour: emColour, name: emName });
    }
  });
  return { traces, marks, bands };
}

// a set's label ("P0 = 20 kPa", after a study's label) with its pressure in the chosen unit
function setLabel(s) {
  return s.label.replace(/P0 = .*$/, `P0 = ${fmt(Units.show(s.squeeze_pressure, "pressure"))} ${Units.name("pressure")}`);
}

// points outside the theory's validity (valid = NO), crossed
function outsideTheory(x, y, extra = {}) {
  return { x, y, name: "outside the theory (valid = NO)", type: "scatter", mode: "markers",
    marker: { symbol: "x-thin-open", size: 12, color: "#b3261e", line: { width: 2 } },
    hovertemplate: "%{x:.4~g}, %{y:.4~e}: outside the theory<extra></extra>", ...extra };
}

// the title of a leak-rate axis in the chosen unit: a gas's pV throughput, a liquid's volume flow
function leakTitle(gas) {
  return gas ? `gas leak rate${Units.name("throughput") === "sccm" ? "" : " Q_pV"} (${Units.name("throughput")})`
    : `leak rate Q (${Units.name("volume_flow")})`;
}

// ---------------------------------------------------------------- the seal over its life ([conditions] time and temperature)
// the units of a time, as sealeak.cases.life has them (a: the Julian year)
const TIME_UNITS = [["a", 365.25 * 86400], ["d", 86400], ["h", 3600], ["min", 60], ["s", 1]];
// Plotly's colours, one per temperature (or time) in every panel
// twenty colours (matplotlib's tab10, then its tab20's light tones): a life file's 20 cases each have their own
const COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
  "#aec7e8", "#ffbb78", "#98df8a", "#ff9896", "#c5b0d5", "#c49c94", "#f7b6d2", "#c7c7c7", "#dbdb8d", "#9edae5"];
// the most loads a life plot draws a panel for (evenly spread beyond), its panels' height and the gap (px) for a heading
const LIFE = { panels: 4, height: 210, gap: 46 };
const KELVIN = 273.15;  // 0 °C in K

// "1 h", "30 d": a time (s) in the largest unit in which 4 digits show it exactly, else the largest it reaches
function timeText(t) {
  const spanned = TIME_UNITS.filter(([, f]) => t >= f);
  const exact = spanned.find(([, f]) => Math.abs(Number((t / f).toPrecision(4)) - t / f) <= 1e-9 * (t / f));
  const [u, f] = exact || spanned[0] || ["s", 1];
  return `${fmt(t / f)} ${u}`;
}

// the cases of a life file as a grid: its times (s) and temperatures (K), sorted, the variants of a [study] (in the
// order of the rows; [""] without one), its loads (the n-th row of each case: a pressure, a compression) and
// ``at(n, t, T, v)`` the row of variant v; null where the rows have no time
function lifeGrid(rows) {
  if (!rows.some(r => typeof r.time === "number")) return null;
  const cases = new Map();
  const keyOf = (v, t, T) => JSON.stringify([v, t, T]);
  for (const r of rows) {
    const key = keyOf(studyVariant(r), r.time, r.temperature);
    if (!cases.has(key)) cases.set(key, []);
    cases.get(key).push(r);
  }
  const sorted = v => [...new Set(v)].sort((a, b) => a - b);
  const loads = Math.min(...[...cases.values()].map(c => c.length));
  const shown = Math.min(loads, LIFE.panels);  // the loads drawn: evenly spread, the first and the last
  const panels = [...new Set(Array.from({ length: shown }, (_, k) => (shown > 1 ? Math.round(k * (loads - 1) / (shown - 1)) : 0)))];
  const variants = [...new Set(rows.map(studyVariant))];
  return { times: sorted(rows.map(r => r.time)), temps: sorted(rows.map(r => r.temperature)), variants, loads, panels,
    cases: [...cases.values()], at: (n, t, T, v = variants[0]) => (cases.get(keyOf(v, t, T)) || [])[n] };
}

// the [study] variant of a life file's row: its variant's label without its life part ("h_rms = 2 µm" of
// "h_rms = 2 µm; t = 1 h, T = -20 °C"; "" without a study), as sealeak.cases.life.life_variant
function studyVariant(r) {
  const parts = String(r.variant ?? "").split("; ");
  if (/^t = .*, T = .* °C$/.test(parts[parts.length - 1])) parts.pop();
  return parts.join("; ");
}

// the curves of a life plot: one per ``names`` entry (a temperature or a time; its colour) and variant of a study
// (its dash; its label before the entry's name)
function lifeCurves(grid, names, points) {
  const dashes = ["solid", "dash", "dot", "dashdot", "longdash"];
  return grid.variants.flatMap((v, j) => names.map((name, i) => ({
    name: (grid.variants.length > 1 ? `${v}, ` : "") + name, colour: COLORS[i % COLORS.length], dash: dashes[j % dashes.length],
    points: n => points(n, i, v) })));
}

// a panel's heading: its load as shown (an O-ring's compression changes with the temperature and the compression set)
function lifeHeading(grid, n, key) {
  const xa = X_AXES[key] || X_AXES.profile_scale;
  const v = showX({ x: key, squeeze_pressure: grid.cases.map(c => c[n][key]) }).filter(x => typeof x === "number");
  const lo = fmt(Math.min(...v), 3), hi = fmt(Math.max(...v), 3);
  return lo === hi ? `${xa.title()}: ${lo}` : `${xa.title()}: ${lo} … ${hi} (it changes over the life)`;
}

// a life plot: a panel per load (up to LIFE.panels, stacked over the shared x axis), in each a curve per ``curves``
// entry ({name, points(n): [[x, row], ...]}) of the leak rate Q (a gas: Q_pV) in the chosen unit, ``limit``
// (conditions.max_leak_rate, SI) dash-dotted, points outside the theory crossed
function lifePlot(id, title, x, curves, grid, key, limit, rows) {
  const el = document.getElementById(id);
  if (!el) return;
  el.hidden = false;
  const gas = rows[0].leak_rate_pv !== undefined, dim = gas ? "throughput" : "volume_flow";
  const q = r => { const v = r && (gas ? r.leak_rate_pv : r.leak_rate); return typeof v === "number" && v > 0 ? Units.show(v, dim, rows) : null; };
  const n = grid.panels.length, area = n * LIFE.height + (n - 1) * LIFE.gap;
  const traces = [], extra = { annotations: [], margin: { t: 64 } };
  let belowKey = false;  // the legend's one entry for the points below an axis
  grid.panels.forEach((load, k) => {
    const yaxis = k ? `y${k + 1}` : "y", first = k === 0;
    const out = [];  // the points outside the theory
    const panel = curves.map((c, i) => {
      const pts = c.points(load), y = pts.map(p => q(p[1]));
      pts.forEach(([xv, r], j) => { if (y[j] !== null && r.valid === false) out.push([xv, y[j]]); });
      return line(pts.map(p => p[0]), y, c.name, { mode: "lines+markers", marker: { size: 5 },
        line: { color: c.colour || COLORS[i % COLORS.length], dash: c.dash || "solid" }, yaxis, legendgroup: c.name, showlegend: first });
    });
    const xs = panel.flatMap(t => t.x), ys = panel.flatMap(t => t.y);
    traces.push(...panel);
    if (out.length) traces.push(outsideTheory(out.map(o => o[0]), out.map(o => o[1]), { yaxis, legendgroup: "outside", showlegend: first }));
    const lim = limit ? Units.show(limit.value, dim, rows) : null;
    if (lim) traces.push(line([Math.min(...xs), Math.max(...xs)], [lim, lim], `max_leak_rate = ${limit.text}`,
      { yaxis, legendgroup: "limit", showlegend: first, line: { dash: "dashdot", color: "#333", width: 1.5 } }));
    const top = 1 - k * (LIFE.height + LIFE.gap) / area;
    const range = fitRange(lim ? [...ys, lim] : ys, true, 20);  // a cold, young seal may leak decades less: shown
    if (range) {  // points more than 20 decades under the top: open triangles at the axis' foot, in their curve's colour
      const foot = Math.pow(10, range[0] + 0.1);
      panel.forEach((t, i) => {
        const below = t.x.filter((_, j) => t.y[j] !== null && t.y[j] < foot);
        if (!below.length) return;
        traces.push({ x: below, y: below.map(() => foot), name: `${t.name}: below the axis`, type: "scatter", mode: "markers",
          yaxis, showlegend: false, marker: { symbol: "triangle-down-open", size: 9, color: t.line.color, line: { width: 2 } },
          hovertemplate: "%{x:.4~g}: %{fullData.name}<extra></extra>" });
        if (!belowKey) {
          belowKey = true;
          traces.push({ x: [null], y: [null], name: "below the axis (more than 20 decades under the top)", type: "scatter",
            mode: "markers", yaxis, marker: { symbol: "triangle-down-open", size: 10, color: "#555" } });
        }
      });
    }
    extra[k ? `yaxis${k + 1}` : "yaxis"] = { ...axis(leakTitle(gas), true), anchor: "x", domain: [top - LIFE.height / area, top],
      range };
    extra.annotations.push({ text: lifeHeading(grid, load, key), xref: "paper", yref: "paper", x: 0, y: top, xanchor: "left",
      yanchor: "bottom", showarrow: false, font: { size: 12 } });
  });
  const more = n < grid.loads ? ` (${n} of the ${grid.loads} loads, evenly spread)` : "";
  plot(id, traces, title + more, { ...x, anchor: n > 1 ? `y${n}` : "y" }, extra.yaxis, extra, area);
}

// the life plots of a prediction whose rows carry a time: Q against the time since assembly (log axis; a curve per
// temperature) and against the temperature (a curve per time); hidden otherwise, and where one time or temperature
function drawLife(pred) {
  const rows = pred.json.results, grid = lifeGrid(rows);
  const [byTime, byTemp] = ["plot-life-time", "plot-life-temperature"].map(id => document.getElementById(id));
  if (byTime) byTime.hidden = true;
  if (byTemp) byTemp.hidden = true;
  if (!grid) return;
  const key = (pred.plots.leak[0] || {}).x || "squeeze_pressure", limit = pred.plots.limit;
  const times = grid.times.filter(t => t > 0);  // t = 0 (just after assembly) has no place on a log axis
  if (times.length > 1) {
    const [unit, f] = TIME_UNITS.find(([, g]) => times[0] >= g) || ["s", 1];
    const curves = lifeCurves(grid, grid.temps.map(T => `T = ${fmt(T - KELVIN)} °C`),
      (n, i, v) => times.map(t => [t / f, grid.at(n, t, grid.temps[i], v)]));
    lifePlot("plot-life-time", `Leak rate over the life of the seal${times.length < grid.times.length ? " (t = 0 not on the log axis)" : ""}`,
      { ...axis(`time since assembly t (${unit})`, true), range: fitRange(times.map(t => t / f), true, 20) }, curves, grid, key, limit, rows);
  }
  if (grid.temps.length > 1) {
    const x = grid.temps.map(T => T - KELVIN);
    const curves = lifeCurves(grid, grid.times.map(t => `t = ${timeText(t)}`),
      (n, i, v) => grid.temps.map((T, k) => [x[k], grid.at(n, grid.times[i], T, v)]));
    lifePlot("plot-life-temperature", "Leak rate against temperature over the life of the seal",
      { ...axis("temperature T (°C)", false), range: fitRange(x, false) }, curves, grid, key, limit, rows);
  }
}

function drawPlots(pred) {
  drawLife(pred);
  const p = { ...pred.plots };
  p.sets = p.sets.map(s => ({ ...s, label: setLabel(s) }));
  p.gaps = { ...p.gaps, labels: p.sets.map(s => s.label) };
  const rows = pred.json.results;
  const colour = curveColours();
  const { traces: leak, marks, bands } = leakCurves(p, rows, false, {}, colour);
  const pinned = Pins.curves(colour);
  const all = [...leak, ...pinned];
  const yr = fitRange(all.flatMap(t => t.y), true);
  // sealed points (no leak path: Q = 0) sit at the foot of the axis, in their curve's colour (nested: the later curves'
  // markers smaller, so that curves sealed at the same load all show); points below the axis (the axis spans 8 decades)
  // are open triangles there; points outside the theory (valid = NO) are crossed
  const foot = Math.pow(10, (yr ? yr[0] : 0) + 0.1);
  // a band's percentile sealed, or below the axis, runs along the foot: the median stays between its percentiles
  for (const t of bands) t.y = t.y.map(v => v === null ? null : v > foot ? v : foot);
  const ix = [], iy = [], legend = new Set();
  const key = (name, symbol) => {  // one legend entry per kind of marker, in grey
    if (legend.has(name)) return;
    legend.add(name);
    all.push({ x: [null], y: [null], name, type: "scatter", mode: "markers", marker: { symbol, size: 10, color: "#555" } });
  };
  marks.forEach((m, j) => {
    const sealed = [], below = [];
    m.x.forEach((x, i) => {
      const y = m.y[i];
      if (y === null || !(y > 0)) sealed.push(x);
      else if (y < foot) below.push(x);
      if (y > 0 && m.valid[i] === false) { ix.push(x); iy.push(Math.max(y, foot)); }
    });
    const size = Math.max(12 - 2 * j, 5);
    if (sealed.length) {
      key("sealed (no leak path), in the colour of its curve", "triangle-down");
      all.push({ x: sealed, y: sealed.map(() => foot), name: `${m.name}: sealed`, type: "scatter", mode: "markers", showlegend: false,
        marker: { symbol: "triangle-down", size, color: m.colour }, hovertemplate: "%{x:.4~g}: %{fullData.name}<extra></extra>" });
    }
    if (below.length) {
      key("below the axis (more than 8 decades under the top)", "triangle-down-open");
      all.push({ x: below, y: below.map(() => foot), name: `${m.name}: below the axis`, type: "scatter", mode: "markers", showlegend: false,
        marker: { symbol: "triangle-down-open", size, color: m.colour, line: { width: 2 } },
        hovertemplate: "%{x:.4~g}: %{fullData.name}<extra></extra>" });
    }
  });
  if (ix.length) all.push(outsideTheory(ix, iy));
  const c0 = p.leak[0] || { x: "squeeze_pressure" };
  const xa = X_AXES[c0.x] || X_AXES.profile_scale;
  const kinds = new Set(p.leak.map(c => c.gas));
  const ytitle = kinds.size > 1 ? "leak rate (the unit of each curve in its legend)" : leakTitle(c0.gas);
  // no point leaks (every one sealed): an axis of no numbers, its triangles at the foot (an auto-range put them at 10⁻³⁰,
  // mid-axis, as if Q were 10⁻³⁰)
  const yaxis = yr ? { ...axis(ytitle, true), range: yr }
    : { ...axis(`${ytitle}: 0 everywhere`, true), range: [0, 1], showticklabels: false };
  plot("plot-leak", all, "Leak rate", { ...axis(xa.title(), xa.log), range: fitRange(all.flatMap(t => t.x), xa.log) }, yaxis);
  plot("plot-psd", p.spectra.map(s => line(s.q, s.C, s.label)), "Power spectrum C(q)",
    { ...axis("wavevector q (1/m)", true), range: fitRange(p.spectra.flatMap(s => s.q), true, 12) },
    { ...axis("C(q) (m⁴)", true), range: fitRange(p.spectra.flatMap(s => s.C), true, 30) });
  plot("plot-area", p.sets.map(s => line(s.zeta, s.area, s.label)), "Contact area A(ζ)/A0",
    { ...axis("magnification ζ", true), range: fitRange(p.sets.flatMap(s => s.zeta), true, 12) }, axis("A(ζ)/A0", false));
  const lu = Units.name("length");
  const gaps = p.sets.map(s => line(s.zeta_gap, s.mean_gap.map(v => v === null ? null : Units.show(v, "length")), s.label));
  plot("plot-gap", gaps, "Mean separation ū(ζ)", { ...axis("magnification ζ", true), range: fitRange(p.sets.flatMap(s => s.zeta_gap), true, 12) },
    { ...axis(`ū(ζ) (${lu})`, true), range: fitRange(gaps.flatMap(t => t.y), true, 4) });
  const u = p.gaps.u.map(v => Units.show(v, "length"));
  plot("plot-gaps", p.gaps.density.map((d, i) => line(u, d, p.gaps.labels[i])), "Gap distribution u·P(u)",
    { ...axis(`gap u (${lu})`, true), range: fitRange(u, true, 6) }, axis("u·P(u)", false));
}

// ---------------------------------------------------------------- pinned results: their curves overlaid, their inputs compared
const Pins = {
  list: JSON.parse(sessionStorage.getItem("sealeak.pins") || "[]"),
  save() { sessionStorage.setItem("sealeak.pins", JSON.stringify(this.list)); },

  pin(state) {
    if (!state || !state.prediction) return;
    const p = state.prediction.plots;
    const n = this.list.length ? Math.max(...this.list.map(x => x.n)) + 1 : 1;
    const title = (state.prediction.json.cases[0] || {}).title || state.name;
    this.list.push({ n, title, name: state.name, fields: state.fields, rows: state.prediction.json.results.slice(0, 1),
      leak: p.leak.map(c => ({ label: c.label, x: c.x, gas: c.gas, squeeze_pressure: c.squeeze_pressure, leak_rate: c.leak_rate,
        leak_rate_effective_medium: c.leak_rate_effective_medium })) });
    this.save();
  },
  unpin(n) { this.list = this.list.filter(x => x.n !== n); this.save(); },

  // the pinned leak curves in the current units, dotted, named "#n title", in the colours after the live curves' (``colour``)
  curves(colour) {
    const out = [];
    for (const pin of this.list) {
      const { traces } = leakCurves({ leak: pin.leak.map(c => ({ ...c, label: `#${pin.n} ${short(pin.title)}` })) }, pin.rows, true,
        { line: { dash: "dot", width: 1.5 }, marker: { size: 4, symbol: "circle-open" }, opacity: 0.8 }, colour);
      out.push(...traces);
    }
    return out;
  },

  // the table: the first leak rate of each case, then every input in which the current case and the pinned ones differ
  table(state) {
    const box = $("#compare");
    if (!box) return;
    box.hidden = !this.list.length;
    if (!this.list.length) return;
    const cases = [{ n: 0, title: "current case", fields: state.fields || {}, rows: state.prediction ? state.prediction.json.results : [] }, ...this.list];
    const keys = [...new Set(cases.flatMap(c => Object.keys(c.fields)))].sort();
    const differ = keys.filter(k => new Set(cases.map(c => c.fields[k] ?? "")).size > 1);
    const first = c => {
      const r = c.rows[0] || {};
      const gas = r.leak_rate_pv !== undefined, si = gas ? r.leak_rate_pv : r.leak_rate, dim = gas ? "throughput" : "volume_flow";
      return typeof si === "number" ? `${fmt(Units.show(si, dim, c.rows), 4)} ${Units.name(dim)}` : "sealed";
    };
    const head = `<thead><tr><th>input</th>${cases.map(c => `<th title="${esc(c.title)}">${c.n ? `#${c.n} ` : ""}${esc(short(c.title))}${c.n ? ` <button class="secondary unpin" data-n="${c.n}" title="unpin">×</button>` : ""}</th>`).join("")}</tr></thead>`;
    const lead = `<tr class="lead"><td>leak rate at the first point</td>${cases.map(c => `<td>${esc(first(c))}</td>`).join("")}</tr>`;
    const body = differ.map(k => `<tr data-key="${esc(k)}"><td><code>${esc(k)}</code></td>${cases.map(c => `<td>${esc(c.fields[k] ?? "(default)")}</td>`).join("")}</tr>`).join("");
    $("#compare-table").innerHTML = head + `<tbody>${lead}${body || `<tr><td colspan="${cases.length + 1}" class="muted">the inputs are the same</td></tr>`}</tbody>`;
    $$("#compare-table .unpin").forEach(b => b.addEventListener("click", () => { this.unpin(Number(b.dataset.n)); refresh(); }));
  },
};

let lastState = null;

function refresh() {
  if (lastState && lastState.prediction) drawPrediction(lastState.prediction);
  if (lastState) Pins.table(lastState);
}

async function pagePrediction() {
  const both = $("#both-theories");
  $("#results").hidden = true;  // until a case has run (below)
  await Form.init(true, state => {
    const model = $('#case-form [name="theory.model"]');
    if (model) both.checked = model.value === "both";
    if (state.prediction) lastState = state;
    // while the case has an error the results shown are those of the last valid case: greyed out; before any (no case,
    // or one that never ran) none: no dangling "Leak rate Q at :", empty plots or downloads that answer an error
    $("#results").classList.toggle("stale", !!state.error);
    $("#results").hidden = !lastState;
    if (state.prediction) refresh();  // (shown first: a plot drawn hidden took Plotly's 700 px, past its cell)
  });
  for (const sel of $$("#units select")) {
    const dim = sel.dataset.dim;
    for (const u of Units.table[dim]) {
      const o = document.createElement("option");
      o.value = u.name; o.textContent = u.name;
      sel.appendChild(o);
    }
    sel.value = Units.name(dim);
    sel.addEventListener("change", () => { Units.choose(dim, sel.value); refresh(); });
  }
  $("#pin").addEventListener("click", () => { Pins.pin(lastState); refresh(); });
  let resized = null;  // a legend's rows follow the plot's width: drawn again once the window is resized
  window.addEventListener("resize", () => { clearTimeout(resized); resized = setTimeout(refresh, 250); });
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
  $("#surface-waiting").hidden = true;
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
  plot("plot-psd", traces, "C(q) (shaded: the reliable range of each file)", axis("wavevector q (1/m)", true),
    axis("C(q) (m⁴)", true), { shapes }, 290);
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
      : (j.state === "done" ? `<button class="secondary show" data-id="${j.id}">Show result</button> ` : "") +
        `<button class="secondary remove" data-id="${j.id}" title="delete this simulation and its results from the session">Remove</button>`;
    return `<tr data-job="${j.id}"><td>${j.id}</td><td>${esc(j.title)}</td><td>${esc(opts)}</td>
      <td class="state state-${j.state}">${j.state}${j.message && j.state !== "cancelled" ? `: ${esc(j.message)}` : ""}</td>
      <td><span class="progress"><div data-pct="${pct}"></div></span> ${j.total ? `${j.done}/${j.total} tasks` : ""}</td>
      <td>${j.elapsed} s</td><td>${action}</td></tr>`;
  }).join("") || '<tr><td colspan="7" class="muted">no simulation yet</td></tr>';
  $$("#jobs .progress > div").forEach(d => { d.style.width = `${d.dataset.pct}%`; });  // CSSOM: no style attribute (CSP)
  $$("#jobs .cancel").forEach(b => b.addEventListener("click", async () => {
    try { await api("POST", `/api/jobs/${b.dataset.id}/cancel`); } catch (e) { showMessage(e.message); }
    refreshJobs();
  }));
  $$("#jobs .remove").forEach(b => b.addEventListener("click", async () => {
    try { await api("DELETE", `/api/jobs/${b.dataset.id}`); } catch (e) { showMessage(e.message); }
    if (shownJob === b.dataset.id) { shownJob = null; $("#job-result").hidden = true; }
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
const PAGES = { case: pageCase, prediction: pagePrediction, surface: pageSurface, simulation: pageSimulation, help: pageHelp };
document.addEventListener("DOMContentLoaded", () => {
  markNav();
  // no form is ever submitted: each field is sent as it changes (no inline handlers: the pages' CSP forbids them)
  $$("form").forEach(f => f.addEventListener("submit", ev => ev.preventDefault()));
  const run = PAGES[document.body.dataset.page];
  // data-ready: the page has loaded what it shows (the browser tests wait for it)
  if (run) run().catch(e => showMessage(e.message)).finally(() => { document.body.dataset.ready = "1"; });
});
