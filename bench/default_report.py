"""The scene format's default against the error-control issue's bars, and its error estimate
against the true local error.

Reads the results of `cloth_sim_bench accuracy --default-only` (accuracy.csv,
accuracy_reference.csv, local_error.csv) from one or more directories and writes into the
first directory given after --out:
- default.md: per case at 1 s, the default's RMS error over the diagonal, the reference's own
  error (its distance to the same run at twice its step), its max strain and energy over the
  reference's, how much the reference's own energy moves when its step doubles (energy_2h; not
  in results from before that column), the ms per frame (wall and CPU, median) and the mean
  substeps,
  each bar marked; then, per case, the estimate of each probed frame over its true local error
  (the truncation estimate alone, and the whole one: plus the iteration errors carried).
- local_error.png: whole estimate against true local error (m per frame), log-log, with the line of
  equality and the factor-3 band.

Usage: default_report.py --out DIR RESULT_DIR [RESULT_DIR ...]
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

RMS_BAR = 0.02        # of the diagonal, at 1 s
CHAOTIC_BAR = 1.2     # or this times the reference's own error, where the motion is chaotic
STRAIN_BAR = 1.5      # max strain over the reference's
ENERGY_BAR = 0.15     # |energy / reference's - 1|
FRAME_MS = 1000.0 / 60.0
ESTIMATE_BAR = 3.0    # estimate within this factor of the true local error


def _read(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def _mark(ok):
    return "" if ok else " ✗"


def reference_errors(references):
    """case -> the reference's own error at 1 s (RMS over the diagonal)."""
    return {r["case"]: float(r["floor_rms"]) for r in references
            if r["time"] and float(r["time"]) == 1.0}


def reference_energy_changes(references):
    """case -> |E(2 h) / E(h) - 1| of the reference at 1 s (absent from older results)."""
    return {r["case"]: abs(float(r["energy_2h"]) / float(r["energy"]) - 1.0) for r in references
            if r["time"] and float(r["time"]) == 1.0 and r.get("energy_2h")
            and float(r["energy"]) != 0.0}


def rms_held(rms, reference_error):
    """The RMS bar: 2 % of the diagonal, or, where the motion is so sensitive that the
    reference's own error is comparable, 1.2x that error (the bar marks which held)."""
    if rms <= RMS_BAR:
        return True, ""
    if reference_error is not None and rms <= CHAOTIC_BAR * reference_error:
        return True, " (chaotic)"
    return False, " ✗"


def default_table(rows, references):
    floors = reference_errors(references)
    energy_changes = reference_energy_changes(references)
    lines = ["| case | RMS / diagonal | reference's own error | max strain / ref | energy / ref "
             "| reference's own energy change | ms per frame (CPU) | mean substeps |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["solver"] != "default" or not r["time"] or float(r["time"]) != 1.0:
            continue
        rms = float(r["rms_error"])
        floor = floors.get(r["case"])
        _, rms_mark = rms_held(rms, floor)
        strain = float(r["max_strain"]) / float(r["ref_max_strain"])
        energy = float(r["energy_ratio"])
        change = energy_changes.get(r["case"])
        wall, cpu = float(r["frame_ms_median"]), float(r["cpu_ms_median"])
        lines.append(
            f"| {r['case']} | {100 * rms:.2f} %{rms_mark} "
            f"| {'-' if floor is None else f'{100 * floor:.2f} %'} "
            f"| {strain:.2f}{_mark(strain <= STRAIN_BAR)} "
            f"| {energy:.3f}{_mark(abs(energy - 1) <= ENERGY_BAR)} "
            f"| {'-' if change is None else f'{100 * change:.1f} %'} "
            f"| {wall:.1f} ({cpu:.1f}){_mark(wall <= FRAME_MS)} "
            f"| {float(r['mean_substeps']):.1f} |")
    return lines


def _whole(r):
    """The frame's whole estimate: truncation plus the iteration errors carried to its end
    (local_error.csv from before that column: the truncation estimate alone)."""
    return float(r["estimate"]) + float(r.get("carried_iteration_error") or 0.0)


def local_table(rows):
    by_case = defaultdict(list)
    for r in rows:
        if r["solver"] == "default" and float(r["true_error"]) > 0:
            truth = float(r["true_error"])
            by_case[r["case"]].append((float(r["estimate"]) / truth, _whole(r) / truth))
    lines = ["| case | frames | truncation estimate / true local error: median | whole "
             "estimate / true: median | min | max | within 3x |", "|---|---|---|---|---|---|---|"]
    for case, pairs in by_case.items():
        truncation = [p[0] for p in pairs]
        ratios = [p[1] for p in pairs]
        inside = sum(1 for q in ratios if 1 / ESTIMATE_BAR <= q <= ESTIMATE_BAR)
        lines.append(f"| {case} | {len(ratios)} | {statistics.median(truncation):.2f} "
                     f"| {statistics.median(ratios):.2f} "
                     f"| {min(ratios):.2f} | {max(ratios):.2f} | {inside} / {len(ratios)} |")
    return lines


def plot(rows, path):
    fig, ax = plt.subplots(figsize=(6.5, 5.5))
    by_case = defaultdict(list)
    for r in rows:
        if float(r["true_error"]) > 0 and _whole(r) > 0:
            by_case[f"{r['case']} {r['solver']}"].append((float(r["true_error"]), _whole(r)))
    lo, hi = math.inf, 0.0
    for n, (name, points) in enumerate(sorted(by_case.items())):
        xs, ys = zip(*points)
        ax.loglog(xs, ys, "os^"[n // 10 % 3], ms=4, label=name)  # 10 colours per marker
        lo, hi = min(lo, *xs, *ys), max(hi, *xs, *ys)
    if hi > 0:
        line = [lo / 2, hi * 2]
        ax.loglog(line, line, "k-", lw=1, label="estimate = truth")
        ax.loglog(line, [v / ESTIMATE_BAR for v in line], "k:", lw=1, label="factor 3")
        ax.loglog(line, [v * ESTIMATE_BAR for v in line], "k:", lw=1)
    ax.set_xlabel("true local error of the frame (m, RMS)")
    ax.set_ylabel("whole error estimate of the frame (m)")
    ax.set_title("Error estimate against the true local error")
    ax.legend(fontsize=6, loc="upper left")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv):
    if len(argv) < 4 or argv[1] != "--out":
        sys.exit("usage: default_report.py --out DIR RESULT_DIR [RESULT_DIR ...]")
    out, dirs = argv[2], argv[3:]
    accuracy, local, references = [], [], []
    for d in dirs:
        accuracy += _read(os.path.join(d, "accuracy.csv"))
        local += _read(os.path.join(d, "local_error.csv"))
        references += _read(os.path.join(d, "accuracy_reference.csv"))
    os.makedirs(out, exist_ok=True)
    text = ["# The scene format's default against the bars", "",
            "Bars: RMS <= 2 % of the diagonal (or <= 1.2x the reference's own error where the "
            "motion is chaotic: marked), max strain <= 1.5x and energy within 15 % of the "
            "reference's, <= 16.7 ms per frame (wall); ✗ marks a miss.", ""]
    text += default_table(accuracy, references)
    text += ["", "## Error estimate against the true local error", ""]
    text += local_table(local)
    with open(os.path.join(out, "default.md"), "w") as f:
        f.write("\n".join(text) + "\n")
    plot(local, os.path.join(out, "local_error.png"))


if __name__ == "__main__":
    main(sys.argv)
