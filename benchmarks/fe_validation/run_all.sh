#!/bin/bash
# The runs behind docs/validation.md's section "The elastic disc against a CalculiX contact model".
# Needs: apt-get install -y --no-install-recommends calculix-ccx gmsh python3-gmsh (CalculiX 2.20,
# gmsh 4.8 with its Python module; /usr/bin/python3 with numpy) and ltca's release build for the
# rigid comparison (tabulate.py). Each run is one ccx process on one thread (OMP_NUM_THREADS=1);
# two run at once here. Results go under OUT (default /tmp/cx), nothing under the repository.
# Wall times on the shared 2-core machine: 10-40 min a run.
#
#   bash benchmarks/fe_validation/run_all.sh [OUT]
set -euo pipefail
OUT=${1:-/tmp/cx}
HERE=$(cd "$(dirname "$0")" && pwd)
PY=/usr/bin/python3
run() { local name=$1; shift; $PY "$HERE/liu52_ccx.py" --core 0.606 --first-inc 0.5 "$@" --out "$OUT/$name" > "$OUT/$name.json"; }
mkdir -p "$OUT"
# the pin's core radius that gives ltca's pin term (0.606 mm)
$PY "$HERE/pin_calibration.py" --out "$OUT/pin" > "$OUT/pin.txt"
# bore 22, crank 0: the convergence sequence (contact size h0, body size hdisc)
run h10 --h0 0.01 --refine 3,4,5,6,7,8,9 --psi 22:26:2 &
run h5 --h0 0.005 --refine 3,4,5,6,7,8,9 --psi 23:25:2
wait
run h10b --h0 0.01 --hdisc 0.75 --refine 3,4,5,6,7,8,9 --psi 22:26:2 &
# bore 22, crank 4.5 deg
run c45h10 --crank-deg 4.5 --h0 0.01 --refine 3,4,5,6,7,8,9,10 --psi 22:26:2
wait
# bores 12 and 50 mm, crank 0
run b12 --bore 12 --h0 0.01 --refine 3,4,5,6,7,8,9 --psi 40:46:3 &
run b50 --bore 50 --h0 0.01 --refine 3,4,5,6,7,8,9 --psi 11:15:2
wait
# the disc elastic only within 2 mm of the contacts (E x 1000 beyond), bore 22, crank 0
run local2 --local 2 --h0 0.01 --refine 3,4,5,6,7,8,9 --psi 8:12:2
$PY "$HERE/tabulate.py" --ltca "${LTCA:-build/release/ltca}" "$OUT"/{h10,h5,h10b,c45h10,b12,b50,local2}
