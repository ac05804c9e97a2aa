#!/usr/bin/env python3
"""Summarises the runs of bench/self_collision.sh into self_collision.csv and .md.

Per run: the CPU ms per frame of the whole run (user + system over the frames: what a step
costs whoever else uses the machine), the mean wall ms per frame of the step, of self-contact
(bound, pairs, projection) and of the intersection counter, and the max intersecting pairs.
The shares of the step are ratios of wall times measured in the same frames, so the load
inflates both sides alike.
"""
import csv
import statistics
import sys


def main(runs_csv, out_dir):
    rows = []
    with open(runs_csv) as f:
        for run in csv.DictReader(f):
            with open(run["csv"]) as g:
                steps = list(csv.DictReader(g))
            wall = [float(s["wall_ms"]) for s in steps]
            self_ms = [float(s["self_contact_ms"]) for s in steps]
            inter_ms = [float(s["intersection_ms"]) for s in steps]
            inter = [int(s["intersections"]) for s in steps]
            rows.append({
                "n": int(run["n"]), "particles": int(run["particles"]),
                "self_collision": run["self_collision"],
                "wall_ms_mean": statistics.mean(wall), "wall_ms_median": statistics.median(wall),
                "self_contact_ms_mean": statistics.mean(self_ms),
                "intersection_ms_mean": statistics.mean(inter_ms),
                "max_intersections": max(inter),
                "failed_steps": sum(s["status"] != "ok" for s in steps),
                "cpu_ms_per_frame": 1e3 * float(run["cpu_s"]) / len(steps),
                "load_before": run["load_before"], "load_after": run["load_after"],
            })
    keys = list(rows[0].keys())
    with open(out_dir + "/self_collision.csv", "w") as f:
        w = csv.DictWriter(f, keys)
        w.writeheader()
        w.writerows(rows)
    with open(out_dir + "/self_collision.md", "w") as f:
        f.write("| grid | particles | mode | CPU per frame off (ms) | CPU per frame on (ms) | "
                "added CPU (ms) | added per particle (us) | self-contact / step (wall) | counter "
                "/ step (wall) | step wall off / on (ms) | max intersecting pairs | load |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        by = {(r["n"], r["self_collision"]): r for r in rows}
        for n in sorted({r["n"] for r in rows}):
            off = by.get((n, "off"))
            for mode in ("triangles", "particles"):
                on = by.get((n, mode))
                if off is None or on is None:
                    continue
                s, c, w = on["self_contact_ms_mean"], on["intersection_ms_mean"], on["wall_ms_mean"]
                added = on["cpu_ms_per_frame"] - off["cpu_ms_per_frame"]
                f.write(f"| {n} x {n} | {on['particles']} | {mode} | "
                        f"{off['cpu_ms_per_frame']:.1f} | {on['cpu_ms_per_frame']:.1f} | "
                        f"{added:.1f} | {1e3 * added / on['particles']:.2f} | {100 * s / w:.0f} % | "
                        f"{100 * c / w:.0f} % | {off['wall_ms_mean']:.0f} / {w:.0f} | "
                        f"{on['max_intersections']} | {off['load_before']}-{on['load_after']} |\n")
        two = [r for r in rows if r["self_collision"] == "triangles-2-threads"]
        if two:
            f.write("\nMode triangles on two threads (the walk and the pairs' start geometry shared; "
                    "wall times, so the share depends on the other core being free):\n\n")
            f.write("| grid | step wall, 1 / 2 threads (ms) | self-contact wall, 1 / 2 threads (ms) | "
                    "self-contact / step, 1 / 2 threads | counter / step, 2 threads | "
                    "max intersecting pairs | load |\n")
            f.write("|---|---|---|---|---|---|---|\n")
            for r in sorted(two, key=lambda r: r["n"]):
                one = by.get((r["n"], "triangles"))
                if one is None:
                    continue
                f.write(f"| {r['n']} x {r['n']} | {one['wall_ms_mean']:.0f} / {r['wall_ms_mean']:.0f} | "
                        f"{one['self_contact_ms_mean']:.0f} / {r['self_contact_ms_mean']:.0f} | "
                        f"{100 * one['self_contact_ms_mean'] / one['wall_ms_mean']:.0f} % / "
                        f"{100 * r['self_contact_ms_mean'] / r['wall_ms_mean']:.0f} % | "
                        f"{100 * r['intersection_ms_mean'] / r['wall_ms_mean']:.0f} % | "
                        f"{r['max_intersections']} | {r['load_before']}-{r['load_after']} |\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
