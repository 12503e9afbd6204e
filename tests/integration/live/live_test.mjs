// SPDX-License-Identifier: Apache-2.0
// End-to-end check of the daemon's control interface and live view with the reference client
// (@foxglove/ws-protocol over `ws`) and Node's fetch: starts `coxswain run` with every device
// absent, then drives the status page, the token-protected buttons, `coxswain ctl`, the Foxglove
// channels (subscribe, receive, unsubscribe, throttled rate) and the parameter interface (heading
// PID, avoidance, speed schedule, vision HSV boxes), then replays the run's recording with the
// live changes in it.
// Usage: node live_test.mjs COXSWAIN_EXE SOURCE_DIR WORK_DIR
import { spawn, spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import wsProtocol from "@foxglove/ws-protocol";
import WebSocket from "ws";
import { check, fail, killOnFail, sleep, until } from "./harness.mjs";

const { FoxgloveClient } = wsProtocol;

const [exe, srcDir, work] = process.argv.slice(2);
const TOKEN = "shore-test-token-1234";

fs.rmSync(work, { recursive: true, force: true });
fs.mkdirSync(work, { recursive: true });
let devices = fs.readFileSync(path.join(srcDir, "config/devices.yaml"), "utf8");
devices = devices
  .replaceAll("/dev/", path.join(work, "absent") + "/")
  .replace("http_port: 8765", "http_port: 0")
  .replace('token: ""', `token: "${TOKEN}"`);
fs.writeFileSync(path.join(work, "devices.yaml"), devices);
const logDir = path.join(work, "runs");
let daemon = spawn(exe, ["--devices", path.join(work, "devices.yaml"), "--log-dir", logDir,
  "run", "--run-for-s", "60", "--target", "red", "triangle"],
  { stdio: ["ignore", "inherit", "inherit"] });
killOnFail(daemon);
daemon.on("exit", (code) => console.log(`daemon exited with ${code}`));

const runDir = await until("the run directory", () => {
  const runs = fs.existsSync(logDir) ? fs.readdirSync(logDir) : [];
  return runs.length === 1 ? path.join(logDir, runs[0]) : null;
});
const port = await until("live.port", () => {
  const p = path.join(runDir, "live.port");
  return fs.existsSync(p) && fs.readFileSync(p, "utf8").trim() !== ""
    ? Number(fs.readFileSync(p, "utf8").trim()) : null;
});
const base = `http://127.0.0.1:${port}`;

// ---- status page and HTTP API ----
const page = await fetch(base + "/");
const html = await page.text();
check(page.status === 200 && page.headers.get("content-type").startsWith("text/html"),
  "GET / serves HTML");
check(html.includes("<!DOCTYPE html>") && html.includes("/api/") && !/src="http/.test(html),
  "the page is self-contained and posts to /api/");
const status = async () => (await fetch(base + "/api/status")).json();
let s = await until("a first tick in the status", async () => {
  const v = await status();
  return v.tick > 0 ? v : null;
});
check(typeof s.state_path === "string" && s.state_path.length > 0, `state path '${s.state_path}'`);
check(s.devices.lidar.state !== "running" && s.devices_ok === false,
  "absent devices are reported unhealthy");
check(s.operator.target_colour === "red" && s.operator.target_shape === "triangle",
  "--target reached the store");
check(s.controls && s.controls.enabled === true, "the status says the controls are enabled");
const post = (cmd, token, body) => fetch(base + "/api/" + cmd, {
  method: "POST", body: JSON.stringify(body || {}),
  headers: token === undefined ? {} : { "X-Coxswain-Token": token } });
check((await post("hold")).status === 401, "a button without the token is refused");
check((await post("hold", TOKEN.slice(0, -1) + "X")).status === 401, "a wrong token is refused");
check((await post("hold", TOKEN)).status === 200, "hold with the token is accepted");
s = await status();
check(s.operator.hold === true && s.operator.hold_count === 1, "hold reached the store");
check((await post("target", TOKEN, { colour: "blue", shape: "circle" })).status === 200,
  "target from the page");
check((await post("target", TOKEN, { colour: "mauve", shape: "circle" })).status === 400,
  "an unknown colour is refused");
s = await status();
check(s.operator.target_colour === "blue" && s.operator.target_shape === "circle",
  "the page's target reached the store");

// ---- coxswain ctl over the control socket ----
const sock = path.join(runDir, "control.sock");
check((fs.statSync(sock).mode & 0o777) === 0o660, "control socket mode 0660");
const ctl = (...args) => spawnSync(exe, ["ctl", "--socket", sock, ...args], { encoding: "utf8" });
let r = ctl("resume");
check(r.status === 0 && JSON.parse(r.stdout).ok === true, "ctl resume");
r = ctl("target", "green", "cross");
check(r.status === 0, "ctl target green cross");
r = ctl("status");
const ctlStatus = JSON.parse(r.stdout);
check(r.status === 0 && ctlStatus.operator.hold === false &&
  ctlStatus.operator.target_colour === "green", "ctl status shows resume and the new target");
r = ctl("target", "green");
check(r.status !== 0, "ctl refuses a malformed command");
r = spawnSync(exe, ["--log-dir", logDir, "ctl", "status"], { encoding: "utf8" });
check(r.status === 0 && JSON.parse(r.stdout).state_path !== undefined,
  "ctl finds the newest run's socket by itself");

// ---- Foxglove WebSocket ----
// A browser page of another origin is refused at the handshake, even with the token.
const evil = new WebSocket(`ws://127.0.0.1:${port}/?token=${TOKEN}`,
  [FoxgloveClient.SUPPORTED_SUBPROTOCOL], { origin: "http://evil.example" });
const evilResult = await new Promise((resolve) => {
  evil.on("open", () => resolve("open"));
  evil.on("unexpected-response", (_req, res) => resolve(res.statusCode));
  evil.on("error", () => resolve("error"));
});
check(evilResult === 403, `a cross-origin WebSocket is refused (${evilResult})`);
// Live tuning needs the token in the URL (Foxglove can only pass it there).
const ws = new WebSocket(`ws://127.0.0.1:${port}/?token=${TOKEN}`,
  [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const received = new Map();  // subscription id -> [{timestamp, json}]
let serverInfo = null;
let channels = [];
const statuses = [];
let lastParams = null;
client.on("serverInfo", (i) => { serverInfo = i; });
client.on("advertise", (c) => { channels = channels.concat(c); });
client.on("status", (m) => statuses.push(m));
// Every answer by its request id too: a later message must not hide the one a step waits for.
const paramsById = new Map();
client.on("parameterValues", (p) => {
  lastParams = p;
  if (p.id) paramsById.set(p.id, p);
});
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const text = new TextDecoder().decode(data);
  if (!received.has(subscriptionId)) received.set(subscriptionId, []);
  received.get(subscriptionId).push({ timestamp, at: Date.now(), json: JSON.parse(text) });
});
client.on("error", (e) => fail("websocket error " + e));
await until("serverInfo and advertise", () => serverInfo && channels.length >= 5);
check(ws.protocol === "foxglove.websocket.v1", "subprotocol foxglove.websocket.v1");
check(serverInfo.capabilities.includes("parameters"), "capability 'parameters'");
const byTopic = Object.fromEntries(channels.map((c) => [c.topic, c]));
for (const [topic, schema] of [["/tf", "foxglove.FrameTransform"],
  ["/viz/scene", "foxglove.SceneUpdate"], ["/viz/scan", "foxglove.LaserScan"],
  ["/viz/fix", "foxglove.LocationFix"], ["/log", "foxglove.Log"]]) {
  check(byTopic[topic] && byTopic[topic].schemaName === schema &&
    byTopic[topic].encoding === "json" && JSON.parse(byTopic[topic].schema).type === "object",
    `advertised ${topic} as ${schema}`);
}
const tfSub = client.subscribe(byTopic["/tf"].id);
const sceneSub = client.subscribe(byTopic["/viz/scene"].id);
const logSub = client.subscribe(byTopic["/log"].id);
await until("/tf and /viz/scene messages", () =>
  (received.get(tfSub) || []).length >= 5 && (received.get(sceneSub) || []).length >= 2);
const tf = received.get(tfSub)[0].json;
check(tf.parent_frame_id === "map" && tf.child_frame_id === "boat", "/tf is map -> boat");
check(Array.isArray(received.get(sceneSub)[0].json.entities), "/viz/scene holds entities");
// Throttled: the tick runs at 50 Hz, the live view sends at most 10 Hz (+ slack for bursts).
const t0 = Date.now();
const n0 = received.get(tfSub).length;
await sleep(2000);
const rate = (received.get(tfSub).length - n0) / ((Date.now() - t0) / 1000);
check(rate > 2 && rate <= 13, `/tf throttled to ${rate.toFixed(1)} Hz`);
client.unsubscribe(tfSub);
await sleep(500);
const afterUnsub = received.get(tfSub).length;
await sleep(1000);
check(received.get(tfSub).length === afterUnsub, "no /tf after unsubscribe");

// ---- parameters ----
lastParams = null;
paramsById.clear();
client.getParameters([], "all");
await until("parameterValues", () => (lastParams = paramsById.get("all") ?? null));
const kp = lastParams.parameters.find((p) => p.name === "heading_pid.kp_per_deg");
check(kp && typeof kp.value === "number", `heading_pid.kp_per_deg = ${kp && kp.value}`);
check(lastParams.parameters.some((p) => p.name === "clustering.group_gap_m"),
  "clustering parameters exposed");
const wanted = kp.value === 0.05 ? 0.06 : 0.05;
lastParams = null;
paramsById.clear();
client.setParameters([{ name: "heading_pid.kp_per_deg", value: wanted }], "set1");
const set1 = await until("the answer to the set", () => paramsById.get("set1"));
check(set1.parameters[0].value === wanted,
  `the set is answered with the value the tick applied (${set1.parameters[0].value})`);
await until("the new gain applied by the tick", async () => {
  lastParams = null;
  paramsById.clear();
  client.getParameters(["heading_pid.kp_per_deg"], "poll");
  await until("poll answer", () => (lastParams = paramsById.get("poll") ?? null));
  return lastParams.parameters[0].value === wanted;
});
check(true, `heading_pid.kp_per_deg applied as ${wanted}`);
await until("the parameter request on /log", () =>
  (received.get(logSub) || []).some((m) => /kp_per_deg/.test(m.json.message)));
check(true, "the parameter request was published on /log");
client.setParameters([{ name: "heading_pid.kp_per_deg", value: 5.0 }], "bad");
await until("an error status for an out-of-range value", () =>
  statuses.some((m) => m.level === 2 && /kp_per_deg/.test(m.message)));
lastParams = null;
paramsById.clear();
client.getParameters(["heading_pid.kp_per_deg"], "after");
await until("answer", () => (lastParams = paramsById.get("after") ?? null));
check(lastParams.parameters[0].value === wanted, "the rejected value was not applied");

// Avoidance, speed schedule and the vision HSV boxes, like the team's trackbars.
const value = (params, name) => (params.find((p) => p.name === name) || {}).value;
lastParams = null;
paramsById.clear();
client.getParameters([], "all2");
await until("parameterValues", () => (lastParams = paramsById.get("all2") ?? null));
const all = lastParams.parameters;
check(["selection", "score", "risk_bin"].includes(value(all, "avoidance.strategy")),
  `an enumeration is its name (avoidance.strategy = ${value(all, "avoidance.strategy")})`);
for (const name of ["avoidance.clearance_m", "avoidance.detection_range_m",
  "speed.max_thrust_frac", "speed.rise_per_s", "vision.red.h_min", "vision.red.s_min",
  "vision.black.v_max", "vision.purple.h_max"]) {
  check(typeof value(all, name) === "number", `${name} exposed (${value(all, name)})`);
}
const clearance = value(all, "avoidance.clearance_m") === 0.5 ? 0.55 : 0.5;
const redSat = value(all, "vision.red.s_min") === 120 ? 121 : 120;
const maxThrust = value(all, "speed.max_thrust_frac") === 0.8 ? 0.85 : 0.8;
client.setParameters([{ name: "avoidance.clearance_m", value: clearance },
  { name: "vision.red.s_min", value: redSat },
  { name: "speed.max_thrust_frac", value: maxThrust }], "set2");
await until("the avoidance, vision and speed values in force", async () => {
  lastParams = null;
  paramsById.clear();
  client.getParameters(["avoidance.clearance_m", "vision.red.s_min", "speed.max_thrust_frac"],
    "poll2");
  await until("poll answer", () => (lastParams = paramsById.get("poll2") ?? null));
  return value(lastParams.parameters, "avoidance.clearance_m") === clearance &&
    value(lastParams.parameters, "vision.red.s_min") === redSat &&
    value(lastParams.parameters, "speed.max_thrust_frac") === maxThrust;
});
check(true, `avoidance.clearance_m ${clearance}, vision.red.s_min ${redSat}, ` +
  `speed.max_thrust_frac ${maxThrust} applied by the tick`);
// Validated as a set: a minimum range above the detection range, a saturation floor above its
// ceiling, a fractional hue are refused and change nothing.
const detection = value(all, "avoidance.detection_range_m");
statuses.length = 0;
client.setParameters([{ name: "avoidance.min_detection_range_m", value: detection + 1.0 }], "bad2");
await until("an error status for the avoidance range", () =>
  statuses.some((m) => m.level === 2 && /min_detection_range_m/.test(m.message)));
client.setParameters([{ name: "vision.red.s_min", value: 256 }], "bad3");
await until("an error status for the saturation", () =>
  statuses.some((m) => m.level === 2 && /vision.red.s_min/.test(m.message)));
client.setParameters([{ name: "vision.red.h_min", value: 170.5 }], "bad4");
await until("an error status for a fractional hue", () =>
  statuses.some((m) => m.level === 2 && /whole number/.test(m.message)));
lastParams = null;
paramsById.clear();
client.getParameters(["avoidance.min_detection_range_m", "vision.red.s_min"], "after2");
await until("answer", () => (lastParams = paramsById.get("after2") ?? null));
check(value(lastParams.parameters, "vision.red.s_min") === redSat &&
  value(lastParams.parameters, "avoidance.min_detection_range_m") ===
    value(all, "avoidance.min_detection_range_m"), "the refused values were not applied");
client.close();

// ---- shutdown ----
daemon.kill("SIGTERM");
const code = await until("the daemon to stop", () => daemon.exitCode !== null ? { c: daemon.exitCode } : null);
check(code.c === 0, "daemon exits 0 on SIGTERM");
check(!fs.existsSync(sock), "the control socket is removed at exit");
const log = fs.readFileSync(path.join(runDir, "coxswain.log"), "utf8");
check(/live: tunable parameters applied/.test(log), "the parameter change is in the log");
check(/control: hold \(from status page\)/.test(log), "operator commands are logged");

// The recording holds both applied sets (/params) and replays bit for bit with them.
const replayed = spawnSync(exe, ["replay", path.join(runDir, "run.mcap")], { encoding: "utf8" });
if (replayed.status !== 0 || !/identical/.test(replayed.stdout)) {
  fail("coxswain replay of the run:\n" + replayed.stdout + replayed.stderr);
}
check(true, "coxswain replay of the run is identical");
check(/2 live parameter sets applied at tick \d+ \d+/.test(replayed.stdout),
  "replay applied the two recorded parameter sets");
console.log("PASS");
