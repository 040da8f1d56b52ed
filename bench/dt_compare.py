"""Compares shape-study runs at several time steps (see dt-study.sh): per shape and quantity,
the mean with its 95 % interval (normal, 1.96 standard errors) and the two-sample
Kolmogorov-Smirnov statistic D of each time step against the finest, with the 5 % critical
value c = 1.358 * sqrt((n + m) / (n m)). Standard library only."""
import csv
import json
import math
import sys
from collections import defaultdict


def per_rock(path, downhill, origin):
    """Per rock: run-out along the fall line, lateral end offset, largest recorded energy (kJ)."""
    rows = defaultdict(list)
    with open(path) as f:
        for r in csv.DictReader(f):
            rows[int(r["rock_id"])].append(r)
    ux, uy = downhill
    out = []
    for rs in rows.values():
        x0, y0 = float(rs[0]["x_m"]), float(rs[0]["y_m"])
        x1, y1 = float(rs[-1]["x_m"]), float(rs[-1]["y_m"])
        dx, dy = x1 - x0, y1 - y0
        e = max(float(r["e_trans_j"]) + float(r["e_rot_j"]) for r in rs) / 1e3
        out.append((dx * ux + dy * uy, ux * dy - uy * dx, e))
    return out


def ks(a, b):
    a, b = sorted(a), sorted(b)
    i = j = 0
    d = 0.0
    while i < len(a) and j < len(b):
        if a[i] <= b[j]:
            i += 1
        else:
            j += 1
        d = max(d, abs(i / len(a) - j / len(b)))
    return d


def mean_ci(v):
    m = sum(v) / len(v)
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1))
    h = 1.96 * sd / math.sqrt(len(v))
    return m, m - h, m + h


def main():
    out, dts = sys.argv[1], sys.argv[2:]
    study = json.load(open(f"{out}/dt_{dts[0]}/study.json"))
    line = study["fall_line"]
    shapes = [s["shape"] for s in study["shapes"]]
    names = ["run-out (m)", "lateral end (m)", "max energy (kJ)"]
    print("| shape | quantity | " + " | ".join(f"dt {float(d)*1e3:g} ms" for d in dts)
          + " | KS D vs finest (critical 5 %) |")
    print("|---|---|" + "--:|" * len(dts) + "---|")
    for shape in shapes:
        data = {d: per_rock(f"{out}/dt_{d}/{shape}/trajectories.csv", line["downhill"],
                            line["origin_m"]) for d in dts}
        for k, name in enumerate(names):
            cols = []
            for d in dts:
                m, lo, hi = mean_ci([r[k] for r in data[d]])
                cols.append(f"{m:.1f} [{lo:.1f}, {hi:.1f}]")
            tests = []
            a = [r[k] for r in data[dts[0]]]
            for d in dts[1:]:
                b = [r[k] for r in data[d]]
                c = 1.358 * math.sqrt((len(a) + len(b)) / (len(a) * len(b)))
                tests.append(f"{float(d)*1e3:g} ms: {ks(a, b):.3f} ({c:.3f})")
            print(f"| {shape} | {name} | " + " | ".join(cols) + " | " + "; ".join(tests) + " |")


if __name__ == "__main__":
    main()
