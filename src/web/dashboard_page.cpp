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
&middot; mean answer time: <b id="latency">-</b> &middot;
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
<th>Value</th></tr></thead><tbody></tbody></table>
<div id="message" class="err"></div></section>
<section><h2>Requests</h2><table id="requests"><thead><tr><th>Unit</th><th>Function</th>
<th>Requests</th><th>Exceptions</th></tr></thead><tbody></tbody></table>
<button id="reset">Reset counters</button>
<h2>Diagnostics (FC 08)</h2><table id="diagnostics"><tbody></tbody></table>
<h2>Event log (FC 0C, newest first)</h2><div id="log"></div></section>
<section><h2>Fault rules</h2><table id="faults"><thead><tr><th>On</th><th>Rule</th><th></th></tr>
</thead><tbody></tbody></table>
<p><input id="newrule" size="40" value='{"action":"exception","exception":4,"functions":[3]}'>
<button id="add">Add rule</button></p></section>
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
)css";

constexpr std::string_view kScript = R"js("use strict";
const PAGE = 20;
const $ = id => document.getElementById(id);
let source = null, lastTotal = null, lastTime = 0, unitList = [];
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
function cell(row, text) { const td = row.insertCell(); td.textContent = text; return td; }
function unitPath() { return "/api/units/" + $("unit").value; }
// The name the profile gives the range that holds `address` in the bank shown.
function rangeName(address) {
  const unit = unitList.find(u => String(u.unit) === $("unit").value);
  const ranges = unit ? unit.banks[$("bank").value] || [] : [];
  const range = ranges.find(r => address >= r.start && address < r.start + r.count);
  return range ? range.name : "";
}
// Numbers the profile types (f32, u32 and the rest, in their word order), decoded by the server.
function showPoints(points) {
  const body = $("points").tBodies[0];
  body.innerHTML = "";
  for (const p of points || []) {
    const row = body.insertRow();
    const value = Number.isInteger(p.value) ? p.value : Number(p.value.toPrecision(7));
    [p.address, p.name, p.type + (p.type.endsWith("16") ? "" : " " + p.order), value].forEach(t => cell(row, t));
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
function showCounters(c) {
  $("connections").textContent = c.connections;
  const now = performance.now();
  if (lastTotal !== null && now > lastTime) {
    $("rate").textContent = Math.round((c.latency.count - lastTotal) * 1000 / (now - lastTime));
  }
  lastTotal = c.latency.count; lastTime = now;
  $("latency").textContent = c.latency.count ? (1e6 * c.latency.sum_seconds / c.latency.count).toFixed(1) + " \u00b5s" : "-";
  const body = $("requests").tBodies[0];
  body.innerHTML = "";
  for (const r of c.requests) {
    const row = body.insertRow();
    [r.unit, "0x" + r.function.toString(16).padStart(2, "0").toUpperCase(), r.requests, r.exceptions].forEach(t => cell(row, t));
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
      cell(row, JSON.stringify(spec)).style.textAlign = "left";
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
$("add").onclick = () => {
  let rule;
  try { rule = JSON.parse($("newrule").value); } catch (e) { $("message").textContent = "the rule is not valid JSON"; return; }
  call("POST", unitPath() + "/faults", rule).then(loadRules).catch(() => {});
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
