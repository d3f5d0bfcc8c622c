#!/bin/bash
# `squeal modes` against CalculiX on a clamped C3D10 disc of 64,512 equations (issue 11).
#
# Sample run (from the repository root, after `cargo build --release` and
# `apt-get install -y calculix-ccx`):
#
#     bash examples/bench_modes.sh                 # 3 repetitions in ./bench-modes
#     REPS=5 OUT=/tmp/b bash examples/bench_modes.sh
#     COUNT=20 bash examples/bench_modes.sh        # the 20 lowest modes (*FREQUENCY, 20)
#
# With COUNT, the deck asks `*FREQUENCY` for that many modes and no upper frequency, and
# squeal is given no --fmax: both programs find the N lowest modes, squeal by the path a
# deck's count takes (src/analysis/modes.rs, `lowest_of_a_held_model`).
#
# Writes the deck with examples/make_disc_deck.py (--nt 96 --nr 8 --nz 3: 22,848 nodes,
# 13,824 C3D10, 64,512 free DOFs, 16 modes below 10 kHz; not committed, ~2 MB), then times,
# interleaved so that a load from elsewhere falls on all three alike, REPS runs each of
#   mpirun -n 1 squeal modes disc65.inp --mass-rule gauss4 --fmax 10000
#   mpirun -n 2 squeal modes ...
#   ccx -i disc65   (OMP_NUM_THREADS=1: one thread)
# and prints the medians, squeal's ratios to ccx, and the load average seen by each run.
# The two programs' frequencies agree to the 7 digits ccx prints (checked at the end).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SQUEAL=${SQUEAL:-$ROOT/target/release/squeal}
OUT=${OUT:-$PWD/bench-modes}
REPS=${REPS:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
command -v ccx >/dev/null || { echo "ccx not found: apt-get install -y calculix-ccx" >&2; exit 1; }
mkdir -p "$OUT" && cd "$OUT"
[ -f disc65.inp ] || python3 "$ROOT/examples/make_disc_deck.py" --nt 96 --nr 8 --nz 3 -o disc65.inp
DECK=disc65
BAND=(--fmax 10000)
if [ -n "${COUNT:-}" ]; then
    DECK=disc65_n$COUNT
    sed "s/^60, , 10000$/$COUNT/" disc65.inp >"$DECK.inp"
    grep -qx "$COUNT" "$DECK.inp" || { echo "no *FREQUENCY data line to replace" >&2; exit 1; }
    BAND=()
fi

seconds() { # command... -> wall seconds on stdout, the command's output in last.log
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >last.log 2>&1 || { cat last.log >&2; exit 1; }
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc
}
median() { sort -g | awk '{v[NR]=$1} END {print (NR%2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}'; }

# OpenBLAS's kernel moves squeal's factorisations by about 1.5x (Prescott against SkylakeX
# on the disc) and ccx's time not at all: say which one each side runs. squeal pins one
# where OPENBLAS_CORETYPE is unset (src/study/blas_kernel.rs); a value set in the
# environment is used by both programs as it is.
echo "kernel: squeal $("$SQUEAL" info 2>/dev/null | grep -ao 'kernel [A-Za-z0-9]*' | cut -d' ' -f2 || echo '?'), \
ccx ${OPENBLAS_CORETYPE:-the one OpenBLAS picks}" | tee kernel.txt
: >times.txt
for i in $(seq "$REPS"); do
    for n in 1 2; do
        t=$(seconds mpirun --oversubscribe -n $n "$SQUEAL" modes "$DECK.inp" --mass-rule gauss4 \
            "${BAND[@]}" -o "out-$n")
        echo "squeal$n $t $(cut -d' ' -f1 /proc/loadavg)" | tee -a times.txt
    done
    t=$(seconds ccx -i "$DECK")
    echo "ccx $t $(cut -d' ' -f1 /proc/loadavg)" | tee -a times.txt
done
c=$(awk '$1=="ccx" {print $2}' times.txt | median)
for n in 1 2; do
    s=$(awk -v k="squeal$n" '$1==k {print $2}' times.txt | median)
    printf 'squeal, %d rank(s): median %.2f s, %.3f of ccx (median %.2f s)\n' \
        "$n" "$s" "$(echo "$s / $c" | bc -l)" "$c"
done
# Same modes: squeal's frequencies against the ones ccx printed.
DECK=$DECK python3 - <<'EOF'
import csv, os, re
dat = open(os.environ["DECK"] + ".dat").read()
ccx = [float(m.group(1)) for m in
       re.finditer(r"^\s+\d+\s+\S+\s+\S+\s+(\S+)\s+\S+\s*$", dat, re.M)]
for n in (1, 2):
    sq = [float(r["frequency_hz"]) for r in csv.DictReader(open(f"out-{n}/modes.csv"))]
    worst = max(abs(a - b) / b for a, b in zip(sq, ccx))
    print(f"{n} rank(s): {len(sq)} modes, ccx {len(ccx)}; largest relative difference {worst:.1e}")
EOF
