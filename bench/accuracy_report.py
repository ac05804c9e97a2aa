"""Plots and tables of `cloth_sim_bench accuracy` (accuracy.csv, accuracy_reference.csv).

accuracy.png: per case, RMS position error at 1 s (or the first sample time; over the cloth's diagonal)
against ms per 1/60 s frame, log-log, one colour per solver, its Pareto front as a line.
accuracy.md: the reference's own error (step halving), the Pareto front of every case, and the
best configuration within half a frame (8.3 ms) and within a frame (16.7 ms). Every table has a
"floor" row: the spread between the two references (h and h / 2) at each time, below which no
error can be told apart. A BDF2 run's solver is "<solver>/bdf2", drawn in its solver's colour
with a hollow marker and a dashed front.

report_peer: the peers' scene (peer_cloth, 1 m) against XPBD, in mm: peer.md (the Pareto front
of each solver at 0.5 s, the best error of each within 1, 4, 16 and 64 ms per frame, the floor,
the energy drift of drift.csv) and accuracy.png at 0.5 s.
"""
import csv
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


def plot(rows, path, style, at=None, scale=None, unit="RMS error / diagonal", cpu=False):
    """at: the time drawn (default primary_time); scale: case -> factor applied to the errors;
    cpu: CPU ms per frame on x (when measured) instead of wall ms."""
    configs = _configs(rows)
    cases = list(configs)
    if not cases:
        return
    cols = min(3, len(cases))
    nrows = (len(cases) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(5 * cols, 4 * nrows), squeeze=False)
    for ax, case in zip(axes.flat, cases):
        t0 = at if at is not None else primary_time(configs[case])
        f = scale.get(case, 1.0) if scale else 1.0
        by_solver = defaultdict(list)
        for by_t in configs[case].values():
            r = by_t.get(t0)
            if r:
                ms = _ms(r) if cpu else _num(r["frame_ms_median"])
                by_solver[r["solver"]].append((ms, f * _num(r["rms_error"])))
        for solver, pts in sorted(by_solver.items()):
            colour, marker, line = style_of(style, solver)
            ax.scatter(*zip(*pts), marker=marker, s=14, alpha=0.5,
                       **({"edgecolors": colour, "facecolors": "none"} if line == "--" else {"color": colour}))
            front = pareto(pts)
            ax.plot(*zip(*front), color=colour, ls=line, label=solver)
        ax.axvline(FRAME_MS, color="gray", ls="--", lw=0.8)
        ax.axvline(FRAME_MS / 2, color="gray", ls=":", lw=0.8)
        if not scale:
            ax.axhline(0.02, color="red", ls=":", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{case}, t = {t0:g} s")
        ax.set_xlabel("CPU ms per 1/60 s frame" if cpu else "ms per 1/60 s frame")
        ax.set_ylabel(unit)
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


# --- the peers' scene against XPBD, in mm ---------------------------------------------------
PEER_BUDGETS_MS = (1.0, 4.0, 16.0, 64.0)


def _read(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def _mm(v):
    return "-" if math.isnan(v) else (f"{v:.3g}" if v < 100 else f"{v:.0f}")


def _ms(r, which="median"):
    """CPU ms per frame of this thread when measured (the machine's other jobs do not count),
    else wall ms."""
    v = _num(r.get(f"cpu_ms_{which}"))
    return v if not math.isnan(v) else _num(r[f"frame_ms_{which}"])


def peer_tables(rows, refs, drift):
    """Markdown: per case, the floor, the best of each solver within each budget (RMS at 0.25 and
    0.5 s, CoM at 1 s, in mm), and each solver's Pareto front at 0.5 s."""
    configs = _configs(rows)
    diag = {r["case"]: _num(r["diagonal"]) for r in refs}
    ref_by_case = defaultdict(dict)
    for r in refs:
        ref_by_case[r["case"]][_num(r["time"])] = r
    out = ["# Against XPBD on the peers' scene\n",
           "Errors in mm against the Verlet reference (the cloth is 1 m; 1 % of its diagonal is "
           "14.1 mm); ms per 1/60 s frame: this thread's CPU time, median (p10-p90), one thread "
           "(the wall time, inflated by the machine's other jobs, is in accuracy.csv). "
           "\"floor\": the distance between the two references (h and h / 2), below which no "
           "error can be told apart.\n"]
    for case, by_label in configs.items():
        mm = 1000.0 * diag.get(case, float("nan"))
        refs_t = ref_by_case.get(case, {})

        def cell(by_t, t, key):
            r = by_t.get(t)
            return mm * _num(r[key]) if r else float("nan")

        floor = [mm * _num(refs_t[t]["floor_rms"]) if t in refs_t else float("nan") for t in (0.25, 0.5)]
        floor_com = mm * _num(refs_t[1.0]["floor_com"]) if 1.0 in refs_t else float("nan")
        ref0 = next(iter(refs_t.values()), None)
        out.append(f"## {case}\n")
        if ref0:
            out.append(f"Reference: {ref0['reference']} at h = {_num(ref0['h_ref']):.3g} s, "
                       f"{ref0['particles']} particles. Floor: {_mm(floor[0])} mm RMS at 0.25 s, "
                       f"{_mm(floor[1])} mm at 0.5 s, {_mm(floor_com)} mm centre of mass at 1 s.\n")
        solvers = sorted({by_t[min(by_t)]["solver"] for by_t in by_label.values()})
        out.append("Best within a budget: the RMS columns are those of the configuration with the "
                   "lowest RMS at 0.5 s, the CoM column that of the lowest CoM error at 1 s:\n")
        out.append("| solver | within CPU ms per frame | RMS at 0.25 s (mm) | RMS at 0.5 s (mm) | configuration "
                   "| CoM at 1 s (mm) | configuration |")
        out.append("|---|---|---|---|---|---|---|")
        for budget in PEER_BUDGETS_MS:
            for solver in solvers:
                fits = [(name, by_t) for name, by_t in by_label.items()
                        if by_t[min(by_t)]["solver"] == solver
                        and _ms(by_t[min(by_t)]) <= budget]
                rms = [(cell(b, 0.5, "rms_error"), n, b) for n, b in fits if 0.5 in b]
                com = [(cell(b, 1.0, "com_error"), n) for n, b in fits if 1.0 in b]
                br = min(rms, key=lambda x: x[0]) if rms else None
                bc = min(com, key=lambda x: x[0]) if com else None
                out.append(f"| {solver} | {budget:g} | "
                           f"{_mm(cell(br[2], 0.25, 'rms_error')) if br else '-'} | "
                           f"{_mm(br[0]) if br else '-'} | {br[1] if br else '-'} | "
                           f"{_mm(bc[0]) if bc else '-'} | {bc[1] if bc else '-'} |")
        out.append(f"| floor | - | {_mm(floor[0])} | {_mm(floor[1])} | - | {_mm(floor_com)} | - |")
        out.append("")
        out.append("Pareto front of each solver (RMS at 0.5 s against ms per frame):\n")
        out.append("| configuration | CPU ms per frame (p10-p90) | RMS at 0.25 s (mm) | RMS at 0.5 s (mm) "
                   "| CoM at 1 s (mm) | energy / ref at 1 s | max strain / ref at 1 s |")
        out.append("|---|---|---|---|---|---|---|")
        out.append(f"| floor (reference h vs h/2) | - | {_mm(floor[0])} | {_mm(floor[1])} | "
                   f"{_mm(floor_com)} | - | - |")
        for solver in solvers:
            pts = [(_ms(b[0.5]), _num(b[0.5]["rms_error"]), n)
                   for n, b in by_label.items() if 0.5 in b and b[0.5]["solver"] == solver]
            for _, _, name in pareto(pts):
                b = by_label[name]
                first = b[min(b)]
                last = b.get(1.0, b[max(b)])
                out.append(f"| {name} | {_ms(first):.2f} "
                           f"({_ms(first, 'p10'):.2f}-{_ms(first, 'p90'):.2f}) | "
                           f"{_mm(cell(b, 0.25, 'rms_error'))} | {_mm(cell(b, 0.5, 'rms_error'))} | "
                           f"{_mm(cell(b, 1.0, 'com_error'))} | {_num(last['energy_ratio']):.3f} | "
                           f"{_num(last['max_strain']) / _num(last['ref_max_strain']):.2f} |")
        out.append("")
    if drift:
        out.append("## Energy drift of the undamped cloth\n")
        out.append("| case | configuration | energy at 0 (J) | at 1 s | at the end | drift (J) | "
                   "min, max over the run (J) | kinetic max (J) | ms per frame |")
        out.append("|---|---|---|---|---|---|---|---|---|")
        for r in drift:
            out.append(f"| {r['case']} | {r['solver']} s{r['substeps']} i{r['iterations']}, "
                       f"{_num(r['duration']):g} s | {_num(r['energy_start']):.3f} | "
                       f"{_num(r['energy_1s']):.3f} | {_num(r['energy_end']):.3f} | "
                       f"{_num(r['drift']):+.3f} | {_num(r['energy_min']):.3f}, "
                       f"{_num(r['energy_max']):.3f} | {_num(r['kinetic_max']):.3f} | "
                       f"{_num(r['frame_ms_median']):.2f} |")
        out.append("")
    return "\n".join(out)


def report_peer(results, style):
    """peer.md and accuracy.png (RMS at 0.5 s in mm) of the peer sweep in @p results."""
    rows = _read(os.path.join(results, "accuracy.csv"))
    refs = _read(os.path.join(results, "accuracy_reference.csv"))
    drift = _read(os.path.join(results, "drift.csv"))
    scale = {r["case"]: 1000.0 * _num(r["diagonal"]) for r in refs}
    plot(rows, os.path.join(results, "accuracy.png"), style, at=0.5, scale=scale,
         unit="RMS error at 0.5 s (mm)", cpu=True)
    with open(os.path.join(results, "peer.md"), "w") as f:
        f.write(peer_tables(rows, refs, drift))


def bullet_tables(rows, refs, times=(0.25, 0.5, 1.0)):
    """Markdown: per case, the best RMS error (% of the diagonal) of cloth_sim's configurations
    and of Bullet's within 1, 4, 16 and 64 CPU ms per frame, and Bullet's every run."""
    configs = _configs(rows)
    floor = {(r["case"], _num(r["time"])): _num(r["floor_rms"]) for r in refs}

    def blew_up(by_t):
        """A spring stretched past twice its rest length at a sample (the reference's max
        strain stays below 0.3 on these cases): a blown-up run, left out of the budget table."""
        return any(_num(r["max_strain"]) > 1.0 for r in by_t.values())

    out = ["# Bullet's implicit solver side by side\n",
           "RMS position error over the cloth's diagonal against the accuracy benchmark's "
           "reference; ms per 1/60 s frame: this thread's CPU time, median (the wall time is in "
           "the CSV files). cloth_sim: accuracy.csv, Bullet: peers.csv, same session. Best within "
           "a budget: the configuration with the lowest RMS at 1 s among those whose median CPU "
           "ms per frame fits and that did not blow up (a spring past 100 % strain at a sample; "
           "marked \"blew up\" below).\n"]
    for case, by_label in configs.items():
        out.append(f"## {case}\n")
        out.append("| within CPU ms per frame | cloth_sim: RMS at 1 s | configuration | "
                   "Bullet: RMS at 1 s | configuration |")
        out.append("|---|---|---|---|---|")
        for budget in PEER_BUDGETS_MS:
            cells = []
            for bullet in (False, True):
                fits = [(_num(b[1.0]["rms_error"]), n, _ms(b[1.0])) for n, b in by_label.items()
                        if 1.0 in b and b[1.0]["solver"].startswith("bullet") == bullet
                        and _ms(b[1.0]) <= budget and not blew_up(b)]
                best = min(fits) if fits else None
                cells += [_pct(best[0]) if best else "-",
                          f"{best[1]} ({best[2]:.3g} ms)" if best else "-"]
            out.append(f"| {budget:g} | " + " | ".join(cells) + " |")
        out.append("| floor (reference h vs h/2) | " + _pct(floor.get((case, 1.0), float("nan")))
                   + " | - | - | - |\n")
        out.append("Bullet, every run:\n")
        out.append("| configuration | CPU ms per frame (p10-p90) | "
                   + " | ".join(f"RMS at {t:g} s" for t in times)
                   + " | energy / ref at 1 s | max strain at 1 s (ref) |")
        out.append("|---|---|" + "---|" * len(times) + "---|---|")
        for name, b in sorted(by_label.items(), key=lambda kv: (kv[0].split()[0],
                                                                int(kv[0].split()[1][1:]))):
            first = b[min(b)]
            if not first["solver"].startswith("bullet"):
                continue
            last = b.get(1.0)
            if blew_up(b):
                name += " (blew up)"
            out.append(f"| {name} | {_ms(first):.3g} ({_ms(first, 'p10'):.3g}-{_ms(first, 'p90'):.3g}) | "
                       + " | ".join(_pct(_num(b[t]["rms_error"])) if t in b else "-" for t in times)
                       + (f" | {_num(last['energy_ratio']):.3g} | {_num(last['max_strain']):.3g} "
                          f"({_num(last['ref_max_strain']):.3g}) |" if last else " | - | - |"))
        out.append("")
    return "\n".join(out) + "\n"


def report_bullet(results, style):
    """bullet.md and bullet.png (RMS at 1 s against CPU ms per frame) of the run in @p results:
    cloth_sim's accuracy.csv and Bullet's peers.csv (cloth_sim_bench peers) side by side."""
    rows = _read(os.path.join(results, "accuracy.csv")) + _read(os.path.join(results, "peers.csv"))
    refs = _read(os.path.join(results, "accuracy_reference.csv"))
    plot(rows, os.path.join(results, "bullet.png"), style, at=1.0, cpu=True)
    with open(os.path.join(results, "bullet.md"), "w") as f:
        f.write(bullet_tables(rows, refs))
