#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
#
# Measures the MPI messages and bytes each rank sends per time step, by kind
# (particle exchange, ghost values of grid vectors, collectives, and the
# full-mass CG solve), at several rank counts (doc/scaling.md).
#
#   contrib/utilities/mpi_volumes.sh [scene.prm]
#
# Compiles contrib/utilities/mpi_counter.c (a PMPI interposition library)
# into a temporary directory and runs build/applications/benchmark/
# fmpm-benchmark on the scene (default parameters/benchmark_2d.prm) under
# mpirun with it preloaded, for every method, scaling and rank count, each
# with STEPS and 2*STEPS time steps; the difference of the two runs, per
# rank, divided by STEPS is the traffic of one step (set-up, the first
# STEPS steps and the final output cancel). Volumes, not times: ranks may
# oversubscribe the cores.
#
# Environment (defaults in brackets):
#   PROCS       rank counts ["2 4 8 16"]
#   STEPS       N of the N and 2N step runs [10]
#   METHODS     "flip-lumped" (FLIP, lumped mass) and/or "fmpm-full" (FMPM
#               update, exact full mass matrix solved by CG)
#               ["flip-lumped fmpm-full"]
#   SCALINGS    "strong" (the scene as it is) and/or "weak" (Mesh/
#               Subdivisions = WEAK_CELLS*sqrt(P) per direction, so cells and
#               points per rank stay constant) ["strong weak"]
#   WEAK_CELLS  cells per direction of the weak scene at one rank [141]
#   DETAIL      1: also print the traffic per fmpm function (demangled) of
#               the largest run of each method and scaling [0]
#   RESULTS     if set, the per-step figures are also written there as JSON
#   KEEP        1: keep the temporary directory [0]
#   REUSE       a directory that KEEP=1 kept: no runs, only the tables from
#               its counts (same PROCS, STEPS, METHODS, SCALINGS)
#   BUILD_DIR   [build]
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build_dir="${BUILD_DIR:-$here/build}"
benchmark="$build_dir/applications/benchmark/fmpm-benchmark"
scene="$(realpath "${1:-$here/parameters/benchmark_2d.prm}")"
procs="${PROCS:-2 4 8 16}"
steps="${STEPS:-10}"
methods="${METHODS:-flip-lumped fmpm-full}"
scalings="${SCALINGS:-strong weak}"
weak_cells="${WEAK_CELLS:-141}"
python=/usr/bin/python3
[ -x "$python" ] || python=python3

if [ ! -x "$benchmark" ]; then
  echo "mpi_volumes: $benchmark not found; build first" >&2
  exit 1
fi

if [ -n "${REUSE:-}" ]; then
  tmp="$(realpath "$REUSE")"
  methods_runs=""
else
  tmp="$(mktemp -d "${TMPDIR:-/tmp}/mpi_volumes.XXXXXX")"
  methods_runs="$methods"
fi
if [ "${KEEP:-0}" = 1 ] || [ -n "${REUSE:-}" ]; then
  echo "mpi_volumes: keeping $tmp"
else
  trap 'rm -rf "$tmp"' EXIT
fi

[ -n "$methods_runs" ] &&
  mpicc -shared -fPIC -O2 -o "$tmp/libmpi_counter.so" \
    "$here/contrib/utilities/mpi_counter.c" -ldl

export OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

method_settings() {
  case "$1" in
    flip-lumped)
      printf 'subsection Particle update\n  set Model name = flip\nend\n'
      printf 'subsection Mass matrix\n  set Model name = lumped\nend\n' ;;
    fmpm-full)
      # As in fmpm-benchmark --methods: stresses from lumped velocities.
      printf 'subsection Particle update\n  set Model name = fmpm\nend\n'
      printf 'subsection Mass matrix\n  set Model name = full\nend\n'
      printf 'subsection Time\n  set Strain update mass matrix = lumped\nend\n' ;;
    *)
      echo "mpi_volumes: unknown method $1" >&2
      exit 1 ;;
  esac
}

for method in $methods_runs; do
  for scaling in $scalings; do
    for p in $procs; do
      for n in "$steps" "$((2 * steps))"; do
        run="$method-$scaling-$p-$n"
        mkdir -p "$tmp/$run/counts"
        {
          method_settings "$method"
          printf 'subsection Time\n  set Maximum number of steps = %s\nend\n' "$n"
          printf 'subsection Output\n  set Directory = %s\n' "$tmp/$run/output"
          printf '  set Progress interval = 1e9\n  set Write vtu = false\nend\n'
          printf 'subsection Checkpoint\n  set Step interval = 0\n'
          printf '  set Wall time interval = 0\nend\n'
          if [ "$scaling" = weak ]; then
            cells="$("$python" -c "print(round($weak_cells * $p ** 0.5))")"
            printf 'subsection Mesh\n  set Subdivisions = %s, %s\nend\n' \
              "$cells" "$cells"
          fi
        } > "$tmp/$run/override.prm"
        echo "mpi_volumes: $method, $scaling scaling, $p ranks, $n steps" >&2
        if ! mpirun -np "$p" \
            -x LD_PRELOAD="$tmp/libmpi_counter.so" \
            -x MPI_COUNTER_DIR="$tmp/$run/counts" \
            -x MPI_COUNTER_FRAME_PREFIXES=_ZN4fmpm,_ZNK4fmpm \
            "$benchmark" "$scene" -- "$tmp/$run/override.prm" \
            > "$tmp/$run/log" 2>&1; then
          tail -n 30 "$tmp/$run/log" >&2
          echo "mpi_volumes: run $run failed" >&2
          exit 1
        fi
      done
    done
  done
done

# Demangle every context once (c++filt reads one name per line).
"$python" - "$tmp" > "$tmp/mangled.txt" <<'EOF'
import glob, json, sys
names = set()
for path in glob.glob(sys.argv[1] + "/*/counts/rank-*.json"):
    for context, _, _, _ in json.load(open(path))["counts"]:
        names.update(context.split("<-"))
print("\n".join(sorted(names)))
EOF
c++filt < "$tmp/mangled.txt" > "$tmp/demangled.txt"

"$python" - "$tmp" "$steps" "$methods" "$scalings" "$procs" \
  "${DETAIL:-0}" "${RESULTS:-}" <<'EOF'
import glob, json, sys

tmp, steps = sys.argv[1], int(sys.argv[2])
methods, scalings, procs = (a.split() for a in sys.argv[3:6])
detail, results_path = sys.argv[6] == "1", sys.argv[7]
demangled = dict(zip(open(tmp + "/mangled.txt").read().split("\n"),
                     open(tmp + "/demangled.txt").read().split("\n")))

def context_name(context):
    return " <- ".join(demangled.get(c, c) for c in context.split("<-"))

def in_mass_matrix(context):
    return "fmpm::MassMatrix::" in context_name(context)

# The categories of the tables, from (context, kind).
CATEGORIES = ["particle exchange", "particle exchange: collectives",
              "ghost values", "collectives",
              "full-mass solve: ghost values", "full-mass solve: collectives",
              "other point-to-point"]

def category(context, kind):
    if kind.startswith("self:"):
        return None  # one-rank communicators: no traffic
    if kind in ("p2p:particles", "p2p:fmpm-points"):
        return "particle exchange"
    # The sort sends the points that leave the rank to its ghost neighbours
    # (fmpm's neighbour exchange, tag 1100; before 2026-11-26 deal.II's
    # some_to_some(): its data messages, the empty messages and barriers of
    # the consensus algorithm that counts the senders), after the sort's
    # own reduction. Exchanges elsewhere (contact) are not particle exchange.
    if "sort_particles_into_cells" in context_name(context):
        if kind.startswith("coll:"):
            return "particle exchange: collectives"
        if kind in ("p2p:some-to-some", "p2p:dealii-other"):
            return "particle exchange"
    mass = in_mass_matrix(context)
    if kind == "p2p:ghost":
        return "full-mass solve: ghost values" if mass else "ghost values"
    if kind.startswith("coll:"):
        return "full-mass solve: collectives" if mass else "collectives"
    return "other point-to-point"

def load(run):
    ranks = {}
    for path in glob.glob(f"{tmp}/{run}/counts/rank-*.json"):
        data = json.load(open(path))
        ranks[data["rank"]] = data
    summary = json.load(open(f"{tmp}/{run}/output/summary.json"))
    return ranks, summary

def per_rank(data, key):
    """{key(context, kind): [messages, bytes]} of one rank."""
    out = {}
    for context, kind, messages, nbytes in data["counts"]:
        k = key(context, kind)
        if k is None:
            continue
        entry = out.setdefault(k, [0, 0])
        entry[0] += messages
        entry[1] += nbytes
    return out

def per_step(short, long, key):
    """Per rank, {key: [messages, bytes] per step} from the N and 2N runs."""
    out = []
    for rank in sorted(long):
        a, b = per_rank(short[rank], key), per_rank(long[rank], key)
        out.append({k: [(b.get(k, [0, 0])[i] - a.get(k, [0, 0])[i]) / steps
                        for i in range(2)]
                    for k in set(a) | set(b)})
    return out

def cg_iterations(summary):
    return summary.get("cg_iterations_mean", 0) * summary.get("cg_solves", 0)

def fmt(x):
    return f"{x:,.0f}" if abs(x) >= 100 else f"{x:.3g}"

results = []
for method in methods:
    for scaling in scalings:
        for p in procs:
            short, s_summary = load(f"{method}-{scaling}-{p}-{steps}")
            long, l_summary = load(f"{method}-{scaling}-{p}-{2 * steps}")
            ranks = per_step(short, long, category)
            peers = {k: max(r["peers"].get(k, 0) for r in long.values())
                     for k in ("p2p:ghost", "p2p:particles",
                               "p2p:some-to-some", "p2p:fmpm-points")}
            # Particles travel by ParticleHandler (adaptation, the full
            # sort) or by the exchange after the re-bin of every step
            # (some-to-some before 2026-11-26, now to the ghost neighbours).
            peers["p2p:particles"] = max(peers["p2p:particles"],
                                         peers.pop("p2p:some-to-some"),
                                         peers.pop("p2p:fmpm-points"))
            n_points = l_summary["n_particles"]
            iterations = (cg_iterations(l_summary) -
                          cg_iterations(s_summary)) / steps
            print(f"\n### {method}, {scaling} scaling, {p} ranks: "
                  f"{n_points:,} points ({n_points / int(p):,.0f} per rank), "
                  f"{l_summary['n_cells']:,} cells, point imbalance "
                  f"{l_summary.get('point_imbalance', 1):.2f}, "
                  f"most neighbours: {peers['p2p:ghost']} (ghost), "
                  f"{peers['p2p:particles']} (particles)"
                  + (f", CG iterations per step {iterations:.1f}"
                     if iterations else ""))
            print("\n| per rank and step | messages mean | messages max "
                  "| bytes mean | bytes max |\n|---|---|---|---|---|")
            row = {"method": method, "scaling": scaling, "ranks": int(p),
                   "points": n_points, "cells": l_summary["n_cells"],
                   "point_imbalance": l_summary.get("point_imbalance", 1),
                   "neighbours": peers, "cg_iterations_per_step": iterations,
                   "categories": {}}
            for c in CATEGORIES:
                messages = [r.get(c, [0, 0])[0] for r in ranks]
                nbytes = [r.get(c, [0, 0])[1] for r in ranks]
                if max(messages) == 0 and min(messages) == 0:
                    continue
                mean = lambda v: sum(v) / len(v)
                print(f"| {c} | {fmt(mean(messages))} | {fmt(max(messages))} "
                      f"| {fmt(mean(nbytes))} | {fmt(max(nbytes))} |")
                row["categories"][c] = {
                    "messages_mean": mean(messages),
                    "messages_max": max(messages),
                    "bytes_mean": mean(nbytes), "bytes_max": max(nbytes)}
            results.append(row)
        if detail:
            p = procs[-1]
            short, _ = load(f"{method}-{scaling}-{p}-{steps}")
            long, _ = load(f"{method}-{scaling}-{p}-{2 * steps}")
            ranks = per_step(short, long,
                             lambda c, k: None if k.startswith("self:")
                             else (context_name(c), k))
            print(f"\n#### {method}, {scaling}, {p} ranks, per fmpm function "
                  "(mean over ranks per step)\n\n| function | kind | messages "
                  "| bytes |\n|---|---|---|---|")
            keys = sorted({k for r in ranks for k in r},
                          key=lambda k: -sum(r.get(k, [0, 0])[1]
                                             for r in ranks))
            for k in keys:
                messages = sum(r.get(k, [0, 0])[0] for r in ranks) / len(ranks)
                nbytes = sum(r.get(k, [0, 0])[1] for r in ranks) / len(ranks)
                if abs(messages) < 1e-9:
                    continue
                print(f"| {k[0][:110]} | {k[1]} | {fmt(messages)} "
                      f"| {fmt(nbytes)} |")
if results_path:
    json.dump(results, open(results_path, "w"), indent=1)
EOF
