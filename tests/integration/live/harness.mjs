// SPDX-License-Identifier: Apache-2.0
// What every live test script shares: ok/FAIL lines, waiting for a condition, and the daemon to
// kill when a check fails (so a failed test never leaves it running).
export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

let child = null;
/// The process `fail` kills before exiting.
export function killOnFail(proc) {
  child = proc;
}

export function fail(message) {
  console.error("FAIL: " + message);
  if (child && child.exitCode === null) child.kill("SIGKILL");
  process.exit(1);
}

export function check(cond, message) {
  if (!cond) fail(message);
  console.log("ok: " + message);
}

/// Polls `fn` every 50 ms until it returns something truthy (returned), or fails after timeoutMs.
export async function until(what, fn, timeoutMs = 15000) {
  const end = Date.now() + timeoutMs;
  for (;;) {
    const v = await fn();
    if (v) return v;
    if (Date.now() > end) fail("timed out waiting for " + what);
    await sleep(50);
  }
}
