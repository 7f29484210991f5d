#!/bin/bash
# The runs behind docs/validation.md's section "The stage against a CalculiX contact model":
# cases/stage/cycloidal_drive.toml, rigid eccentric bearing, the disc elastic with its 8 output-pin
# holes and a 28 mm bore, crank 0, 206 N*m (stage_ccx.py). Needs what run_all.sh needs. One ccx
# process at a time, one thread. Results under OUT (default /tmp/cx), nothing under the repository.
#
#   bash benchmarks/fe_validation/run_stage.sh [OUT]
set -euo pipefail
OUT=${1:-/tmp/cx}
HERE=$(cd "$(dirname "$0")" && pwd)
PY=/usr/bin/python3
export OMP_NUM_THREADS=1
mkdir -p "$OUT"
# the output pin's rigid core (r_w = 5 mm) that gives ltca's pin-side term of the hole law: 1.010 mm
# at b = 0.1 mm, 1.025 mm at b = 0.325 mm (the loaded output pin's half-width at 4.7 kN); 1.02 used
$PY "$HERE/pin_calibration.py" --radius 5 --cores 0.6,1.0,1.5 --bs 0.1,0.325 --h0 0.005 --out "$OUT/opin" > "$OUT/opin.txt"
run() { local name=$1; shift; $PY "$HERE/stage_ccx.py" "$@" --out "$OUT/$name" > "$OUT/$name.json"; }
# the mesh sequence (each line the run behind a column of the tables)
run s0 --h0 0.05 --hout 0.1 --hdisc 3 --psi 190:210:4
run sA --psi 194:202:2
# sB: the docs' figures are from its increments to 196 and 199 arcsec (stopped before 202: 33 min)
run sB --h0 0.01 --hout 0.02 --dout 0.4 --hhole 0.4 --hdisc 2.0 --psi 196:202:2
# the largest pressure's check: sA with pin 6's contact (the largest pressure) refined to 5 um
run sP6 --fine-pins 6 --h0-fine 0.005 --psi 197:199:1
$PY "$HERE/tabulate_stage.py" --ltca "${LTCA:-build/release/ltca}" "$OUT"/{s0,sA,sB,sP6}
