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
# Each line is the run behind a figure of the docs, with the options it was run with (a later
# option overrides run()'s --first-inc 0.5). P39 = the contacts refined: pins 3-9.
P39=3,4,5,6,7,8,9
# bore 22, crank 0: the convergence sequence (contact size h0, body size hdisc, growth)
run h10 --h0 0.01 --psi 21:27:4 --first-inc 0.1 &          # every modelled pin (2-12) refined
run h5 --h0 0.005 --refine $P39 --psi 23:25:2 --first-inc 1
wait
run h10b --h0 0.01 --hdisc 0.75 --refine $P39 --psi 23:25:2 &
run h10g --h0 0.01 --grow 0.12 --refine $P39 --psi 23:25:2
wait
# bore 22, crank 4.5 deg; bore 50, crank 0
run c45h10 --crank-deg 4.5 --h0 0.01 --refine $P39,10 --psi 22:26:2 --first-inc 1 &
run b50 --bore 50 --h0 0.01 --refine $P39 --psi 11:15:2 --first-inc 1
wait
# bore 12, crank 0; the disc elastic only within 2 mm of the contacts (E x 1000 beyond), bore 22
run b12 --bore 12 --h0 0.01 --refine $P39 --psi 40:46:3 &
run local2 --local 2 --h0 0.01 --refine $P39 --psi 8:12:2
wait
run local1 --local 1 --h0 0.01 --refine $P39 --psi 8:12:2 &
run local3 --local 3 --h0 0.01 --refine $P39 --psi 8:12:2
wait
# crank 4.5 deg and bore 12 at h0 = 5 um (the figures of the tables)
run c45h5 --crank-deg 4.5 --h0 0.005 --refine $P39,10 --psi 23:25:2 &
run b12h5 --bore 12 --h0 0.005 --refine $P39 --psi 42:44:2
wait
$PY "$HERE/tabulate.py" --ltca "${LTCA:-build/release/ltca}" "$OUT"/{h10,h5,h10b,h10g,c45h10,c45h5,b12,b12h5,b50,local1,local2,local3}
