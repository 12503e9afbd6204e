// SPDX-License-Identifier: Apache-2.0
// The status page of a daemon whose live.token is empty (as shipped): /api/status says the
// controls are disabled, why and how to enable them, and the page, rendered in headless Chromium,
// shows it and disables its buttons. Chromium is optional: without it only the API is checked.
// Usage: node controls_test.mjs COXSWAIN_EXE SOURCE_DIR WORK_DIR
import { spawn, spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import { check, killOnFail, until } from "./harness.mjs";

const [exe, srcDir, work] = process.argv.slice(2);
let daemon = null;

fs.rmSync(work, { recursive: true, force: true });
fs.mkdirSync(work, { recursive: true });
const shipped = fs.readFileSync(path.join(srcDir, "config/devices.yaml"), "utf8");
check(/token: ""/.test(shipped), "the shipped devices.yaml has no token");
const devices = shipped
  .replaceAll("/dev/", path.join(work, "absent") + "/")
  .replace("http_port: 8765", "http_port: 0");
fs.writeFileSync(path.join(work, "devices.yaml"), devices);
const logDir = path.join(work, "runs");
daemon = spawn(exe, ["--devices", path.join(work, "devices.yaml"), "--log-dir", logDir, "run",
  "--run-for-s", "30", "--no-record"], { stdio: ["ignore", "ignore", "inherit"] });
killOnFail(daemon);
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
const s = await (await fetch(base + "/api/status")).json();
check(s.controls && s.controls.enabled === false, "the status says the controls are disabled");
check(/no token/.test(s.controls.why) && /live\.token/.test(s.controls.how),
  `it says why and how to enable them (${s.controls.how})`);

const chromium = spawnSync("sh", ["-c", "command -v chromium"], { encoding: "utf8" });
if (chromium.status !== 0) {
  console.log("SKIP (partly): chromium is not installed; the rendered page was not checked");
} else {
  const dom = spawnSync("timeout", ["60", "chromium", "--headless", "--no-sandbox",
    "--disable-gpu", "--disable-dev-shm-usage", "--disable-background-networking",
    "--disable-component-update", "--no-first-run", `--user-data-dir=${work}/chromium-profile`,
    "--virtual-time-budget=3000", "--dump-dom", base + "/"], { encoding: "utf8" });
  check(dom.status === 0, "chromium rendered the status page");
  check(/<div id="controls" class="bad">Controls disabled: no token is configured[^<]*live\.token/
    .test(dom.stdout), "the page says the controls are disabled and how to enable them");
  const buttons = dom.stdout.match(/<button[^>]*>/g) || [];
  check(buttons.length >= 4 && buttons.every((b) => /disabled/.test(b)),
    `its ${buttons.length} buttons are disabled`);
}

daemon.kill("SIGTERM");
const code = await until("the daemon to stop",
  () => daemon.exitCode !== null ? { c: daemon.exitCode } : null);
check(code.c === 0, "daemon exits 0 on SIGTERM");
console.log("PASS");
