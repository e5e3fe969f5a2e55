# SPDX-License-Identifier: LGPL-2.1-or-later
# Shared by the NairnMPM twin scripts (nairn_bar.sh, nairn_disk_impact.sh, nairn_rotation.sh, ...):
# source it, then
#   nairn_binary               sets $nairn_bin (NAIRN, or $NAIRN_DIR/bin/NairnMPM, default ~/.nairn/bin)
#   nairn_task VARIANT         prints the <CustomTasks> body for FLIP | PIC | XPIC<k> | FMPM<k>
#   nairn_workdir PREFIX       makes and enters a fresh temporary folder
#   nairn_run THREADS [keep-going]  runs in.xml there (output.txt), sets $nairn_wall (seconds);
#                              a failed run stops the script unless keep-going is given
# and read the results in Python with contrib/utilities/nairn_results.py.
# NairnMPM: github.com/nairnj/nairn-mpm-fea, built with 'make SYSTEM=mpm'; NairnMPM.dtd beside it.

nairn_binary() {
  nairn_bin=${NAIRN:-${NAIRN_DIR:-$HOME/.nairn}/bin/NairnMPM}
  [[ -x $nairn_bin ]] || {
    echo "NairnMPM not found at $nairn_bin: build it from github.com/nairnj/nairn-mpm-fea and set NAIRN" >&2
    exit 1
  }
}

nairn_task() {
  local schedule='<Schedule name="PeriodicXPIC"><Parameter name="%s">%s</Parameter><Parameter name="periodicSteps">1</Parameter></Schedule>'
  case $1 in
    FLIP) ;;
    PIC) printf "$schedule" FMPMOrder 1 ;;
    XPIC*) printf "$schedule" XPICOrder "${1#XPIC}" ;;
    FMPM*) printf "$schedule" FMPMOrder "${1#FMPM}" ;;
    *) echo "unknown variant $1: FLIP, PIC, XPIC<k> or FMPM<k>" >&2; exit 2 ;;
  esac
}

# <CustomTasks> element for VARIANT, or nothing for FLIP.
nairn_custom_tasks() {
  local task; task=$(nairn_task "$1")
  [[ -n $task ]] && echo "  <CustomTasks>$task</CustomTasks>"
  return 0
}

nairn_workdir() {
  cd "$(mktemp -d -t "$1.XXXXXX")"
}

nairn_run() {
  cp "$(dirname "$nairn_bin")/NairnMPM.dtd" .
  local start; start=$(date +%s.%N)
  "$nairn_bin" -np "$1" in.xml > output.txt 2>&1 || {
    echo "NairnMPM failed: $(tail -3 output.txt | tr '\n' ' ')" >&2
    [[ ${2:-} == keep-going ]] || exit 1
  }
  nairn_wall=$(awk "BEGIN{print $(date +%s.%N) - $start}")
}
