"""The course report's Table I from Python: the rod canopy under 20, 200 and 2000 N
(studies/table1.toml), printed as a table and, when matplotlib is installed, plotted.

    python python/examples/table1.py [--out DIR] [--jobs N] [--quick]

The three 10 s flights take well under a minute on 2 cores and give the numbers of
docs/report-study.md's Table I. ``--quick`` runs 1 s flights of a coarser strip instead (a
smoke test, not those results). The plot, ``OUT/table1.png``, shows vz(t) of each case and the
terminal speed against the load.
"""

import argparse
import pathlib
import sys

import chute

REPO = pathlib.Path(__file__).resolve().parents[2]
STUDY = REPO / "studies" / "table1.toml"
COLUMNS = [
    ("case", "case", "{}"),
    ("load.weight_n", "load (N)", "{:g}"),
    ("terminal_velocity_mps", "v_t (m/s)", "{:.4g}"),
    ("time_to_terminal_s", "t_terminal (s)", "{:.3g}"),
    ("reached_terminal", "reached", "{}"),
    ("max_extended_height_m", "max height (m)", "{:.4g}"),
    ("force_balance_error", "force balance", "{:.2%}"),
]


def table(rows):
    """The rows as a Markdown table."""
    head = "| " + " | ".join(title for _, title, _ in COLUMNS) + " |"
    lines = [head, "|" + "---|" * len(COLUMNS)]
    for r in rows:
        cells = []
        for key, _, fmt in COLUMNS:
            v = r.get(key)
            cells.append("—" if v is None else fmt.format(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(rows, path):
    """vz(t) per case and |v_t| against W; False when matplotlib is not installed."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return False
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for r in rows:
        ts = chute.Result(r["out_dir"]).timeseries
        ax1.plot(ts["t_s"], ts["vz_mps"], label=f"load {r['load.weight_n']:g} N")
    ax1.set(xlabel="t (s)", ylabel="canopy vz (m/s)", title="descent velocity")
    ax1.legend()
    w = [r["load.weight_n"] for r in rows]
    v = [abs(r["terminal_velocity_mps"]) for r in rows]
    ax2.loglog(w, v, "o-")
    ax2.set(xlabel="load (N)", ylabel="|v_t| (m/s)", title="terminal speed")
    ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return True


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="runs/table1", help="study directory (default: %(default)s)")
    ap.add_argument("--jobs", type=int, default=None, help="cases in parallel (default: cores)")
    ap.add_argument("--quick", action="store_true", help="1 s flights of a 21-node strip")
    args = ap.parse_args(argv)
    quick = {"time.duration_s": 1.0, "canopy.nodes": 21} if args.quick else None
    rows = chute.study(STUDY, jobs=args.jobs, out=args.out, set=quick, force=True)
    print(table(rows))
    failed = [r["case"] for r in rows if r["status"] != "complete"]
    if failed:
        print(f"cases that did not complete: {', '.join(failed)}", file=sys.stderr)
        return 1
    png = pathlib.Path(args.out) / "table1.png"
    if plot(rows, png):
        print(f"plot: {png}")
    else:
        print("(install matplotlib for the plot)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
