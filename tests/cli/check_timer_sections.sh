#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The TimerOutput sections of a run are the stages the run header prints
# ("each step: ..."), one section per stage and named as it, besides the
# sections of the run (set-up, output, ...) and of every step's frame (set-up,
# end, failure checks), and sub-sections "<part>: <detail>" that run within
# them. A stage or section renamed on one side only fails here. Runs the
# colliding disks with three strain-update schemes (USF; USL-; USAVG+, which
# re-extrapolates the momenta) and a scene of two materials in contact.
#
#   check_timer_sections.sh FMPM SOURCE_DIR
set -u
fmpm="$1"; source_dir="$2"
root="$source_dir/../.."
fail() { echo "FAIL: $*"; exit 1; }
rm -rf timer-sections; mkdir timer-sections; cd timer-sections || exit 1

check() { # name, scene
  local name="$1" scene="$2"
  printf "subsection Output\n set Directory = %s\n set Write vtu = false\nend\nsubsection Time\n set Maximum number of steps = 6\n%s\nend\n" \
    "$name" "$scheme" > "$name.prm"
  "$fmpm" "$root/parameters/$scene.prm" "$name.prm" > "$name.log" 2>&1 || { tail "$name.log"; fail "$name run"; }
  python3 - "$name.log" <<'PY' || fail "$name: timer sections differ from the printed stages"
import re, sys
log = open(sys.argv[1]).read().splitlines()
stages = [l.split("each step:", 1)[1].strip() for l in log if "each step:" in l]
assert len(stages) == 1, "no 'each step:' line in the run header"
stages = set(s.strip() for s in stages[0].split(","))
sections, in_table = set(), False
for l in log:
    if l.startswith("| Section"):
        in_table = True
    elif in_table and l.startswith("|"):
        sections.add(l.split("|")[1].strip())
run = {"setup", "run start", "output", "progress", "statistics", "summary",
       "vtu points", "vtu grid", "vtu records", "vtu writer", "checkpoint",
       "mesh adaptation", "step set-up", "step end", "failure checks"}
top = {s for s in sections if ": " not in s} - run
print("stages:  ", sorted(stages))
print("sections:", sorted(top), "sub-sections:",
      sorted(s for s in sections if ": " in s))
sys.exit(0 if sections and top == stages else 1)
PY
  echo "ok: $name"
}

scheme="set Strain update = usf"; check usf colliding_disks
scheme="set Strain update = usl"; check usl colliding_disks
scheme="set Strain update = usavg+"; check usavg_plus colliding_disks
scheme=""; check contact benchmark_contact_2d
grep -q "contact: corrections" contact.log || fail "the contact run has no 'contact: corrections' sub-section"
echo PASS
