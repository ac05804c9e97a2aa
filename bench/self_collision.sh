#!/usr/bin/env bash
# Cost of self-collision against the particle count (docs/benchmark.md, "Self-collision"): the
# fold scene at N x N particles (--resolution: the scene's 3 mm in mode triangles, the automatic
# thickness, the mean rest edge, in mode particles), its corner carried over the cloth in 1.5 s
# and let go (--fold), 3 s, with self-collision off, in mode triangles and in mode particles,
# one thread; then mode triangles on two threads (the broad phase's walk and the pairs' start
# geometry share them, as the solver's kernels do).
# Writes bench/results/self_collision.csv (one row per run) and self_collision.md (the table).
# Usage: bench/self_collision.sh [N ...]   (default 32 64 128: 1k to 16k particles)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/env.sh"
RUN="$WS/devel/lib/cloth_sim/cloth_sim_run"
OUT="$REPO_ROOT/bench/results"
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(32 64 128)
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
SCENE="$REPO_ROOT/config/scenes/fold.yaml"
# The same scene in mode particles.
sed 's/^self_collision:.*/self_collision: {mode: particles, friction: 0.3}/' "$SCENE" \
  > "$tmp/fold_particles.yaml"
echo "n,particles,self_collision,load_before,load_after,cpu_s,csv" > "$tmp/runs.csv"
for n in "${sizes[@]}"; do
  for mode in off triangles particles triangles-2-threads; do
    load_before=$(cut -d' ' -f1 /proc/loadavg)
    scene="$SCENE" on=on
    [ "$mode" = particles ] && scene="$tmp/fold_particles.yaml"
    [ "$mode" = off ] && on=off
    threads=1
    [ "$mode" = triangles-2-threads ] && threads=2
    # CPU time (user + system) of the whole run as well as the wall times of the CSV: on a
    # loaded machine the wall time of a step includes the time others had the core.
    /usr/bin/time -f "%U %S" -o "$tmp/time" "$RUN" --scene "$scene" \
        --resolution "$n" --fold 1.5 --duration 3 --self-collision "$on" --threads "$threads" --quiet \
        --csv "$tmp/fold_${n}_${mode}.csv"
    cpu=$(awk '{print $1 + $2}' "$tmp/time")
    echo "$n,$((n * n)),$mode,$load_before,$(cut -d' ' -f1 /proc/loadavg),$cpu,$tmp/fold_${n}_${mode}.csv" \
        >> "$tmp/runs.csv"
    echo "[self_collision] $n x $n, self-collision $mode done (load $(cut -d' ' -f1-3 /proc/loadavg))"
  done
done
/usr/bin/python3 "$REPO_ROOT/bench/self_collision_report.py" "$tmp/runs.csv" "$OUT"
