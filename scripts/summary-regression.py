#!/usr/bin/env python3
"""Bit-for-bit regression of every bundled scenario's summary.

A refactoring step must not change physics. This script runs each scenario in
`scenarios/` with the given `chute` binary and compares every numeric and boolean
field of `summary.json` (except wall-clock and memory fields, the `solver` times
included; its counts are compared) with a recorded baseline, to the last digit.

    scripts/summary-regression.py record  BASELINE.json [--chute target/release/chute]
    scripts/summary-regression.py compare BASELINE.json [--chute target/release/chute]

It takes a few minutes (the report's cases are 10 s flights), so it is a
before/after check for refactors, not part of `cargo test`.
"""
import argparse, json, pathlib, subprocess, sys, tempfile

# Fields that measure the machine, not the physics.
VOLATILE = {"wall_time_s", "peak_rss_mib", "timings", "ms_per_step"}
# The wall times of the `solver` object (docs/outputs.md §solver); its counts are compared.
SOLVER_TIMES = {"assembly_s", "factor_s", "solve_s"}


def physics(summary):
    out = {k: v for k, v in summary.items() if k not in VOLATILE}
    if isinstance(out.get("solver"), dict):
        out["solver"] = {k: v for k, v in out["solver"].items() if k not in SOLVER_TIMES}
    return out


def run_all(chute, only):
    root = pathlib.Path(__file__).resolve().parent.parent
    out = {}
    for s in sorted((root / "scenarios").glob("*.toml")):
        if only and s.stem not in only:
            continue
        with tempfile.TemporaryDirectory() as d:
            r = subprocess.run([chute, "run", str(s), "--out", d + "/run", "-q", "--no-viewer"],
                               capture_output=True, text=True)
            if r.returncode != 0 and "--no-viewer" in r.stderr:
                r = subprocess.run([chute, "run", str(s), "--out", d + "/run", "-q"],
                                   capture_output=True, text=True)
            if r.returncode not in (0, 3):
                sys.exit(f"{s.name}: exit {r.returncode}\n{r.stderr}")
            out[s.stem] = physics(json.loads(pathlib.Path(d, "run", "summary.json").read_text()))
        print(f"ran {s.stem}", file=sys.stderr)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mode", choices=["record", "compare"])
    ap.add_argument("baseline")
    ap.add_argument("--chute", default="target/release/chute")
    ap.add_argument("--only", nargs="*", default=[])
    a = ap.parse_args()
    now = run_all(a.chute, a.only)
    path = pathlib.Path(a.baseline)
    if a.mode == "record":
        path.write_text(json.dumps(now, indent=1, sort_keys=True) + "\n")
        return
    base = json.loads(path.read_text())
    bad = 0
    for name, got in now.items():
        want = base.get(name)
        if want is None:
            print(f"{name}: not in baseline")
            continue
        for k in sorted(set(want) | set(got)):
            if k in want and k in got and want[k] != got[k]:
                print(f"{name}.{k}: {want[k]!r} (baseline) vs {got[k]!r} (now)")
                bad += 1
            elif k not in got:
                print(f"{name}.{k}: missing now")
                bad += 1
    print("identical" if not bad else f"{bad} field(s) differ")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
