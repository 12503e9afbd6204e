#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Mission-parameter tuner: an Optuna study over named mission parameters, each trial a
`coxswain-sim batch` on tuning seeds scored as the contest scores (time + penalties, a failed run
priced at the time limit), shared by any number of workers through Optuna's storage, and a final
report that checks the best parameters against the shipped ones on held-out seeds.

  tune.py worker  ... run trials (start one per core, per machine, or per Slurm array task)
  tune.py report  ... re-check the best trials, evaluate tuned vs shipped on held-out seeds,
                      write the overlay file and a markdown table

Parameter ranges come from the parameter table (`coxswain config params --json`: a JSON array of
{"key", "type", "min", "max", "default", "values", ...}); a search range may be narrowed per
parameter on the command line (KEY:MIN:MAX). Trial parameters reach the simulator as
`coxswain-sim batch --set KEY=VALUE`. Standard library, optuna and yaml only (Debian:
python3-optuna, python3-yaml).
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import time
import warnings

import optuna
import yaml

# JournalStorage and constant_liar are marked experimental in Debian 12's Optuna 3.1.
warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)

# ---------------------------------------------------------------------------------------------
# Parameters


def parse_seed_range(text):
    """'1-200' or '1-100,150-160' -> sorted list of seeds."""
    seeds = set()
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        if "-" in part:
            lo, hi = part.split("-", 1)
            lo, hi = int(lo), int(hi)
            if lo > hi or lo < 0:
                raise ValueError(f"bad seed range {part}")
            seeds.update(range(lo, hi + 1))
        else:
            seeds.add(int(part))
    return sorted(seeds)


def contiguous_blocks(seeds):
    """Sorted seeds -> [(seed0, runs)] covering exactly those seeds."""
    blocks = []
    for s in sorted(seeds):
        if blocks and blocks[-1][0] + blocks[-1][1] == s:
            blocks[-1] = (blocks[-1][0], blocks[-1][1] + 1)
        else:
            blocks.append((s, 1))
    return blocks


class Param:
    """One searched parameter: its table entry and the range searched."""

    # The table's type names (`coxswain config params --json` says number/integer/boolean).
    TYPES = {"double": "double", "number": "double", "real": "double", "int": "int",
             "integer": "int", "bool": "bool", "boolean": "bool", "enum": "enum"}

    def __init__(self, entry, lo=None, hi=None):
        self.key = entry["key"]
        if entry.get("type", "double") not in self.TYPES:
            raise ValueError(f"{self.key}: a {entry.get('type')} parameter cannot be searched")
        self.type = self.TYPES[entry.get("type", "double")]
        self.default = entry.get("default")
        self.values = entry.get("values")
        self.unit = entry.get("unit", "")
        if self.type in ("double", "int"):
            self.lo = float(entry["min"]) if lo is None else lo
            self.hi = float(entry["max"]) if hi is None else hi
            if not (float(entry["min"]) <= self.lo < self.hi <= float(entry["max"])):
                raise ValueError(
                    f"{self.key}: search range {self.lo}..{self.hi} outside the table's "
                    f"{entry['min']}..{entry['max']}")
        elif self.type == "enum" and not self.values:
            raise ValueError(f"{self.key}: an enum without values")

    def suggest(self, trial):
        if self.type == "double":
            return trial.suggest_float(self.key, self.lo, self.hi)
        if self.type == "int":
            return trial.suggest_int(self.key, int(math.ceil(self.lo)), int(math.floor(self.hi)))
        if self.type == "bool":
            return trial.suggest_categorical(self.key, [False, True])
        return trial.suggest_categorical(self.key, list(self.values))

    def as_number(self, value):
        """What `--set` takes: numbers; booleans 0/1; enums their index in the table's list."""
        if self.type == "bool":
            return 1 if value else 0
        if self.type == "enum":
            return self.values.index(value)
        return value


def load_params(params_json, specs):
    """specs: ['key', 'key:lo:hi', ...] -> [Param]."""
    with open(params_json, encoding="utf-8") as f:
        table = json.load(f)
    if not isinstance(table, list):
        raise ValueError(f"{params_json}: expected a JSON array of parameters")
    # Mission parameters only, when the table covers several file kinds ("kind": "mission").
    by_key = {e["key"]: e for e in table
              if isinstance(e, dict) and "key" in e and e.get("kind", "mission") == "mission"}
    out = []
    for spec in specs:
        parts = spec.split(":")
        key = parts[0]
        if key not in by_key:
            raise ValueError(f"{key}: not in {params_json}")
        if len(parts) == 3:
            out.append(Param(by_key[key], float(parts[1]), float(parts[2])))
        elif len(parts) == 1:
            out.append(Param(by_key[key]))
        else:
            raise ValueError(f"{spec}: expected KEY or KEY:MIN:MAX")
    return out


def set_args(values, params):
    args = []
    for p in params:
        if p.key in values:
            args += ["--set", f"{p.key}={p.as_number(values[p.key])}"]
    return args


# ---------------------------------------------------------------------------------------------
# Batches


def run_batch(args, seeds, extra, jobs, max_time=None):
    """Runs coxswain-sim batch over exactly `seeds`; returns the run lines by seed. `max_time`
    stops hopeless runs early (a failure is still priced at the contest's time limit)."""
    lines = {}
    for seed0, runs in contiguous_blocks(seeds):
        cmd = [args.sim, "batch", "--seed0", str(seed0), "--runs", str(runs), "--jobs",
               str(jobs)]
        if args.course:
            cmd += ["--course", args.course]
        else:
            cmd += ["--kind", args.kind]
        if args.mission:
            cmd += ["--mission", args.mission]
        if args.no_camera:
            cmd.append("--no-camera")
        for f in args.set_file or []:
            cmd += ["--set-file", f]
        if max_time:
            cmd += ["--max-time", str(max_time)]
        cmd += extra
        if args.nice:
            cmd = ["nice", "-n", str(args.nice)] + cmd
        done = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed ({done.returncode}): {done.stderr}")
        for text in done.stdout.splitlines():
            j = json.loads(text)
            if not j.get("summary"):
                lines[j["seed"]] = j
    missing = set(seeds) - set(lines)
    if missing:
        raise RuntimeError(f"runs missing from the batch: {sorted(missing)[:5]}")
    return lines


def read_lines_file(path, seeds):
    """Run lines of a batch already run (e.g. the shipped values on the held-out seeds, run while
    the study was running); must hold exactly `seeds`."""
    lines = {}
    with open(path, encoding="utf-8") as f:
        for text in f:
            if text.strip():
                j = json.loads(text)
                if not j.get("summary"):
                    lines[j["seed"]] = j
    if set(lines) != set(seeds):
        raise RuntimeError(f"{path} does not hold exactly the held-out seeds")
    return lines


def mean_score(lines):
    return sum(j["contest_score_s"] for j in lines.values()) / max(1, len(lines))


def trial_seeds(pool, runs, trial_number, study_seed):
    """A fresh window of `runs` consecutive seeds of the tuning pool per trial (reproducible from
    the trial number), so no trial is judged on the seeds every other trial saw and TPE does not
    fit a handful of seeds; consecutive, so one batch process sails them (generated courses of
    neighbouring seeds are unrelated)."""
    rng = random.Random(study_seed * 1_000_003 + trial_number)
    n = min(runs, len(pool))
    start = rng.randrange(0, len(pool) - n + 1)
    return pool[start:start + n]


# ---------------------------------------------------------------------------------------------
# Storage


def make_storage(url):
    """'journal:PATH' (a journal file, shared folders included: it locks by symlink) or an RDB
    URL (sqlite:///file.db, postgresql://...)."""
    if url.startswith("journal:"):
        path = url[len("journal:"):]
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        return optuna.storages.JournalStorage(optuna.storages.JournalFileStorage(path))
    return url


def open_study(args, create):
    storage = make_storage(args.storage)
    sampler = optuna.samplers.TPESampler(seed=None, n_startup_trials=args.startup_trials,
                                         constant_liar=True)
    if create:
        return optuna.create_study(study_name=args.study, storage=storage, direction="minimize",
                                   sampler=sampler, load_if_exists=True)
    return optuna.load_study(study_name=args.study, storage=storage, sampler=sampler)


# ---------------------------------------------------------------------------------------------
# Commands


def cmd_worker(args):
    params = load_params(args.params_json, args.param)
    pool = parse_seed_range(args.tuning_seeds)
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = open_study(args, create=True)
    # The shipped values as the first trial (once per study), so the search starts from them and
    # the study shows what they score on the same footing.
    if args.enqueue_shipped and not study.trials:
        shipped = {p.key: p.default for p in params if p.default is not None}
        study.enqueue_trial(shipped, skip_if_exists=True)

    def objective(trial):
        values = {p.key: p.suggest(trial) for p in params}
        seeds = trial_seeds(pool, args.runs, trial.number, args.study_seed)
        t0 = time.time()
        lines = run_batch(args, seeds, set_args(values, params), args.jobs, args.max_time)
        score = mean_score(lines)
        passed = sum(1 for j in lines.values() if j.get("passed"))
        clean = sum(1 for j in lines.values() if j.get("collisions", 0) == 0)
        trial.set_user_attr("seeds", seeds)
        trial.set_user_attr("passed", passed)
        trial.set_user_attr("clean", clean)
        trial.set_user_attr("seconds", round(time.time() - t0, 1))
        print(f"trial {trial.number}: {score:.2f} s ({passed}/{len(seeds)} passed, "
              f"{clean} clean) {values}", flush=True)
        return score

    # Stop when the study as a whole has max_trials finished trials (several workers share it).
    def enough(study_, _trial):
        finished = [t for t in study_.trials if t.state == optuna.trial.TrialState.COMPLETE]
        if len(finished) >= args.max_trials:
            study_.stop()

    # A trial whose batch failed (e.g. a set the engines reject) is recorded as failed; the worker
    # goes on.
    study.optimize(objective, n_trials=args.trials, callbacks=[enough], catch=(RuntimeError,))


def summarize(lines):
    values = list(lines.values())
    n = max(1, len(values))
    passed = [j for j in values if j.get("passed")]
    times = sorted(j["elapsed_s"] for j in passed)

    def pct(v, p):
        if not v:
            return float("nan")
        i = p * (len(v) - 1)
        lo, hi = math.floor(i), math.ceil(i)
        return v[lo] + (v[hi] - v[lo]) * (i - lo)

    return {
        "runs": len(values),
        "success": len(passed) / n,
        "clean": sum(1 for j in values if j.get("collisions", 0) == 0 and "error" not in j) / n,
        "collisions": sum(j.get("collisions", 0) for j in values),
        "score_mean": mean_score(lines),
        "time_p50": pct(times, 0.5),
        "time_p90": pct(times, 0.9),
    }


def cmd_report(args):
    params = load_params(args.params_json, args.param)
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = open_study(args, create=False)
    done = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
    if not done:
        sys.exit("no finished trials")
    done.sort(key=lambda t: t.value)
    # A trial's value comes from a handful of seeds: the lowest is partly luck. Re-check the
    # best few (and the shipped values) on more tuning seeds and keep the best of those.
    recheck_seeds = parse_seed_range(args.recheck_seeds)
    # "shipped" is the mission file as it is (no --set at all), whatever the table's defaults.
    candidates = [("shipped", None)] + [(f"trial {t.number}", t.params)
                                        for t in done[:args.top]]
    rechecked = []
    for name, values in candidates:
        lines = run_batch(args, recheck_seeds, set_args(values or {}, params), args.jobs,
                          args.max_time)
        s = summarize(lines)
        rechecked.append((s["score_mean"], name, values, s))
        print(f"re-check {name}: {s['score_mean']:.2f} s on {len(recheck_seeds)} tuning seeds",
              flush=True)
    rechecked.sort(key=lambda r: r[0])
    best_score, best_name, best, _ = rechecked[0]
    shipped_won = best is None
    if shipped_won:
        print("the shipped values re-checked best; the table still compares the best trial")
        best_score, best_name, best, _ = next(r for r in rechecked if r[2] is not None)
    # Held-out seeds: neither the trials nor the re-check saw them.
    held = parse_seed_range(args.heldout_seeds)
    if set(held) & (set(parse_seed_range(args.tuning_seeds)) | set(recheck_seeds)):
        sys.exit("held-out seeds overlap the tuning seeds")
    tuned_lines = run_batch(args, held, set_args(best, params), args.jobs)
    if args.shipped_lines:
        shipped_lines = read_lines_file(args.shipped_lines, held)
    else:
        shipped_lines = run_batch(args, held, [], args.jobs)
    tuned, base = summarize(tuned_lines), summarize(shipped_lines)
    better = sum(1 for s in held
                 if tuned_lines[s]["contest_score_s"] < shipped_lines[s]["contest_score_s"] - 1e-9)
    worse = sum(1 for s in held
                if tuned_lines[s]["contest_score_s"] > shipped_lines[s]["contest_score_s"] + 1e-9)

    overlay = {p.key: p.as_number(best[p.key]) for p in params if p.key in best}
    with open(args.overlay, "w", encoding="utf-8") as f:
        f.write(f"# Tuned by tools/tune/tune.py, study {args.study} ({len(done)} trials, "
                f"{best_name}); apply with coxswain-sim batch --set-file\n")
        yaml.safe_dump(overlay, f, sort_keys=True)

    where = f"--course {args.course}" if args.course else f"--kind {args.kind}"
    md = []
    per_trial = len(done[0].user_attrs.get("seeds", [])) or args.runs
    verdict = (f"the shipped values scored best there ({rechecked[0][0]:.1f} s), the best trial "
               f"({best_name}, {best_score:.1f} s) is compared anyway" if shipped_won else
               f"{best_name} kept ({best_score:.1f} s mean contest score there)")
    md.append(f"Study `{args.study}`: {len(done)} trials, each {per_trial} runs on consecutive "
              f"seeds drawn from {args.tuning_seeds} ({where}); the best {args.top} re-checked "
              f"with the shipped values on seeds {args.recheck_seeds}: {verdict}. Held-out seeds "
              f"{args.heldout_seeds} ({len(held)} runs each), seen by neither:")
    md.append("")
    md.append("| parameters | runs | success | no-contact runs | collisions | "
              "mean contest score | time p50 | time p90 |")
    md.append("|---|---|---|---|---|---|---|---|")
    for label, s in (("shipped", base), ("tuned", tuned)):
        md.append(f"| {label} | {s['runs']} | {100 * s['success']:.1f}% | "
                  f"{100 * s['clean']:.1f}% | {s['collisions']} | {s['score_mean']:.1f} s | "
                  f"{s['time_p50']:.1f} s | {s['time_p90']:.1f} s |")
    md.append("")
    md.append(f"Per seed, tuned vs shipped contest score: {better} better, {worse} worse, "
              f"{len(held) - better - worse} equal.")
    md.append("")
    md.append("| parameter | table default | tuned | searched |")
    md.append("|---|---|---|---|")
    for p in params:
        rng = f"{p.lo:g} .. {p.hi:g}" if p.type in ("double", "int") else ", ".join(
            map(str, p.values or [False, True]))
        tv = best.get(p.key)
        tv = f"{tv:.4g}" if isinstance(tv, float) else tv
        md.append(f"| `{p.key}` | {p.default} | {tv} | {rng} {p.unit} |")
    text = "\n".join(md) + "\n"
    with open(args.table, "w", encoding="utf-8") as f:
        f.write(text)
    print(text)
    with open(args.table + ".json", "w", encoding="utf-8") as f:
        json.dump({"shipped": base, "tuned": tuned, "best": best, "best_name": best_name,
                   "better": better, "worse": worse, "trials": len(done),
                   "rechecked": [{"name": n, "score": sc, "summary": s}
                                 for sc, n, _, s in rechecked]}, f, indent=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)

    def common(p):
        p.add_argument("--storage", required=True,
                       help="journal:PATH (a file on a shared folder) or an RDB URL")
        p.add_argument("--study", required=True, help="study name")
        p.add_argument("--params-json", required=True,
                       help="parameter table (coxswain config params --json)")
        p.add_argument("--param", action="append", required=True,
                       help="KEY or KEY:MIN:MAX to search (repeatable)")
        p.add_argument("--sim", default="coxswain-sim", help="the coxswain-sim program")
        p.add_argument("--kind", default="obstacle", help="generated course kind")
        p.add_argument("--course", help="a course file instead of generated courses")
        p.add_argument("--mission", help="mission file (default: the kind's shipped one)")
        p.add_argument("--set-file", action="append", help="overlay applied before the trial's")
        p.add_argument("--no-camera", action="store_true", help="no camera frames (faster)")
        p.add_argument("--tuning-seeds", default="1-200", help="the seeds trials draw from")
        p.add_argument("--runs", type=int, default=10, help="runs per trial")
        p.add_argument("--jobs", type=int, default=1, help="threads per batch")
        p.add_argument("--max-time", type=float, default=None,
                       help="hard stop per run in trials and the re-check, simulated seconds "
                            "(failures are still priced at the contest's limit; the held-out "
                            "runs always sail to the simulator's default)")
        p.add_argument("--nice", type=int, default=0, help="run batches under nice -n")
        p.add_argument("--study-seed", type=int, default=1, help="seeds the per-trial seed draw")
        p.add_argument("--startup-trials", type=int, default=20,
                       help="random trials before TPE takes over")

    w = sub.add_parser("worker", help="run trials of the shared study")
    common(w)
    w.add_argument("--trials", type=int, default=None, help="trials this worker runs at most")
    w.add_argument("--max-trials", type=int, default=200,
                   help="stop once the study has this many finished trials")
    w.add_argument("--enqueue-shipped", action="store_true", default=True,
                   help=argparse.SUPPRESS)
    w.set_defaults(func=cmd_worker)

    r = sub.add_parser("report", help="re-check the best, evaluate on held-out seeds, write "
                                      "the overlay and the table")
    common(r)
    r.add_argument("--top", type=int, default=5, help="best trials re-checked")
    r.add_argument("--recheck-seeds", default="1-40", help="tuning seeds of the re-check")
    r.add_argument("--heldout-seeds", default="20001-20200", help="seeds of the final table")
    r.add_argument("--shipped-lines",
                   help="JSON lines of the shipped values on the held-out seeds, already run "
                        "(same batch options, no --set)")
    r.add_argument("--overlay", default="tuned.yaml", help="overlay file written")
    r.add_argument("--table", default="tuned.md", help="markdown table written")
    r.set_defaults(func=cmd_report)

    args = ap.parse_args()
    args.func(args)


if __name__ == "__main__":
    main()
