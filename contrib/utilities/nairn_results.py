# SPDX-License-Identifier: LGPL-2.1-or-later
"""Reads a NairnMPM run of the twin scripts (contrib/utilities/nairn_*.sh): the steps and points
from output.txt and the global archive (*.global) as rows and a column index by quantity name."""
import glob
import re


def load(folder='.'):
    out = open(f'{folder}/output.txt').read()
    steps = int(re.search(r'Calculation Steps:\s*(\d+)', out).group(1))
    points = int(re.search(r'Number of Material Points:\s*(\d+)', out).group(1))
    lines = open(glob.glob(f'{folder}/Results*/*.global')[0]).readlines()
    names = re.findall(r'"([^"]+)"', lines[0] + lines[1])
    rows = [list(map(float, l.split())) for l in lines if l.strip() and not l.startswith('#')]
    column = {n: i + 1 for i, n in enumerate(names)}
    return steps, points, rows, column
