#include "web/dashboard_page.hpp"

namespace mblab::web {

namespace {

// The values and counters come from /api/events once the page runs; the page itself holds none.
// Script and style are files of their own so that the Content-Security-Policy every answer
// carries can forbid inline script: markup injected into the page could not run.
// The empty icon keeps browsers from asking for /favicon.ico, a 404 in their console.
constexpr std::string_view kPage = R"html(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>mblab device</title>
<link rel="icon" href="data:,">
<link rel="stylesheet" href="/dashboard.css">
<script src="/dashboard.js" defer></script>
</head><body>
<h1>mblab device <span id="status">connecting...</span></h1>
<div>Connections: <b id="connections">-</b> &middot; answers/s: <b id="rate">-</b>
&middot; exceptions/s: <b id="exrate">-</b> &middot; mean answer time: <b id="latency">-</b> &middot;
<form id="tokenform">token for writes:
<input id="token" type="password" size="12" autocomplete="off"></form></div>
<section><h2>Data</h2>
<label>Unit <select id="unit"></select></label>
<label>Bank <select id="bank"><option>holding_registers</option><option>input_registers</option>
<option>coils</option><option>discrete_inputs</option></select></label>
<label>From <input id="start" type="number" min="0" max="65535" value="0" size="6"></label>
<button id="prev">&lt;</button><button id="next">&gt;</button>
<table id="values"><thead><tr><th>Address</th><th>Value</th><th>Name</th></tr></thead><tbody>
</tbody></table>
<h2>Typed points</h2><table id="points"><thead><tr><th>Address</th><th>Name</th><th>Type</th>
<th>Value</th><th>Trend</th></tr></thead><tbody></tbody></table>
<div id="message" class="err"></div></section>
<section><h2>Requests</h2><table id="requests"><thead><tr><th>Unit</th><th>Function</th>
<th>Requests</th><th>Exceptions</th><th>Requests/s</th></tr></thead><tbody></tbody></table>
<button id="reset">Reset counters</button>
<h2>Diagnostics (FC 08)</h2><table id="diagnostics"><tbody></tbody></table>
<h2>Event log (FC 0C, newest first)</h2><div id="log"></div></section>
<section><h2>Fault rules</h2><table id="faults"><thead><tr><th>On</th><th>Rule</th><th></th></tr>
</thead><tbody></tbody></table>
<form id="ruleform"><fieldset><legend>New rule</legend>
<label>Fault <select id="rule-action"><option value="exception">exception</option>
<option value="delay">delay</option><option value="drop">no answer (drop)</option>
<option value="garbage">garbage answer</option><option value="close">close the connection</option>
</select></label>
<label class="for-exception">code <select id="rule-exception">
<option value="1">01 illegal function</option><option value="2">02 illegal data address</option>
<option value="3">03 illegal data value</option>
<option value="4" selected>04 server device failure</option>
<option value="5">05 acknowledge</option><option value="6">06 server device busy</option>
<option value="8">08 memory parity error</option><option value="10">0A gateway path unavailable</option>
<option value="11">0B gateway target failed to respond</option></select></label>
<label class="for-delay">ms <input id="rule-delay" type="number" min="0" max="600000" value="1000"></label>
<label class="for-garbage">bytes <input id="rule-garbage" type="number" min="1" max="253" value="8">
</label><br>
<label>Function codes <input id="rule-functions" size="10" placeholder="all, or 3, 0x10"></label>
<label>Addresses <input id="rule-first" type="number" min="0" max="65535" placeholder="any"></label>
<label>to <input id="rule-last" type="number" min="0" max="65535" placeholder="any"></label><br>
<label>When <select id="rule-when"><option value="always">on every request</option>
<option value="every">on every Nth request</option><option value="probability">with probability</option>
</select></label>
<input id="rule-when-value" class="for-every for-probability" type="number" min="0" step="any">
<button id="add">Add rule</button> <span id="rule-error" class="err"></span>
</fieldset></form></section>
<section><h2>Traffic (newest first)</h2><table id="traffic"><thead><tr><th>Time</th>
<th>Client</th><th>Unit</th><th>Function</th><th>Request</th><th>Answer</th><th>&micro;s</th></tr>
</thead><tbody></tbody></table></section>
</body></html>
)html";

constexpr std::string_view kStyle = R"css(body{font:14px system-ui,sans-serif;margin:1em;color:#222}
h1{font-size:1.3em}h2{font-size:1.1em;margin-top:1.2em}
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#eee}input.v{width:6em;text-align:right}.err{color:#b00}
section{display:inline-block;vertical-align:top;margin-right:2em}
#tokenform{display:inline}
fieldset{margin-top:.5em}fieldset label{margin-right:.6em}fieldset input[type=number]{width:5.5em}
svg.trend{display:block}svg.trend polyline{fill:none;stroke:#26c;stroke-width:1.5}
)css";

constexpr std::string_view kScript = R"js("use strict";
const PAGE = 20;
const $ = id => document.getElementById(id);
let source = null, unitList = [];
// serve prints the page's address with its token after '#', which no request carries: it is kept
// for this tab and taken off the address bar.
const given = new URLSearchParams(location.hash.slice(1)).get("token");
if (given) { sessionStorage.setItem("mblab-token", given); history.replaceState(null, "", location.pathname); }
$("token").value = sessionStorage.getItem("mblab-token") || "";
$("token").onchange = () => sessionStorage.setItem("mblab-token", $("token").value);
$("tokenform").onsubmit = () => false;
function call(method, path, body) {
  const headers = {"Content-Type": "application/json"};
  if ($("token").value) headers.Authorization = "Bearer " + $("token").value;
  return fetch(path, {method, headers, body: body === undefined ? undefined : JSON.stringify(body)})
    .then(r => r.json().then(j => { if (!r.ok) throw new Error(j.error); $("message").textContent = ""; return j; }))
    .catch(e => { $("message").textContent = e.message; throw e; });
}
function hex(code) { return "0x" + code.toString(16).padStart(2, "0").toUpperCase(); }
function cell(row, text) { const td = row.insertCell(); td.textContent = text; return td; }
function unitPath() { return "/api/units/" + $("unit").value; }
// The name the profile gives the range that holds `address` in the bank shown.
function rangeName(address) {
  const unit = unitList.find(u => String(u.unit) === $("unit").value);
  const ranges = unit ? unit.banks[$("bank").value] || [] : [];
  const range = ranges.find(r => address >= r.start && address < r.start + r.count);
  return range ? range.name : "";
}
// The values of each point a behaviour moves, as the events brought them: up to a minute's trend
// at two events a second. Kept by the page alone, so a page opened later starts a trend of its own.
const TREND = 120, TREND_WIDTH = 120, TREND_HEIGHT = 22;
let trends = new Map();
function trendLine(values) {
  const svg = document.createElementNS("http://www.w3.org/2000/svg", "svg");
  svg.setAttribute("class", "trend");
  svg.setAttribute("width", TREND_WIDTH); svg.setAttribute("height", TREND_HEIGHT);
  const low = Math.min(...values), high = Math.max(...values), span = high - low || 1;
  // The values kept so far across the whole width, the newest at the right edge (a young trend
  // is legible at once, and settles at a minute wide); a constant one as a line across the middle.
  const step = TREND_WIDTH / (values.length - 1);
  const line = document.createElementNS(svg.namespaceURI, "polyline");
  line.setAttribute("points", values.map((v, i) => (i * step).toFixed(1) + "," +
    (high === low ? TREND_HEIGHT / 2 : TREND_HEIGHT - 1 - (v - low) * (TREND_HEIGHT - 2) / span).toFixed(1)).join(" "));
  const title = document.createElementNS(svg.namespaceURI, "title");
  title.textContent = "from " + low + " to " + high + " over the last " + values.length / 2 + " s";
  svg.append(title, line);
  return svg;
}
// Numbers the profile types (f32, u32 and the rest, in their word order), decoded by the server.
function showPoints(points) {
  const body = $("points").tBodies[0];
  body.innerHTML = "";
  for (const p of points || []) {
    const row = body.insertRow();
    const value = Number.isInteger(p.value) ? p.value : Number(p.value.toPrecision(7));
    [p.address, p.name, p.type + (p.type.endsWith("16") ? "" : " " + p.order), value].forEach(t => cell(row, t));
    const trend = row.insertCell();
    if (!p.moving) continue;
    const history = trends.get(p.address) || [];
    history.push(value);
    if (history.length > TREND) history.shift();
    trends.set(p.address, history);
    if (history.length > 1) trend.appendChild(trendLine(history));
  }
}
function showPage(page) {
  showPoints(page.points);
  const body = $("values").tBodies[0];
  if (body.rows.length !== page.values.length) {
    body.innerHTML = "";
    page.values.forEach((v, i) => {
      const row = body.insertRow();
      cell(row, page.start + i);
      const input = document.createElement("input");
      input.className = "v";
      input.onchange = () => call("PUT", unitPath() + "/" + $("bank").value + "/" + row.cells[0].textContent,
                                  {values: [Number(input.value)]});
      row.insertCell().appendChild(input);
      cell(row, "").style.textAlign = "left";
    });
  }
  page.values.forEach((v, i) => {
    const row = body.rows[i];
    row.cells[0].textContent = page.start + i;
    row.cells[2].textContent = rangeName(page.start + i);
    const input = row.cells[1].firstChild;
    if (document.activeElement !== input) input.value = v === null ? "" : v;
    input.disabled = v === null;
  });
}
// The counters of the last two seconds: a rate shows from the second event, half a second after
// the page opens, and follows a change in the traffic within two seconds.
const RATE_WINDOW = 2000;
let samples = [];
function perSecond(now, count, then) {
  const oldest = samples[0];
  return samples.length > 1 ? Math.round((count - then(oldest)) * 1000 / (now - oldest.time)) : "-";
}
function showCounters(c) {
  $("connections").textContent = c.connections;
  const now = performance.now(), pairs = {};
  for (const r of c.requests) pairs[r.unit + ":" + r.function] = r;
  const exceptions = c.requests.reduce((sum, r) => sum + r.exceptions, 0);
  // Counters reset (by the button or FC 08): the rates start again.
  if (samples.length && c.latency.count < samples[samples.length - 1].answers) samples = [];
  samples.push({time: now, answers: c.latency.count, exceptions, pairs});
  while (samples.length > 2 && now - samples[0].time > RATE_WINDOW) samples.shift();
  $("rate").textContent = perSecond(now, c.latency.count, s => s.answers);
  $("exrate").textContent = perSecond(now, exceptions, s => s.exceptions);
  $("latency").textContent = c.latency.count ? (1e6 * c.latency.sum_seconds / c.latency.count).toFixed(1) + " \u00b5s" : "-";
  const body = $("requests").tBodies[0];
  body.innerHTML = "";
  for (const r of c.requests) {
    const row = body.insertRow();
    const rate = perSecond(now, r.requests, s => (s.pairs[r.unit + ":" + r.function] || {requests: 0}).requests);
    [r.unit, hex(r.function), r.requests, r.exceptions, rate].forEach(t => cell(row, t));
  }
  const unit = c.units.find(u => String(u.unit) === $("unit").value) || c.units[0];
  const diag = $("diagnostics").tBodies[0];
  diag.innerHTML = "";
  for (const key of ["bus_messages", "bus_errors", "bus_exceptions", "server_messages", "no_response", "naks", "busy", "overruns", "event_count", "listen_only"]) {
    const row = diag.insertRow(); cell(row, key); cell(row, unit[key]);
  }
  $("log").textContent = unit.event_log.map(e => e.toString(16).padStart(2, "0")).join(" ") || "(empty)";
}
function loadRules() {
  call("GET", unitPath() + "/faults").then(rules => {
    const body = $("faults").tBodies[0];
    body.innerHTML = "";
    for (const rule of rules) {
      const row = body.insertRow();
      const box = document.createElement("input");
      box.type = "checkbox"; box.checked = rule.enabled;
      const spec = Object.assign({}, rule); delete spec.index; delete spec.enabled;
      box.onchange = () => call("PUT", unitPath() + "/faults/" + rule.index, Object.assign(spec, {enabled: box.checked})).then(loadRules);
      row.insertCell().appendChild(box);
      const text = cell(row, ruleText(spec));
      text.style.textAlign = "left"; text.title = JSON.stringify(spec);
      const del = document.createElement("button");
      del.textContent = "Remove";
      del.onclick = () => call("DELETE", unitPath() + "/faults/" + rule.index).then(loadRules);
      row.insertCell().appendChild(del);
    }
  }).catch(() => {});
}
function listen() {
  if (source) source.close();
  const start = Math.max(0, Math.min(65536 - PAGE, Number($("start").value) || 0));
  $("start").value = start;
  $("values").tBodies[0].innerHTML = "";
  trends = new Map();
  source = new EventSource("/api/events?unit=" + $("unit").value + "&bank=" + $("bank").value + "&start=" + start + "&count=" + PAGE);
  source.onopen = () => { $("status").textContent = "live"; };
  source.onerror = () => { $("status").textContent = "reconnecting..."; };
  source.onmessage = e => {
    const event = JSON.parse(e.data);
    if (event.page && event.page.values) showPage(event.page);
    showCounters(event.counters);
  };
}
$("unit").onchange = () => {
  const unit = unitList.find(u => String(u.unit) === $("unit").value);
  if (unit) $("bank").value = unit.start_bank;
  listen(); loadRules();
};
$("bank").onchange = $("start").onchange = listen;
$("prev").onclick = () => { $("start").value = Number($("start").value) - PAGE; listen(); };
$("next").onclick = () => { $("start").value = Number($("start").value) + PAGE; listen(); };
$("reset").onclick = () => call("POST", "/api/counters/reset").catch(() => {});
// A rule in words, as the table shows it (its JSON in the cell's title).
function ruleText(r) {
  const what = {exception: "exception " + hex(r.exception || 0), delay: "delay " + r.delay_ms + " ms",
                drop: "no answer", garbage: r.garbage_bytes + " garbage bytes", close: "close the connection"}[r.action];
  const on = r.functions ? "FC " + r.functions.map(hex).join(", ") : "every function";
  const at = !r.addresses ? "" : r.addresses[0] === r.addresses[1] ? ", address " + r.addresses[0]
                                 : ", addresses " + r.addresses[0] + " to " + r.addresses[1];
  const when = r.every ? ", 1 in " + r.every + " requests" : r.probability < 1 ? ", with probability " + r.probability : "";
  return what + " on " + on + at + when;
}
// The form's rule, held to the limits the server's schema sets (docs/profiles.md) so that a
// mistake is named beside the form before anything is sent; the server checks again.
function whole(id, name, low, high) {
  const text = $(id).value.trim();
  if ($(id).validity.badInput || !/^\d+$/.test(text) || Number(text) < low || Number(text) > high)
    throw new Error(name + ": give a whole number from " + low + " to " + high);
  return Number(text);
}
function ruleFromForm() {
  const rule = {action: $("rule-action").value};
  if (rule.action === "exception") rule.exception = Number($("rule-exception").value);
  if (rule.action === "delay") rule.delay_ms = whole("rule-delay", "delay in ms", 0, 600000);
  if (rule.action === "garbage") rule.garbage_bytes = whole("rule-garbage", "garbage bytes", 1, 253);
  const codes = $("rule-functions").value.split(/[\s,]+/).filter(Boolean);
  if (codes.length) {
    rule.functions = codes.map(c => {
      const code = /^0x[0-9a-f]{1,2}$/i.test(c) ? parseInt(c, 16) : /^\d{1,3}$/.test(c) ? Number(c) : 0;
      if (code < 1 || code > 127) throw new Error("function codes: " + c + " is not a function code from 1 to 127");
      return code;
    });
    if (new Set(rule.functions).size !== codes.length) throw new Error("function codes: one is given twice");
  }
  const first = $("rule-first").value || $("rule-first").validity.badInput, last = $("rule-last").value || $("rule-last").validity.badInput;
  if (first || last) {
    const from = whole(first ? "rule-first" : "rule-last", "addresses", 0, 65535);
    const to = last ? whole("rule-last", "addresses", 0, 65535) : from;
    if (from > to) throw new Error("addresses: the first, " + from + ", is past the last, " + to);
    rule.addresses = [from, to];
  }
  const when = $("rule-when").value;
  if (when === "every") rule.every = whole("rule-when-value", "every Nth request", 1, 1000000);
  if (when === "probability") {
    const p = $("rule-when-value").value.trim() === "" ? NaN : Number($("rule-when-value").value);
    if (!(p >= 0 && p <= 1)) throw new Error("probability: give a number from 0 to 1");
    rule.probability = p;
  }
  return rule;
}
// Only the fields the chosen fault and frequency take are shown.
function ruleFields() {
  const shown = ["for-" + $("rule-action").value, "for-" + $("rule-when").value];
  for (const e of document.querySelectorAll("#ruleform [class*='for-']")) e.hidden = !shown.some(c => e.classList.contains(c));
  $("rule-when-value").placeholder = $("rule-when").value === "every" ? "N" : "0 to 1";
}
$("rule-action").onchange = $("rule-when").onchange = ruleFields;
ruleFields();
$("ruleform").onsubmit = event => {
  event.preventDefault();
  let rule;
  try { rule = ruleFromForm(); } catch (e) { $("rule-error").textContent = e.message; return; }
  $("rule-error").textContent = "";
  call("POST", unitPath() + "/faults", rule).then(loadRules).catch(e => { $("rule-error").textContent = e.message; });
};
// The requests and answers the server logs (GET /api/traffic), asked for once a second: only the
// ones after the last seen come, and the table keeps as many as the server's ring.
let trafficLast = 0;
const TRAFFIC_ROWS = 200;
function requestText(t) {
  const parts = [];
  if (t.sub_function !== undefined) parts.push("sub " + t.sub_function);
  if (t.address !== undefined) parts.push("address " + t.address);
  if (t.quantity !== undefined) parts.push("quantity " + t.quantity);
  if (t.undecoded) parts.push("does not decode: " + t.undecoded);
  return parts.join(", ");
}
function answerText(t) {
  if (t.answer === "exception") return "exception " + t.exception.code + " (" + t.exception.name + ")";
  if (t.answer === "none") return "no answer";
  if (t.answer === "close") return "connection closed";
  return t.values ? t.values.join(" ") + (t.more_values ? " ..." : "") : "ok";
}
function pollTraffic() {
  fetch("/api/traffic?after=" + trafficLast).then(r => r.ok ? r.json() : null).then(t => {
    if (!t) return;
    trafficLast = t.last;
    const body = $("traffic").tBodies[0];
    for (const e of t.entries) {
      const row = body.insertRow(0);
      [e.time.slice(11, 23), e.peer, e.unit, e.name, requestText(e), answerText(e), e.latency_us].forEach(x => cell(row, x));
      if (e.answer === "exception") row.className = "err";
    }
    while (body.rows.length > TRAFFIC_ROWS) body.deleteRow(-1);
  }).catch(() => {}).finally(() => setTimeout(pollTraffic, 1000));
}
pollTraffic();
call("GET", "/api/units").then(units => {
  unitList = units;
  // The profile chooses the bank shown first: where its values move, or its first range.
  if (units.length) $("bank").value = units[0].start_bank;
  for (const u of units) {
    const option = document.createElement("option");
    option.value = u.unit; option.textContent = u.unit + (u.name ? " " + u.name : "");
    $("unit").appendChild(option);
  }
  listen(); loadRules();
});
)js";

}  // namespace

std::string_view dashboard_page() {
    return kPage;
}

std::string_view dashboard_style() {
    return kStyle;
}

std::string_view dashboard_script() {
    return kScript;
}

}  // namespace mblab::web
