"""Plots and tables of `cloth_sim_bench accuracy` (accuracy.csv, accuracy_reference.csv).

accuracy.png: per case, RMS position error at 1 s (or the first sample time; over the cloth's diagonal)
against ms per 1/60 s frame, log-log, one colour per solver, its Pareto front as a line.
accuracy.md: the reference's own error (step halving), the Pareto front of every case, and the
best configuration within half a frame (8.3 ms) and within a frame (16.7 ms). Every table has a
"floor" row: the spread between the two references (h and h / 2) at each time, below which no
error can be told apart. A BDF2 run's solver is "<solver>/bdf2", drawn in its solver's colour
with a hollow marker and a dashed front.
"""
import math
import os
from collections import defaultdict

import matplotlib.pyplot as plt

FRAME_MS = 1000.0 / 60.0


def _num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


def _pct(v):
    return "-" if math.isnan(v) else f"{100 * v:.2f} %"


def label(r):
    it = "conv" if r["iterations"] == "0" else r["iterations"]
    return f"{r['solver']} s{r['substeps']} i{it}"


def _configs(rows):
    """case -> label -> {time: row}, only runs that reached the end without a rollback."""
    out = defaultdict(lambda: defaultdict(dict))
    for r in rows:
        if r["status"] == "ok" and r["time"]:
            out[r["case"]][label(r)][_num(r["time"])] = r
    return out


def com_time(times):
    """The time of the centre-of-mass column: 1 s when sampled, else the last."""
    return 1.0 if 1.0 in times else max(times)


def style_of(style, solver):
    """(colour, marker, line style): a "<solver>/<integrator>" run takes its solver's colour."""
    base, _, integrator = solver.partition("/")
    colour, marker = style.get(base, ("black", "."))
    return (colour, marker, "--") if integrator else (colour, marker, "-")


def primary_time(by_label):
    """The time the fronts are drawn at: 1 s (the bar's) when sampled, else the first."""
    times = {t for by_t in by_label.values() for t in by_t}
    return 1.0 if 1.0 in times else min(times)


def pareto(points):
    """The (ms, error, ...) tuples not beaten in both ms and error, by increasing ms."""
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (p[0], p[1])):
        if p[1] < best:
            front.append(p)
            best = p[1]
    return front


def plot(rows, path, style):
    configs = _configs(rows)
    cases = list(configs)
    if not cases:
        return
    cols = min(3, len(cases))
    nrows = (len(cases) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(5 * cols, 4 * nrows), squeeze=False)
    for ax, case in zip(axes.flat, cases):
        t0 = primary_time(configs[case])
        by_solver = defaultdict(list)
        for by_t in configs[case].values():
            r = by_t.get(t0)
            if r:
                by_solver[r["solver"]].append((_num(r["frame_ms_median"]), _num(r["rms_error"])))
        for solver, pts in sorted(by_solver.items()):
            colour, marker, line = style_of(style, solver)
            ax.scatter(*zip(*pts), marker=marker, s=14, alpha=0.5,
                       **({"edgecolors": colour, "facecolors": "none"} if line == "--" else {"color": colour}))
            front = pareto(pts)
            ax.plot(*zip(*front), color=colour, ls=line, label=solver)
        ax.axvline(FRAME_MS, color="gray", ls="--", lw=0.8)
        ax.axvline(FRAME_MS / 2, color="gray", ls=":", lw=0.8)
        ax.axhline(0.02, color="red", ls=":", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{case}, t = {t0:g} s")
        ax.set_xlabel("ms per 1/60 s frame")
        ax.set_ylabel("RMS error / diagonal")
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(cases):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _row(name, by_t, times):
    first = by_t[min(by_t)]
    cells = [name, f"{_num(first['frame_ms_median']):.2f} ({_num(first['frame_ms_p10']):.2f}-"
                   f"{_num(first['frame_ms_p90']):.2f})"]
    for t in times:
        r = by_t.get(t)
        cells.append(_pct(_num(r["rms_error"])) if r else "-")
    r = by_t.get(com_time(times))
    cells.append(_pct(_num(r.get("com_error"))) if r else "-")
    last = by_t[max(by_t)]
    cells += [f"{_num(last['energy_ratio']):.3f}",
              f"{_num(last['max_strain']) / _num(last['ref_max_strain']):.2f}"]
    return "| " + " | ".join(cells) + " |"


def _floor_row(refs, times):
    """The references' spread (h against h / 2) at each time: the floor of the table."""
    by_t = {_num(r["time"]): r for r in refs}
    cells = ["floor (reference h vs h/2)", "-"]
    cells += [_pct(_num(by_t[t]["floor_rms"])) if t in by_t else "-" for t in times]
    r = by_t.get(com_time(times))
    cells += [_pct(_num(r.get("floor_com"))) if r else "-", "-", "-"]
    return "| " + " | ".join(cells) + " |"


def tables(rows, refs):
    configs = _configs(rows)
    times = sorted({_num(r["time"]) for r in rows if r["time"]})
    head = ("| configuration | ms per frame (p10-p90) | " +
            " | ".join(f"RMS at {t:g} s" for t in times) + f" | CoM at {com_time(times):g} s" +
            f" | energy / ref at {times[-1]:g} s | max strain / ref |\n|" + "---|" * (len(times) + 5))
    out = []
    ref_by_case = defaultdict(list)
    for r in refs or []:
        ref_by_case[r["case"]].append(r)
    budget_lines = ["| case | within 8.3 ms | RMS | within 16.7 ms | RMS |", "|---|---|---|---|---|"]
    for case, by_label in configs.items():
        out.append(f"### {case}\n")
        for r in ref_by_case.get(case, []):
            out.append(f"Reference ({r['reference']}, h = {_num(r['h_ref']):.3g} s, "
                       f"{r['particles']} particles): its error at {_num(r['time']):g} s, from step "
                       f"halving: {_pct(_num(r['floor_rms']))} RMS, {_pct(_num(r['floor_max']))} max.  ")
        t0 = primary_time(by_label)
        pts = [(_num(by_t[t0]["frame_ms_median"]), _num(by_t[t0]["rms_error"]), name)
               for name, by_t in by_label.items() if t0 in by_t]
        out += ["", f"Pareto front (RMS error at {t0:g} s against ms per frame):\n", head,
                _floor_row(ref_by_case.get(case, []), times)]
        out += [_row(name, by_label[name], times) for _, _, name in pareto(pts)]
        out.append("")
        best = []
        for budget in (FRAME_MS / 2, FRAME_MS):
            fits = [p for p in pts if p[0] <= budget]
            b = min(fits, key=lambda p: p[1]) if fits else None
            best += [b[2] if b else "-", _pct(b[1]) if b else "-"]
        budget_lines.append(f"| {case} | " + " | ".join(best) + " |")
    return "\n".join(budget_lines) + "\n\n" + "\n".join(out)


def report(results, rows, refs, style):
    plot(rows, os.path.join(results, "accuracy.png"), style)
    with open(os.path.join(results, "accuracy.md"), "w") as f:
        f.write("# Accuracy against the true motion\n\nBest RMS error at 1 s "
                "within a budget of ms per 1/60 s frame:\n\n" + tables(rows, refs) + "\n")
