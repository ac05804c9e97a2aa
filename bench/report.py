#!/usr/bin/python3
"""Turns the benchmark's CSV files into plots and Markdown tables (docs/benchmark.md).

Usage: bench/report.py [results_dir]   (default: bench/results next to this script)
Reads accuracy.csv, accuracy_reference.csv, speed.csv, traces.csv, references.csv, cases.csv,
floor.csv, kernels.csv, stability.csv, scaling.csv (whichever exist) and writes accuracy.png,
speed.png, speed_position.png, converge.png and accuracy.md, summary.md, speed_table.md,
stability.md, scaling.md (accuracy ones through accuracy_report.py). Needs Debian's python3-matplotlib (hence /usr/bin/python3).
"""
import csv
import math
import os
import statistics
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import accuracy_report  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "results")
TARGET = 1e-3  # relative error for the time-to-error comparison

STYLE = {
    "local_global": ("tab:blue", "o"),
    "local_global:cholmod": ("tab:cyan", "v"),
    "local_global:eigen": ("tab:gray", "^"),
    "local_global_3n": ("tab:brown", "s"),
    "chebyshev": ("tab:green", "D"),
    "local_global+warm": ("tab:olive", "o"),
    "chebyshev+warm": ("tab:olive", "D"),
    "anderson": ("tab:orange", "P"),
    "anderson+warm": ("tab:orange", "X"),
    "lbfgs": ("tab:cyan", "v"),
    "lbfgs+warm": ("tab:cyan", "^"),
    "newton": ("tab:red", "*"),
    "explicit_euler": ("tab:purple", "x"),
    "verlet": ("tab:pink", "+"),
    "xpbd": ("black", "s"),
    "bullet": ("magenta", "h"),
}


def read(name):
    path = os.path.join(RESULTS, name)
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return list(csv.DictReader(f))


def num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


def fmt(v, digits=3):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    if v == 0:
        return "0"
    if abs(v) >= 1e4 or abs(v) < 1e-3:
        return f"{v:.1e}"
    return f"{v:.{digits}g}"


def case_order(rows):
    seen = []
    for r in rows:
        if r["case"] not in seen:
            seen.append(r["case"])
    return seen


def plot_speed(speed, column, path, ylabel):
    cases = case_order(speed)
    cols = 3
    rows_n = math.ceil(len(cases) / cols)
    fig, axes = plt.subplots(rows_n, cols, figsize=(5 * cols, 4 * rows_n), squeeze=False)
    for ax, case in zip(axes.flat, cases):
        by_solver = defaultdict(list)
        for r in speed:
            if r["case"] == case:
                by_solver[r["solver"]].append(r)
        for solver, rs in by_solver.items():
            rs.sort(key=lambda r: int(r["iterations"]))
            xs = [num(r["ms_median"]) for r in rs]
            ys = [max(num(r[column]), 1e-16) for r in rs]
            color, marker = STYLE.get(solver, ("black", "."))
            ax.loglog(xs, ys, marker=marker, color=color, label=solver, linewidth=1)
            if solver in ("local_global", "chebyshev", "newton"):
                for r, x, y in zip(rs, xs, ys):
                    ax.annotate(r["iterations"], (x, y), fontsize=6, color=color,
                                xytext=(2, 2), textcoords="offset points")
        ax.set_title(case)
        ax.set_xlabel("ms per step (median)")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.set_ylim(1e-12, 1e3)
    for ax in axes.flat[len(cases):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7)
    fig.suptitle(f"{ylabel} after one step vs. cost, iterations 1-50 (labels), median over "
                 "sampled states")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def cost_model(speed, case, solver):
    """Least-squares ms = a + b k over the iteration counts of one solver on one case."""
    pts = [(int(r["iterations"]), num(r["ms_median"])) for r in speed
           if r["case"] == case and r["solver"] == solver]
    if len(pts) < 2:
        return None
    n = len(pts)
    mk = sum(k for k, _ in pts) / n
    mt = sum(t for _, t in pts) / n
    b = sum((k - mk) * (t - mt) for k, t in pts) / sum((k - mk) ** 2 for k, _ in pts)
    return mt - b * mk, b


def first_crossing(traces, case, solver, column):
    """Per sample: the first k with error <= TARGET, or None (with the last k tried)."""
    per_sample = defaultdict(list)
    for r in traces:
        if r["case"] == case and r["solver"] == solver:
            per_sample[r["sample"]].append((int(r["k"]), num(r[column])))
    out = []
    for sample, pts in sorted(per_sample.items()):
        pts.sort()
        hit = next((k for k, e in pts if e <= TARGET), None)
        out.append((sample, hit, pts[-1][0], pts[0][1]))
    return out


def converge_table(speed, traces):
    lines = ["| case | error | local_global: iterations to 1e-3 (per state) | time | chebyshev: "
             "iterations | time | time ratio |", "|---|---|---|---|---|---|---|"]
    for case in case_order(speed):
        for column, name in (("err_g", "g"), ("err_x", "x")):
            cells = []
            times = {}
            for solver in ("local_global", "chebyshev"):
                model = cost_model(speed, case, solver)
                cross = first_crossing(traces, case, solver, column)
                if not cross or model is None:
                    cells += ["-", "-"]
                    continue
                a, b = model
                ks, ts, lower = [], [], False
                for _, hit, last, _ in cross:
                    if hit is None:
                        ks.append(f">{last}")
                        ts.append(a + b * last)
                        lower = True
                    else:
                        ks.append(str(hit))
                        ts.append(a + b * hit)
                t = statistics.median(ts)
                times[solver] = (t, lower)
                cells += [", ".join(ks), (">" if lower else "") + fmt(t) + " ms"]
            ratio = "-"
            if len(times) == 2:
                (tl, ll), (tc, lc) = times["local_global"], times["chebyshev"]
                if tc > 0:
                    ratio = ("> " if ll and not lc else "") + fmt(tl / tc) + "x"
                    if lc:
                        ratio = "(cheb. not reached)"
            lines.append(f"| {case} | {name} | {cells[0]} | {cells[1]} | {cells[2]} | {cells[3]} "
                         f"| {ratio} |")
    return "\n".join(lines)


def plot_converge(traces, path):
    cases = [c for c in case_order(traces)]
    if not cases:
        return
    cols = 3
    rows_n = math.ceil(len(cases) / cols)
    fig, axes = plt.subplots(rows_n, cols, figsize=(5 * cols, 3.6 * rows_n), squeeze=False)
    for ax, case in zip(axes.flat, cases):
        for solver, color in (("local_global", "tab:blue"), ("chebyshev", "tab:green")):
            per_sample = defaultdict(list)
            for r in traces:
                if r["case"] == case and r["solver"] == solver:
                    per_sample[r["sample"]].append((int(r["k"]), max(num(r["err_g"]), 1e-16)))
            for i, (_, pts) in enumerate(sorted(per_sample.items())):
                pts.sort()
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], color=color, alpha=0.7,
                          label=solver if i == 0 else None)
        ax.axhline(TARGET, color="black", linewidth=0.5, linestyle="--")
        ax.set_title(case)
        ax.set_xlabel("iterations")
        ax.set_ylabel("(g - g*) / (g0 - g*)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes.flat[len(cases):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def speed_tables(speed):
    out = []
    for case in case_order(speed):
        rs = [r for r in speed if r["case"] == case]
        r0 = rs[0]
        out.append(f"\n#### {case} ({r0['particles']} particles, {r0['springs']} springs, "
                   f"h = 1/{round(1 / num(r0['h']))} s)\n")
        out.append("| solver | iterations | ms/step median [p10, p90] | err g | err x | max strain "
                   "| energy end (J) | failed steps |")
        out.append("|---|---|---|---|---|---|---|---|")
        for r in rs:
            out.append(f"| {r['solver']} | {r['iterations']} | {fmt(num(r['ms_median']))} "
                       f"[{fmt(num(r['ms_p10']))}, {fmt(num(r['ms_p90']))}] | "
                       f"{fmt(num(r['err_g_median']))} | {fmt(num(r['err_x_median']))} | "
                       f"{fmt(num(r['max_strain']))} | {fmt(num(r['energy_end']))} | "
                       f"{r['failures']}/{r['steps']} |")
    return "\n".join(out)


def ratio_table(speed):
    lines = ["| case | local_global 10 it (ms) | local_global_3n 10 it | speed-up | "
             "cholmod solve | eigen solve | chebyshev 10 it |", "|---|---|---|---|---|---|---|"]
    for case in case_order(speed):
        def ms(solver):
            for r in speed:
                if r["case"] == case and r["solver"] == solver and r["iterations"] == "10":
                    return num(r["ms_median"])
            return float("nan")
        lg = ms("local_global")
        lines.append(f"| {case} | {fmt(lg)} | {fmt(ms('local_global_3n'))} | "
                     f"{fmt(ms('local_global_3n') / lg)}x | {fmt(ms('local_global:cholmod'))} | "
                     f"{fmt(ms('local_global:eigen'))} | {fmt(ms('chebyshev'))} |")
    return "\n".join(lines)


def realtime_table(speed, case="drape-128", budget_ms=16.0, target=1e-2):
    lines = [f"| solver | iterations | ms/step | err g | err x | under {budget_ms:g} ms and err g "
             f"<= {target:g} |", "|---|---|---|---|---|---|"]
    for r in speed:
        if r["case"] != case or r["solver"] not in ("local_global", "chebyshev", "newton"):
            continue
        ok = num(r["ms_median"]) < budget_ms and num(r["err_g_median"]) <= target
        lines.append(f"| {r['solver']} | {r['iterations']} | {fmt(num(r['ms_median']))} | "
                     f"{fmt(num(r['err_g_median']))} | {fmt(num(r['err_x_median']))} | "
                     f"{'yes' if ok else ''} |")
    return "\n".join(lines)


def stability_tables(stab):
    hs = sorted({num(r["h"]) for r in stab})
    out = []
    for scenario in case_order([{"case": r["scenario"]} for r in stab]):
        out.append(f"\n#### {scenario}\n")
        out.append("| solver | k (N/m) | " + " | ".join(f"h = 1/{round(1 / h)}" for h in hs) + " |")
        out.append("|---|---|" + "---|" * len(hs))
        rows = defaultdict(dict)
        for r in stab:
            if r["scenario"] == scenario:
                rows[(r["solver"], num(r["stiffness"]))][num(r["h"])] = r
        for (solver, k), cells in rows.items():
            texts = []
            for h in hs:
                r = cells.get(h)
                if r is None:
                    texts.append("")
                    continue
                peak = num(r["peak_strain"])
                if r["stable"] != "1":
                    mark = "✗"
                elif peak > 1.0:
                    mark = "✓*"
                else:
                    mark = "✓"
                texts.append(f"{mark} {fmt(100 * peak, 2)}% {fmt(num(r['end_energy']), 2)} J")
            out.append(f"| {solver} | {k:.0e} | " + " | ".join(texts) + " |")
    return "\n".join(out)


def scaling_table(rows):
    keys = ["case", "parameter", "particles", "spheres", "obstacle_triangles", "ms_median",
            "ms_p10", "ms_p90", "solve_ms_median", "rest_ms_median", "rest_us_per_particle"]
    head = ["case", "spheres or grid", "particles", "spheres", "obstacle triangles",
            "ms/step median", "p10", "p90", "in the solver (ms)", "outside the solver (ms)",
            "outside, us per particle"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        out.append("| " + " | ".join(r[k] if k in keys[:5] else fmt(num(r[k]))
                                     for k in keys) + " |")
    return "\n".join(out)


def main():
    accuracy = read("accuracy.csv")
    if accuracy:
        accuracy_report.report(RESULTS, accuracy, read("accuracy_reference.csv"), STYLE)
    # The peers' scene against XPBD (bench/run.sh accuracy --scenes peer_cloth --out .../peer).
    peer = os.path.join(RESULTS, "peer")
    if os.path.exists(os.path.join(peer, "accuracy.csv")):
        accuracy_report.report_peer(peer, STYLE)
    # Bullet's implicit solver (bench/run.sh peers: bench/results/bullet, with cloth_sim's
    # accuracy sweep of the same cases beside it; bullet64: the same at 64 x 64).
    for name in ("bullet", "bullet64"):
        bullet = os.path.join(RESULTS, name)
        if os.path.exists(os.path.join(bullet, "peers.csv")):
            accuracy_report.report_bullet(bullet, STYLE)
    speed, traces = read("speed.csv"), read("traces.csv")
    summary = []
    if speed:
        plot_speed(speed, "err_g_median", os.path.join(RESULTS, "speed.png"),
                   "(g - g*) / (g0 - g*)")
        plot_speed(speed, "err_x_median", os.path.join(RESULTS, "speed_position.png"),
                   "|x - x*| / |x0 - x*|")
        with open(os.path.join(RESULTS, "speed_table.md"), "w") as f:
            f.write("# Speed against error, every configuration\n" + speed_tables(speed) + "\n")
        summary += ["### ms per step at 10 iterations\n", ratio_table(speed), ""]
        if any(r["case"] == "drape-128" for r in speed):
            summary += ["### drape-128 (sphere collider)\n", realtime_table(speed), ""]
    if speed and traces:
        plot_converge(traces, os.path.join(RESULTS, "converge.png"))
        summary += [f"### time to relative error {TARGET:g}\n", converge_table(speed, traces), ""]
    refs = read("references.csv")
    if refs:
        bad = [r for r in refs if r["converged"] != "1"]
        iters = [int(r["newton_iterations"]) for r in refs]
        good = [num(r["grad_ratio"]) for r in refs if r["converged"] == "1"]
        summary += [f"Newton references: {len(refs)} states, {len(good)} converged"
                    + (f" (|grad g| / |grad g0| <= {fmt(max(good))})" if good else "")
                    + "".join(f"; not converged: {r['case']} state {r['sample']} "
                              f"(|grad g| / |grad g0| = {fmt(num(r['grad_ratio']))})" for r in bad)
                    + f". Newton iterations after the warm start: median "
                    f"{statistics.median(iters)}, max {max(iters)}.", ""]
    for name in ("floor.csv", "kernels.csv"):
        rows = read(name)
        if rows:
            keys = list(rows[0].keys())
            summary += [f"### {name}\n", "| " + " | ".join(keys) + " |",
                        "|" + "---|" * len(keys)]
            # Numbers formatted, text (the first column, units) as is.
            summary += ["| " + " | ".join(r[k] if k == keys[0] or math.isnan(num(r[k]))
                                          else fmt(num(r[k])) for k in keys) + " |" for r in rows]
            summary.append("")
    with open(os.path.join(RESULTS, "summary.md"), "w") as f:
        f.write("\n".join(summary) + "\n")
    scaling = read("scaling.csv")
    if scaling:
        with open(os.path.join(RESULTS, "scaling.md"), "w") as f:
            f.write(scaling_table(scaling) + "\n")
    stab = read("stability.csv")
    if stab:
        with open(os.path.join(RESULTS, "stability.md"), "w") as f:
            f.write("Cells: ✓ stable, ✓* stable with a transient over 100 % strain (recovered), "
                    "✗ unstable; then the peak strain and the energy at the end.\n"
                    + stability_tables(stab) + "\n")


if __name__ == "__main__":
    main()
