#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# --resume with a missing, incomplete, corrupt or foreign checkpoint stops
# with exit code 1 and a message naming the file and what is wrong.
#
#   check_resume_errors.sh FMPM SOURCE_DIR
set -u
fmpm="$1"; source_dir="$2"
disks="$source_dir/../../parameters/colliding_disks.prm"
block_3d="$source_dir/../prm/translating_block_3d.prm"
fail() { echo "FAIL: $*"; exit 1; }
expect_error() { # expected message, then the command
  local message="$1"; shift
  "$@" > log.txt 2>&1
  local code=$?
  [ "$code" -eq 1 ] || { cat log.txt | tail -5; fail "exit code $code (expected 1) for: $message"; }
  grep -qF -- "$message" log.txt || { cat log.txt | tail -5; fail "no message <$message>"; }
}
rm -rf resume-errors; mkdir resume-errors; cd resume-errors || exit 1
printf 'subsection Output\n set Directory = out\n set Write vtu = false\nend\nsubsection Time\n set Maximum number of steps = 4\nend\nsubsection Checkpoint\n set Step interval = 2\n set Keep = 1\nend\nsubsection Timer\n set Type = none\nend\n' > out.prm

expect_error "Cannot resume: there is no complete checkpoint in <out/checkpoint>" \
  "$fmpm" --resume "$disks" out.prm
"$fmpm" "$disks" out.prm > run.log 2>&1 || { tail run.log; fail "the run writing checkpoints"; }
[ -d out/checkpoint/step-000004 ] || fail "no checkpoint step-000004"
[ -d out/checkpoint/step-000002 ] && fail "Keep = 1 kept step-000002"

cp -r out/checkpoint/step-000004 saved
rm out/checkpoint/step-000004/mesh.info
expect_error "Cannot resume from the checkpoint <out/checkpoint/step-000004>: it is incomplete, missing <out/checkpoint/step-000004/mesh.info>" \
  "$fmpm" --resume "$disks" out.prm

rm -rf out/checkpoint/step-000004; cp -r saved out/checkpoint/step-000004
head -c 100 saved/state.bin > out/checkpoint/step-000004/state.bin
expect_error "The checkpoint file <out/checkpoint/step-000004/state.bin> is corrupt or truncated" \
  "$fmpm" --resume "$disks" out.prm

rm -rf out/checkpoint/step-000004; cp -r saved out/checkpoint/step-000004
expect_error "The checkpoint <out/checkpoint/step-000004/state.bin> was written by a 2D run, but the scene is 3D" \
  "$fmpm" --resume "$block_3d" out.prm

printf 'subsection Mesh\n set Subdivisions = 10, 10\nend\n' > other_mesh.prm
expect_error "was written by another scene: it has 400 coarse cells and" \
  "$fmpm" --resume "$disks" out.prm other_mesh.prm

# The intact checkpoint resumes.
"$fmpm" --resume "$disks" out.prm > resume.log 2>&1 || { tail resume.log; fail "resume from the intact checkpoint"; }
echo PASS
