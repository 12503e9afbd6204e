// SPDX-License-Identifier: Apache-2.0
// Drives a `coxswain report` page in headless Chromium (puppeteer-core, the system's chromium)
// as a reader would: the summary (mission, date, result, score) comes first; every plot draws;
// a mouse drag across one time plot zooms every time plot to the same span, the wheel zooms
// further, a double click shows the whole run again; the pointer's time is a cursor line on every
// time plot, values in the legends and the boat on the map; the map zooms with the wheel; the
// estimate before the start calibration is drawn apart from the track. No console error, no
// page error, no request leaves the file.
// Usage: node report_page_test.mjs REPORT.html EXPECT.json
//   EXPECT.json: {"score": true when the recording has the simulator judge's score,
//                 "calibration": true when the run calibrated at the start,
//                 "plan": true when the global planner made a path mid-run}
import puppeteer from "puppeteer-core";
import { readFile } from "node:fs/promises";
import { pathToFileURL } from "node:url";

const [page_file, expect_file] = process.argv.slice(2);
const expected = JSON.parse(await readFile(expect_file, "utf8"));
const problems = [];
const check = (ok, what) => {
  if (!ok) problems.push(what);
  console.log(`${ok ? "ok  " : "FAIL"} ${what}`);
};

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
         "--disable-background-networking", "--disable-component-update"],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 1000 });
  const console_errors = [];
  page.on("console", (m) => { if (m.type() === "error" || m.type() === "warning") console_errors.push(m.text()); });
  page.on("pageerror", (e) => console_errors.push(String(e)));
  const outside = [];
  page.on("request", (r) => { if (!r.url().startsWith("file:")) outside.push(r.url()); });
  await page.goto(pathToFileURL(page_file).href, { waitUntil: "load" });

  // The summary is the first thing under the heading, and says what a team asks first.
  const top = await page.evaluate(() => {
    const h1 = document.querySelector("h1");
    const summary = document.getElementById("summary");
    const rows = {};
    if (summary) for (const r of summary.rows) rows[r.cells[0].textContent] = r.cells[1].textContent;
    return { title: document.title, h1: h1 ? h1.textContent : "",
             next: h1 && h1.nextElementSibling ? h1.nextElementSibling.id : "", rows,
             error: document.getElementById("error").textContent };
  });
  check(top.next === "summary", `the summary table follows the heading (got "${top.next}")`);
  for (const key of ["mission", "date", "result", "score"]) {
    check(typeof top.rows[key] === "string" && top.rows[key].length > 0, `summary has a ${key}: ${top.rows[key]}`);
  }
  check(/^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC$/.test(top.rows.date || ""), "the date is a UTC date and time");
  check(top.title.includes(top.rows.date || "?"), `the title names the date: ${top.title}`);
  if (expected.score) {
    check(/^\d+\.\d\d s \(run /.test(top.rows.score || ""), "the score is the judge's, in seconds");
    check(/score \d+\.\d\d s|failed/.test(top.h1), `the heading gives the verdict: ${top.h1}`);
  }
  check(top.error === "", `no drawing error (${top.error})`);

  // Every plot drew something.
  const plots = await page.$$eval("svg.plot", (svgs) => svgs.map((s) => ({
    id: s.id, rendered: s.getAttribute("data-rendered"), points: +s.getAttribute("data-points"),
    t0: s.getAttribute("data-t0"), t1: s.getAttribute("data-t1"), time: s.classList.contains("time") })));
  check(plots.length >= 9, `${plots.length} plots on the page`);
  for (const p of plots) check(p.rendered === "true" && p.points > 0, `plot ${p.id} drew ${p.points} values`);
  const time_plots = plots.filter((p) => p.time);
  const full = [+time_plots[0].t0, +time_plots[0].t1];
  check(time_plots.length >= 8 && full[1] > full[0], `${time_plots.length} time plots share the view ${full}`);

  const views = async () => page.$$eval("svg.plot.time", (svgs) => svgs.map((s) => [+s.getAttribute("data-t0"), +s.getAttribute("data-t1")]));
  const same = (vs) => vs.every((v) => v[0] === vs[0][0] && v[1] === vs[0][1]);

  // A drag across the middle third of the heading plot zooms every time plot to that span.
  // Into the middle of the window first: the mouse acts only on what is on screen.
  const box_of = async (id) => {
    await page.evaluate((i) => document.getElementById(i).scrollIntoView({ block: "center" }), id);
    return (await page.$("#" + id)).boundingBox();
  };
  const box = await box_of("heading");
  const y = box.y + box.height / 2;
  await page.mouse.move(box.x + box.width * 0.4, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.55, y, { steps: 5 });
  await page.mouse.move(box.x + box.width * 0.7, y, { steps: 5 });
  await page.mouse.up();
  let v = await views();
  const span = v[0][1] - v[0][0];
  check(same(v), "every time plot shows the same span after the drag");
  check(span < (full[1] - full[0]) * 0.45 && v[0][0] > full[0], `the drag zoomed in to ${v[0]}`);
  const points_zoomed = await page.$eval("#heading", (s) => +s.getAttribute("data-points"));
  const points_full = plots.find((p) => p.id === "heading").points;
  check(points_zoomed < points_full, `fewer points drawn in the zoomed view (${points_zoomed} < ${points_full})`);

  // The wheel zooms in around the pointer.
  await page.mouse.move(box.x + box.width * 0.6, y);
  await page.mouse.wheel({ deltaY: -200 });
  await new Promise((r) => setTimeout(r, 100));
  v = await views();
  check(same(v) && v[0][1] - v[0][0] < span * 0.95, `the wheel zoomed in further to ${v[0]}`);

  // The cursor: a line on every time plot, values in the legends, the boat on the map.
  await page.mouse.move(box.x + box.width * 0.5, y + 2);
  const cursor = await page.evaluate(() => ({
    lines: [...document.querySelectorAll("svg.plot.time line.cursor")].map((l) => l.getAttribute("visibility")),
    xs: [...document.querySelectorAll("svg.plot.time line.cursor")].map((l) => +l.getAttribute("x1")),
    readout: document.getElementById("cursor-readout").textContent,
    legend: document.querySelector("#heading-legend .value").textContent,
    boat: document.querySelectorAll("#track circle.boat").length,
    plan: document.querySelectorAll("#track polyline.plan").length,
  }));
  check(cursor.lines.length === time_plots.length && cursor.lines.every((s) => s === "visible"),
        "a cursor line on every time plot");
  check(cursor.xs.every((x) => Math.abs(x - cursor.xs[0]) < 0.5), "the cursor lines sit at one time");
  check(/^t = [0-9.]+ s, state /.test(cursor.readout), `the readout names the time and state: ${cursor.readout}`);
  check(/^-?[0-9.]+$/.test(cursor.legend), `the heading legend shows the value at the cursor: ${cursor.legend}`);
  check(cursor.boat === 1, "the boat is on the map at the cursor");
  if (expected.plan) check(cursor.plan === 1, "the planner's path at the cursor is on the map");

  // A double click shows the whole run again.
  await page.mouse.click(box.x + box.width * 0.5, y, { clickCount: 2 });
  v = await views();
  check(same(v) && v[0][0] === full[0] && v[0][1] === full[1], `a double click resets to ${v[0]}`);

  // The map zooms with the wheel on its own.
  const track_box = await box_of("track");
  const scale0 = await page.$eval("#track", (s) => +s.getAttribute("data-scale"));
  await page.mouse.move(track_box.x + track_box.width / 2, track_box.y + track_box.height / 2);
  await page.mouse.wheel({ deltaY: -200 });
  await new Promise((r) => setTimeout(r, 100));
  const scale1 = await page.$eval("#track", (s) => +s.getAttribute("data-scale"));
  check(scale1 > scale0, `the map zoomed in (${scale0} -> ${scale1} px/m)`);

  if (expected.calibration) {
    const marks = await page.evaluate(() => ({
      precal: document.querySelectorAll("#track path.precalibration").length,
      line: document.querySelectorAll("#heading line.calibration").length,
    }));
    check(marks.precal === 1, "the estimate before the start calibration is drawn apart on the map");
    check(marks.line === 1, "the calibration is marked on the time plots");
  }
  check(console_errors.length === 0, `no console errors (${console_errors.join(" | ")})`);
  check(outside.length === 0, `no request leaves the file (${outside.join(" ")})`);
} finally {
  await browser.close();
}
if (problems.length > 0) {
  console.error(`${problems.length} problems`);
  process.exit(1);
}
console.log("report page: all good");
