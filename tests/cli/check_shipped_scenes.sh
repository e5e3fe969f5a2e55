#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Every scene in parameters/ starts and takes its first steps without a
# warning or note about its own settings (lines naming its output folder,
# which holds the word in the test's name, aside).
#
#   check_shipped_scenes.sh FMPM PARAMETERS_DIR
set -u
fmpm="$1"; parameters="$2"
fail=0
rm -rf shipped-scenes; mkdir shipped-scenes; cd shipped-scenes || exit 1
printf 'subsection Time\n set Maximum number of steps = 2\nend\nsubsection Output\n set Directory = %s/out\n set Write vtu = false\nend\nsubsection Timer\n set Type = none\nend\n' "$PWD" > short.prm
for scene in "$parameters"/*.prm; do
  name=$(basename "$scene" .prm)
  (cd "$parameters" && "$fmpm" "$scene" "$OLDPWD/short.prm") > "$name.log" 2>&1
  code=$?
  if [ "$code" -ne 0 ]; then
    tail -5 "$name.log"; echo "FAIL: $name exits with $code"; fail=1
  elif grep -v -F "$PWD" "$name.log" | grep -i -E "warning|note:"; then
    echo "FAIL: $name warns about its settings"; fail=1
  else
    echo "ok: $name"
  fi
done
[ "$fail" -eq 0 ] && echo PASS
exit "$fail"
