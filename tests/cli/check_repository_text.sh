#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The repository speaks of fmpm to its users: no tracked text file names a
# path of the machine it was built on (a home, /root or /work folder, a
# folder beside the checkout) or tells how fmpm was made (stretches of work,
# issue numbers). Binary files are skipped. The patterns are written so that
# this file does not match them itself.
#
#   check_repository_text.sh SOURCE_DIR
# Exit code 77 (skipped): SOURCE_DIR is not a git checkout.
set -u
cd "$1" || exit 1
if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "SKIP: $1 is not a git checkout (the files are taken from git ls-files)"
  exit 77
fi
fail=0
check() { # description, extended regex, grep flags
  local hits
  hits=$(git ls-files -z | xargs -0 grep -nIE $3 -e "$2" -- 2>/dev/null)
  if [ -n "$hits" ]; then
    echo "$hits"; echo "FAIL: $1"; fail=1
  else
    echo "ok: no $1"
  fi
}
check "path of a build machine" '/(work|root)/|/home/[a-z]' ""
check "path beside the checkout" '\.\./(shared|work)/' ""
check "stretches of work" '\b[s]essions?\b' -i
check "issue numbers" '\b[i]ssues? #?[0-9]|\b[i]ssue#' -i
[ "$fail" -eq 0 ] && echo PASS
exit "$fail"
