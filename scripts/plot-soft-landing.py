#!/usr/bin/env python3
"""Draw docs/img/soft-landing-cargo.svg: touchdown speed against trigger height, from the
tables of `chute study studies/soft-landing.toml` (50 Hz altimeter, the scenario's mesh) and
`chute study studies/soft-landing-mesh.toml` (1 kHz altimeter, three meshes).

Usage: scripts/plot-soft-landing.py [RUNS_DIR] [OUT_SVG]
(defaults: runs/, docs/img/soft-landing-cargo.svg). Standard library only.
"""
import csv
import sys
from pathlib import Path

runs = Path(sys.argv[1] if len(sys.argv) > 1 else "runs")
out = Path(sys.argv[2] if len(sys.argv) > 2 else "docs/img/soft-landing-cargo.svg")


def rows(path):
    with open(path, newline="") as f:
        return [r for r in csv.DictReader(f) if r["status"] == "complete"]


def speed(r):
    return abs(float(r["landing_velocity_mps"]))


series = []  # (label, colour, dashed, [(height, speed)])
shipped = rows(runs / "soft-landing" / "study.csv")
unpulled = [speed(r) for r in shipped if not r.get("control[0].below_m")]
pts = sorted((float(r["control[0].below_m"]), speed(r)) for r in shipped if r.get("control[0].below_m"))
series.append(("50 Hz altimeter, 0.2 m mesh (the study)", "#1f77b4", False, pts))
mesh = rows(runs / "soft-landing-mesh" / "study.csv")
for level, colour in [("0.3", "#d62728"), ("0.2", "#2ca02c"), ("0.15", "#9467bd")]:
    pts = sorted(
        (float(r["control[0].below_m"]), speed(r))
        for r in mesh
        if r["canopy.edge_length_m"] == level
    )
    series.append((f"1 kHz altimeter, {level} m mesh", colour, True, pts))

W, H, L, R, T, B = 720, 420, 70, 20, 20, 60
x0, x1, y0, y1 = 0.0, 3.2, 0.0, 6.0


def sx(x):
    return L + (x - x0) / (x1 - x0) * (W - L - R)


def sy(y):
    return H - B - (y - y0) / (y1 - y0) * (H - T - B)


svg = [
    f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
    f'<rect width="{W}" height="{H}" fill="white"/>',
]
for i in range(0, 7):
    y = float(i)
    svg.append(f'<line x1="{L}" y1="{sy(y):.1f}" x2="{W - R}" y2="{sy(y):.1f}" stroke="#ddd"/>')
    svg.append(f'<text x="{L - 8}" y="{sy(y) + 4:.1f}" text-anchor="end">{i}</text>')
for i in range(0, 7):
    x = 0.5 * i
    svg.append(f'<line x1="{sx(x):.1f}" y1="{T}" x2="{sx(x):.1f}" y2="{H - B}" stroke="#ddd"/>')
    svg.append(f'<text x="{sx(x):.1f}" y="{H - B + 16}" text-anchor="middle">{x:g}</text>')
svg.append(f'<text x="{(L + W - R) / 2}" y="{H - 18}" text-anchor="middle">trigger height below_m (m)</text>')
svg.append(
    f'<text x="18" y="{(T + H - B) / 2}" text-anchor="middle" transform="rotate(-90 18 {(T + H - B) / 2})">touchdown speed (m/s)</text>'
)
if unpulled:
    y = sy(unpulled[0])
    svg.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="black" stroke-dasharray="2,3"/>')
    svg.append(f'<text x="{sx(1.1):.1f}" y="{y - 5:.1f}">unpulled {unpulled[0]:.2f} m/s</text>')
for k, (label, colour, dashed, pts) in enumerate(series):
    path = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in pts)
    dash = ' stroke-dasharray="5,3"' if dashed else ""
    svg.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="1.5"{dash}/>')
    for x, y in pts:
        svg.append(f'<circle cx="{sx(x):.1f}" cy="{sy(y):.1f}" r="2.5" fill="{colour}"/>')
    ly = sy(1.8) + 16 * k  # lower right: empty there
    svg.append(f'<line x1="{W - 300}" y1="{ly - 4}" x2="{W - 275}" y2="{ly - 4}" stroke="{colour}" stroke-width="2"{dash}/>')
    svg.append(f'<text x="{W - 268}" y="{ly}">{label}</text>')
svg.append("</svg>")
out.write_text("\n".join(svg) + "\n")
print(f"wrote {out}")
