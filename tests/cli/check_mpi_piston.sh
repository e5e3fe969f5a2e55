#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# MPI gives the serial physics with velocity conditions: the piston with the
# 'collection full' method (a dense system over the conditions of both
# ranks) and FMPM(3) on 1 and 2 ranks: history.csv, reactions included,
# agrees to 1e-8 (relative).
set -u
fmpm="$1"; source_dir="$2"; shift 2
mpiexec=("$@")
for ranks in 1 2; do
  rm -rf "output-piston-mpi-$ranks"
  printf 'subsection Mass matrix\n set Model name = fmpm\n subsection Fmpm\n  set Order = 3\n end\nend\nsubsection Boundary conditions\n set Method = collection full\nend\nsubsection Time\n set End time = 0.05\nend\nsubsection Output\n set Directory = output-piston-mpi-%s\nend\n' "$ranks" > "piston-mpi-$ranks.prm"
done
"$fmpm" "$source_dir/../../parameters/piston.prm" piston-mpi-1.prm > log-1.txt 2>&1 || { tail log-1.txt; echo "FAIL: serial run"; exit 1; }
"${mpiexec[@]}" "$fmpm" "$source_dir/../../parameters/piston.prm" piston-mpi-2.prm > log-2.txt 2>&1 || { tail log-2.txt; echo "FAIL: 2-rank run"; exit 1; }
grep -q "2 MPI rank" log-2.txt || { echo "FAIL: not on 2 ranks"; exit 1; }
head -1 output-piston-mpi-1/history.csv | grep -q reaction_0_x || { echo "FAIL: no reaction columns"; exit 1; }
numdiff -q -r 1e-8 -a 1e-14 -s ', \n' output-piston-mpi-1/history.csv output-piston-mpi-2/history.csv \
  || { numdiff -r 1e-8 -a 1e-14 -s ', \n' output-piston-mpi-1/history.csv output-piston-mpi-2/history.csv | head -20; echo "FAIL: 1 and 2 ranks differ"; exit 1; }
echo PASS
