#!/usr/bin/env bash
# The benchmark of docs/benchmark.md in one command (make bench): builds (Release), then
#   accuracy   every solver x substeps x iterations x scene x grid, error against the true motion
#   peers      Bullet's implicit deformable solver on hanging and flag at 32 x 32 against the
#              same true motion, and cloth_sim's accuracy sweep of the same cases beside it
#              (bench/results/bullet; says so and skips when the bench was built without Bullet)
#   drift      (only when asked) energy of an undamped scene over 10 s per configuration
#   floor      bandwidth floor and per-iteration cost on the paper's 81 x 81 cloth
#   speed      every solver x iteration count x scene x grid, error against converged Newton
#   stability  every solver over stiffness x time step x hard cases
#   scaling    cost against sphere count, and cloth size over mesh obstacles
#   threads    (only when asked) ms per kernel and per frame at 1 and 2 threads, 32 to 256
#   precision  (only when asked) the float factor against the double one
#   self_collision  cost of self-collision against the particle count (bench/self_collision.sh)
#   self_collision_set  (only when asked) the randomized thin self-contact set at 16 to 128
#   default    (only when asked) the scene format's default on every accuracy scene at 32 and
#              64, its estimate against the true local error (bench/default_report.py)
# and turns the CSV files into plots and tables (bench/report.py). Results: bench/results/.
# Usage: bench/run.sh [accuracy|peers|drift|floor|speed|stability|scaling|threads|precision|self_collision|self_collision_set|default|report|all] [extra cloth_sim_bench options]
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/env.sh"
what="${1:-all}"
shift || true
[ "$what" = report ] || bash "$REPO_ROOT/scripts/build.sh" > /dev/null
BENCH="$WS/devel/lib/cloth_sim/cloth_sim_bench"
echo "[bench] $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; load: $(cut -d' ' -f1-3 /proc/loadavg)"
# One thread everywhere: the timings are single-core and comparable (OpenBLAS would otherwise
# use both cores inside Newton's factorizations).
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
# Bullet beside cloth_sim (docs/benchmark.md, "Bullet's implicit solver side by side").
peers() {
  local out="$REPO_ROOT/bench/results/bullet"
  "$BENCH" peers --scenes hanging,flag --grids 32 --newton-iterations 0,5 --out "$out" "$@"
  if "$BENCH" peers --help | grep -q "Bullet is absent"; then return; fi
  "$BENCH" accuracy --scenes hanging,flag --grids 32 --times 0.25,0.5,1 \
    --solvers local_global,anderson --integrators implicit_euler,bdf2 --substeps 1,2,4,8,16,32 \
    --iterations 1,2,3,5,10 --no-default --newton-max-grid 0 \
    --local-error-frames 0 --out "$out"
}
case "$what" in
  accuracy|drift|floor|speed|stability|scaling|threads|precision|self_collision_set) "$BENCH" "$what" "$@" ;;
  peers) peers "$@" ;;
  self_collision) bash "$REPO_ROOT/bench/self_collision.sh" "$@" ;;
  default)
    out="$REPO_ROOT/bench/results/default"
    "$BENCH" accuracy --default-only --grids 32,64 --times 0.25,0.5,1 --out "$out" \
      --scenes hanging,drape,trampoline,gravity_well,tablecloth,peer_cloth,flag,ball_drop,curtain,table_edge,stiff_flag,soft_flag "$@"
    /usr/bin/python3 "$REPO_ROOT/bench/default_report.py" --out "$out" "$out"
    ;;
  report) ;;
  all)
    "$BENCH" accuracy
    peers
    "$BENCH" floor
    "$BENCH" speed
    "$BENCH" stability
    "$BENCH" scaling
    bash "$REPO_ROOT/bench/self_collision.sh"
    ;;
  *) echo "usage: $0 [accuracy|peers|drift|floor|speed|stability|scaling|threads|precision|self_collision|self_collision_set|default|report|all] [options]" >&2; exit 1 ;;
esac
echo "[bench] load after: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/python3 "$REPO_ROOT/bench/report.py" "$REPO_ROOT/bench/results"
echo "[bench] results in $REPO_ROOT/bench/results"
