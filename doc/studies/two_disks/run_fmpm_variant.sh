#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Runs a variant of parameters/two_disks.prm and prints E(t)/E0 at 4-16 ms.
# usage: run_fmpm_variant.sh NAME FMPM_BINARY [extra prm text on stdin]
#   -> $OUT/NAME/history.csv (OUT defaults to ./two_disks_runs)
name=$1; bin=$2
here=$(cd "$(dirname "$0")" && pwd)
d=${OUT:-$PWD/two_disks_runs}/$name; rm -rf "$d"; mkdir -p "$d"
sed 's#set Directory = output-two-disks#set Directory = '"$d"'#' "$here/../../../parameters/two_disks.prm" > "$d/scene.prm"
cat >> "$d/scene.prm"
start=$(date +%s.%N)
"$bin" "$d/scene.prm" > "$d/log.txt" 2>&1; rc=$?
end=$(date +%s.%N)
python3 - "$d" $rc $start $end <<'PY'
import csv,sys
d,rc,s,e=sys.argv[1],sys.argv[2],float(sys.argv[3]),float(sys.argv[4])
rows=list(csv.DictReader(open(d+'/history.csv')))
E0=float(rows[0]['total_energy'])
def at(t):
    r=min(rows,key=lambda r:abs(float(r['time'])-t)); return float(r['total_energy'])/E0
print(f"{d.split('/')[-1]:40s} rc={rc} wall={e-s:.0f}s E0={E0:.6g} steps={rows[-1].get('step','?')} t_end={float(rows[-1]['time']):.6g} "+" ".join(f"E({t*1e3:g})={at(t):.5f}" for t in (0.004,0.008,0.010,0.012,0.016)))
PY
