#!/usr/bin/env python3
"""Run a parameter study of fmpm and draw charts of the results.

A *study file* (format described in contrib/studies/README.md) names a base
parameter file and the parameters to sweep.  This script

1. expands the swept axes into a list of runs (product of the axes, linked
   axes varying together) and writes the plan to ``<out>/runs.csv``;
2. runs ``fmpm <base.prm> <out>/run_NNNN/override.prm`` for each run
   (optionally several at once, under mpirun, with a timeout), skipping runs
   already done by an earlier invocation;
3. collects every run's ``summary.json`` into ``<out>/results.csv``;
4. draws PNG charts (error against wall time, convergence, stability map,
   energy history) with matplotlib into ``<out>/``.

Usage::

    fmpm_study.py STUDY_FILE [--output DIR] [--fmpm PATH] [--quick]
                  [--jobs N] [--plot-only] [--timeout SECONDS] [--no-charts]

Exit status: 0 when the pipeline worked (failed runs are data), 2 for a bad
study file or command line, 1 when no run produced a summary.
"""

import argparse
import ast
import bisect
import concurrent.futures
import csv
import itertools
import json
import math
import operator
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

#: Name of the axis that sets the number of MPI ranks instead of a parameter.
MPI_AXIS = "MPI ranks"

#: Name of the axis (or linked member) that only names runs in charts
#: (``chart method = Label``); it is not written to the parameter file.
LABEL_AXIS = "Label"

#: Pseudo-parameters that are not fmpm parameters.
NOT_PARAMETERS = (MPI_AXIS, LABEL_AXIS)

#: The parameter the runner sets itself in every override file.
OUTPUT_DIRECTORY = "Output/Directory"

#: Keys allowed in ``chart KEY = VALUE`` lines, with their meaning.
CHART_KEYS = {
    "x_resolution": "parameter whose first number is the resolution n",
    "cell_size": "expression in n giving the cell size h (default 1/n)",
    "method": "parameter(s) naming a curve, several joined with ' + '",
    "error": "summary.json key plotted as the error",
    "stability_x": "parameter on the x axis of the stability map",
    "stability_y": "parameter on the y axis of the stability map",
    "energy_resolution": "resolution n of the runs in the energy history "
                         "(default: the finest per method)",
    "skip": "charts not to draw, by file stem, separated by ',' (e.g. "
            "'energy_history, stability_limits')",
}

KEYWORDS = ("base", "title", "axis", "linked", "set", "chart",
            "reference", "reference columns",
            "quick axis", "quick linked", "quick set")

#: Run id and directory name of the converged fine reference run.
REFERENCE_ID = "reference"

#: history.csv columns compared with the reference run by default.
DEFAULT_REFERENCE_COLUMNS = ("kinetic_energy", "strain_energy",
                             "total_energy")

DEFAULT_ERROR_KEY = "error_velocity_l2"

#: summary.json keys copied into results.csv, in column order.
SUMMARY_COLUMNS = [
    "status", "failure_step", "failure_time", "n_particles", "n_cells",
    "n_dofs", "n_steps", "n_mpi_ranks", "wall_seconds",
    "particle_steps_per_second", "error_velocity_l2",
    "error_displacement_l2", "energy_error", "final_kinetic_energy",
    "final_strain_energy", "final_total_energy", "initial_total_energy",
    "dissipated_energy",
]

#: Columns written by the runner itself after the summary columns.
RUNNER_COLUMNS = ["exit_code", "elapsed_seconds"]

CHART_FILES = ["error_vs_wall_time.png", "convergence.png",
               "stability_map.png", "stability_limits.png",
               "energy_history.png"]

#: Files kept in a run directory by --prune (the rest, e.g. fmpm's log and
#: parameter echo, is deleted once the results are collected).
KEPT_RUN_FILES = ("override.prm", "run.json", "summary.json", "history.csv")

#: Reference-solution errors whose convergence orders are always reported.
ERROR_KEYS = ("error_velocity_l2", "error_displacement_l2")


# ---------------------------------------------------------------------------
# Study file
# ---------------------------------------------------------------------------

class StudyError(Exception):
    """A problem in a study file, reported as ``FILE:LINE: message``."""

    def __init__(self, path, line, message):
        location = f"{path}:{line}" if line else f"{path}"
        super().__init__(f"{location}: {message}")
        self.path = path
        self.line = line


@dataclass
class Axis:
    """One dimension of the sweep.

    A plain axis has one parameter path; a linked group has several paths
    whose values vary together, so ``values[i]`` holds one value per path.
    """

    name: str
    paths: list
    values: list
    line: int
    linked: bool = False


@dataclass
class Study:
    """A parsed study file."""

    path: Path
    base: Path
    title: str
    axes: list
    fixed: dict
    charts: dict
    cell_size: object = None  # compiled expression in n, or None
    reference: dict = None    # overrides of the reference run, or None
    reference_columns: tuple = DEFAULT_REFERENCE_COLUMNS

    @property
    def reference_keys(self):
        """results.csv columns of the errors against the reference run."""
        if self.reference is None:
            return []
        return [f"error_reference_{c}" for c in self.reference_columns]

    @property
    def swept_paths(self):
        """All swept parameter paths, in axis order."""
        return [p for axis in self.axes for p in axis.paths]


@dataclass
class Run:
    """One fmpm run of the study."""

    index: int
    run_id: str
    swept: dict      # path -> value of every swept parameter (incl. MPI ranks)
    settings: dict   # path -> value written to override.prm
    mpi_ranks: int
    directory: Path
    shown: tuple = None  # the swept values in the label (None: all)

    def label(self):
        """Short label of the swept values, e.g. ``flip 32,2``; a linked
        group with a Label member shows only the label."""
        values = self.swept.values() if self.shown is None else self.shown
        return " ".join(re.sub(r"\s+", "", v) for v in values)


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def first_number(text):
    """Return the first number in ``text`` as a float, or None."""
    match = _NUMBER.search(text or "")
    return float(match.group()) if match else None


_ALLOWED_OPS = {
    ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
    ast.Div: operator.truediv, ast.Pow: operator.pow,
    ast.USub: operator.neg, ast.UAdd: operator.pos,
}


def compile_cell_size(expression):
    """Check an arithmetic expression in ``n``; return its AST.

    Only numbers, ``n``, ``+ - * / **`` and parentheses are allowed.
    Raises ValueError otherwise.
    """
    try:
        tree = ast.parse(expression, mode="eval")
    except SyntaxError as error:
        raise ValueError(f"not an expression: {error.msg}") from None
    for node in ast.walk(tree):
        allowed = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Constant,
                   ast.Name, ast.Load) + tuple(_ALLOWED_OPS)
        if not isinstance(node, allowed):
            raise ValueError(f"'{type(node).__name__}' is not allowed "
                             "(use numbers, n, + - * / ** and parentheses)")
        if isinstance(node, ast.Name) and node.id != "n":
            raise ValueError(f"unknown name '{node.id}' (only n is known)")
        if isinstance(node, ast.Constant) and not isinstance(
                node.value, (int, float)):
            raise ValueError("only numbers are allowed as constants")
    return tree


def evaluate_cell_size(tree, n):
    """Evaluate a tree from :func:`compile_cell_size` for resolution n."""

    def walk(node):
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            return float(n)
        if isinstance(node, ast.UnaryOp):
            return _ALLOWED_OPS[type(node.op)](walk(node.operand))
        return _ALLOWED_OPS[type(node.op)](walk(node.left), walk(node.right))

    return walk(tree)


def _split_assignment(text, path, line, what):
    """Split ``LEFT = RIGHT`` into stripped parts, or raise StudyError."""
    if "=" not in text:
        raise StudyError(path, line, f"'{what}' line needs '=': "
                         f"expected '{what} NAME = VALUE'")
    left, right = text.split("=", 1)
    left, right = left.strip(), right.strip()
    if not left:
        raise StudyError(path, line, f"'{what}' line has no name before '='")
    return left, right


def _split_values(text, path, line, name):
    """Split ``a | b | c`` into a list of values, or raise StudyError."""
    if not text.strip():
        raise StudyError(path, line, f"axis '{name}' has no values: "
                         "expected values separated by '|', e.g. 'a | b'")
    values = [v.strip() for v in text.split("|")]
    if any(not v for v in values):
        raise StudyError(path, line, f"axis '{name}' has an empty value "
                         "between '|' separators")
    return values


def _check_mpi_value(value, path, line):
    if not re.fullmatch(r"\d+", value) or int(value) < 1:
        raise StudyError(path, line, f"'{MPI_AXIS}' value '{value}' is not "
                         "a positive integer")


def parse_study(path, quick=False):
    """Parse a study file and return a :class:`Study`.

    With ``quick``, ``quick axis``/``quick linked`` lines replace the values
    of the same-named axis and ``quick set`` lines add fixed settings.
    Raises :class:`StudyError` naming the file and line of any problem.
    """
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except OSError as error:
        raise StudyError(path, 0, f"cannot read study file: "
                         f"{error.strerror}") from None

    base = title = None
    axes = []           # Axis objects in order of first appearance
    axis_of_path = {}   # path -> (axis, index in axis.paths)
    groups = {}         # linked group name -> Axis
    fixed, fixed_lines = {}, {}
    charts = {}
    cell_size = None
    quick_axes = []     # (line, group or None, path, values)
    quick_sets = []     # (line, path, value)
    reference = None
    reference_columns = DEFAULT_REFERENCE_COLUMNS

    for number, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        match = re.match(r"(quick\s+)?([A-Za-z_]+)\s*(.*)$", text)
        keyword = match.group(2) if match else ""
        rest = match.group(3) if match else ""
        if match and match.group(1):
            keyword = "quick " + keyword
        columns = re.match(r"columns\s*(=.*)$", rest)
        if keyword == "reference" and columns:
            keyword, rest = "reference columns", columns.group(1)
        if keyword not in KEYWORDS:
            shown = text.split()[0] if text.split() else text
            raise StudyError(path, number, f"unknown keyword '{shown}'; "
                             f"allowed: {', '.join(KEYWORDS)}")

        if keyword == "reference":
            if reference is not None:
                raise StudyError(path, number, "'reference' given twice")
            if not rest.startswith("="):
                raise StudyError(path, number, "expected 'reference = "
                                 "PATH = VALUE | PATH = VALUE ...'")
            reference = _parse_reference(rest[1:], path, number)
        elif keyword == "reference columns":
            reference_columns = tuple(
                c.strip() for c in rest[1:].split(",") if c.strip())
            if not reference_columns:
                raise StudyError(path, number, "'reference columns' has no "
                                 "history.csv column, e.g. "
                                 "'reference columns = kinetic_energy'")
        elif keyword in ("base", "title"):
            if not rest.startswith("="):
                raise StudyError(path, number, f"expected '{keyword} = ...'")
            value = rest[1:].strip()
            if keyword == "base":
                if base is not None:
                    raise StudyError(path, number, "'base' given twice")
                if not value:
                    raise StudyError(path, number, "'base' has no value: "
                                     "expected 'base = FILE.prm'")
                base = (path.parent / value).resolve()
                if not base.is_file():
                    raise StudyError(path, number,
                                     f"base parameter file '{value}' not "
                                     f"found (looked for {base})")
            else:
                title = value
        elif keyword in ("axis", "quick axis"):
            name, values = _split_assignment(rest, path, number, keyword)
            values = _split_values(values, path, number, name)
            if name == MPI_AXIS:
                for value in values:
                    _check_mpi_value(value, path, number)
            if keyword == "quick axis":
                quick_axes.append((number, None, name, values))
                continue
            if name in axis_of_path:
                raise StudyError(path, number, f"parameter '{name}' is "
                                 "already an axis")
            axis = Axis(name, [name], [(v,) for v in values], number)
            axes.append(axis)
            axis_of_path[name] = (axis, 0)
        elif keyword in ("linked", "quick linked"):
            parts = rest.split(None, 1)
            if len(parts) < 2 or parts[0].startswith("="):
                raise StudyError(path, number, f"expected '{keyword} GROUP "
                                 "PARAMETER = v1 | v2 | ...'")
            group = parts[0]
            name, values = _split_assignment(parts[1], path, number, keyword)
            values = _split_values(values, path, number, name)
            if name == MPI_AXIS:
                for value in values:
                    _check_mpi_value(value, path, number)
            if keyword == "quick linked":
                quick_axes.append((number, group, name, values))
                continue
            if name in axis_of_path:
                raise StudyError(path, number, f"parameter '{name}' is "
                                 "already an axis")
            axis = groups.get(group)
            if axis is None:
                axis = Axis(group, [], [], number, linked=True)
                groups[group] = axis
                axes.append(axis)
            if axis.paths and len(values) != len(axis.values):
                raise StudyError(path, number, f"linked group '{group}' has "
                                 f"{len(axis.values)} values per parameter "
                                 f"but '{name}' has {len(values)}")
            if not axis.paths:
                axis.values = [() for _ in values]
            axis.values = [old + (v,) for old, v in zip(axis.values, values)]
            axis_of_path[name] = (axis, len(axis.paths))
            axis.paths.append(name)
        elif keyword in ("set", "quick set"):
            name, value = _split_assignment(rest, path, number, keyword)
            if name == OUTPUT_DIRECTORY:
                raise StudyError(path, number, f"'{OUTPUT_DIRECTORY}' is set "
                                 "by the runner (one directory per run)")
            if name == MPI_AXIS:
                _check_mpi_value(value, path, number)
            if keyword == "quick set":
                quick_sets.append((number, name, value))
            else:
                fixed[name] = value
                fixed_lines[name] = number
        else:  # chart
            key, value = _split_assignment(rest, path, number, keyword)
            key = re.sub(r"\s+", "_", key)
            if key not in CHART_KEYS:
                raise StudyError(path, number, f"unknown chart key '{key}'; "
                                 f"allowed: {', '.join(CHART_KEYS)}")
            if not value:
                raise StudyError(path, number, f"chart key '{key}' has no "
                                 "value")
            if key in ("x_resolution", "stability_x", "stability_y") and (
                    " + " in value):
                raise StudyError(path, number, f"chart key '{key}' takes one "
                                 "parameter path")
            if key == "cell_size":
                try:
                    cell_size = compile_cell_size(value)
                except ValueError as error:
                    raise StudyError(path, number, f"bad cell size "
                                     f"expression '{value}': {error}"
                                     ) from None
            charts[key] = value

    if base is None:
        raise StudyError(path, 0, "missing 'base = FILE.prm' line (the "
                         "parameter file every run starts from)")

    _apply_quick(path, axes, axis_of_path, quick_axes, apply=quick)
    if quick:
        for number, name, value in quick_sets:
            if name in axis_of_path:
                raise StudyError(path, number, f"quick set: '{name}' is an "
                                 "axis; use 'quick axis' to change it")
            fixed[name] = value
            fixed_lines[name] = number

    for name, number in fixed_lines.items():
        if name in axis_of_path:
            raise StudyError(path, number, f"'{name}' is both set and swept")

    return Study(path=path, base=base, title=title or path.stem, axes=axes,
                 fixed=fixed, charts=charts, cell_size=cell_size,
                 reference=reference, reference_columns=reference_columns)


def _parse_reference(text, path, line):
    """Parse ``PATH = VALUE | PATH = VALUE`` of a ``reference`` line into a
    dict, or raise StudyError."""
    overrides = {}
    for part in text.split("|"):
        if "=" not in part:
            raise StudyError(path, line, f"reference: '{part.strip()}' is "
                             "not 'PATH = VALUE' (pairs separated by '|')")
        name, value = (s.strip() for s in part.split("=", 1))
        if not name:
            raise StudyError(path, line, "reference: a pair has no "
                             "parameter before '='")
        if name in (OUTPUT_DIRECTORY, LABEL_AXIS):
            raise StudyError(path, line, f"reference: '{name}' cannot be "
                             "set for the reference run")
        if name == MPI_AXIS:
            _check_mpi_value(value, path, line)
        overrides[name] = value
    return overrides


def _apply_quick(path, axes, axis_of_path, quick_axes, apply):
    """Replace axis values by those of ``quick axis``/``quick linked`` lines.

    ``quick_axes`` holds (line, linked group or None, parameter, values).
    Members of a linked group that are not replaced keep their values, so
    a group whose length changes must have all its members replaced.  The
    lines are checked even when not ``apply``-ing them (normal mode), so a
    broken quick line is reported at once.
    """
    replacements = {}  # id(axis) -> {member index: (values, line)}
    for number, group, name, values in quick_axes:
        axis, index = axis_of_path.get(name, (None, None))
        if axis is None or axis.linked != (group is not None) or (
                group is not None and axis.name != group):
            where = f"linked group '{group}'" if group else "the plain axes"
            raise StudyError(path, number, f"quick: parameter '{name}' is "
                             f"not in {where}; quick lines can only replace "
                             "an existing axis of the same kind")
        replacements.setdefault(id(axis), {})[index] = (values, number)

    for axis in axes:
        replaced = replacements.get(id(axis))
        if not replaced:
            continue
        columns = [replaced[i][0] if i in replaced
                   else [row[i] for row in axis.values]
                   for i in range(len(axis.paths))]
        if len({len(column) for column in columns}) != 1:
            number = max(line for _, line in replaced.values())
            raise StudyError(path, number, f"quick: the members of linked "
                             f"group '{axis.name}' would have different "
                             "numbers of values; replace all of them")
        if apply:
            axis.values = [tuple(row) for row in zip(*columns)]


def expand_runs(study, output_dir):
    """Return the runs of ``study``: the product of its axes, last axis
    varying fastest; ids ``run_0001``... in that order."""
    output_dir = Path(output_dir).resolve()
    runs = []
    combos = itertools.product(*(axis.values for axis in study.axes))
    for index, combo in enumerate(combos, start=1):
        swept, shown = {}, []
        for axis, values in zip(study.axes, combo):
            swept.update(zip(axis.paths, values))
            if LABEL_AXIS in axis.paths:
                shown.append(values[axis.paths.index(LABEL_AXIS)])
            else:
                shown.extend(values)
        settings = {k: v for k, v in study.fixed.items()
                    if k not in NOT_PARAMETERS}
        settings.update((k, v) for k, v in swept.items()
                        if k not in NOT_PARAMETERS)
        ranks = int(swept.get(MPI_AXIS, study.fixed.get(MPI_AXIS, "1")))
        run_id = f"run_{index:04d}"
        runs.append(Run(index, run_id, swept, settings, ranks,
                        output_dir / run_id, tuple(shown)))
    return runs


def reference_run(study, output_dir):
    """The converged fine reference run (the base with the study's fixed
    settings and the ``reference`` overrides) in ``<out>/reference``, or
    None when the study has no ``reference`` line."""
    if study.reference is None:
        return None
    settings = dict(study.fixed)
    settings.update(study.reference)
    ranks = int(settings.get(MPI_AXIS, "1"))
    settings = {k: v for k, v in settings.items() if k not in NOT_PARAMETERS}
    return Run(0, REFERENCE_ID, {}, settings, ranks,
               Path(output_dir).resolve() / REFERENCE_ID, (REFERENCE_ID,))


# ---------------------------------------------------------------------------
# Parameter files
# ---------------------------------------------------------------------------

def format_override(settings, output_directory, comment=None):
    """Return the text of a deal.II parameter file setting ``settings``.

    ``settings`` maps '/'-separated parameter paths to values; they are
    nested into ``subsection ... end`` blocks.  ``Output/Directory`` is set to
    ``output_directory``.
    """
    tree = {"params": {}, "subs": {}}
    items = dict(settings)
    items[OUTPUT_DIRECTORY] = str(output_directory)
    for path, value in items.items():
        *sections, name = [part.strip() for part in path.split("/")]
        node = tree
        for section in sections:
            node = node["subs"].setdefault(section, {"params": {}, "subs": {}})
        node["params"][name] = value

    lines = [f"# {comment}"] if comment else []

    def emit(node, depth):
        indent = "  " * depth
        for name, value in node["params"].items():
            lines.append(f"{indent}set {name} = {value}".rstrip())
        for name, child in node["subs"].items():
            lines.append(f"{indent}subsection {name}")
            emit(child, depth + 1)
            lines.append(f"{indent}end")

    emit(tree, 0)
    return "\n".join(lines) + "\n"


def read_prm(path):
    """Read the ``set`` lines of a deal.II parameter file.

    Returns a dict of '/'-separated path -> value.  ``include`` and other
    statements are ignored; this is only used to label charts with values
    that the study does not set.
    """
    values, sections = {}, []
    try:
        text = Path(path).read_text()
    except OSError:
        return values
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if line.startswith("subsection "):
            sections.append(line[len("subsection "):].strip())
        elif line == "end" and sections:
            sections.pop()
        elif line.startswith("set ") and "=" in line:
            name, value = line[4:].split("=", 1)
            values["/".join(sections + [name.strip()])] = value.strip()
    return values


# ---------------------------------------------------------------------------
# Running
# ---------------------------------------------------------------------------

def default_fmpm():
    """``fmpm`` on PATH, else the build tree's executable, else None."""
    found = shutil.which("fmpm")
    if found:
        return found
    built = (Path(__file__).resolve().parents[2]
             / "build" / "applications" / "fmpm" / "fmpm")
    return str(built) if built.is_file() else None


def build_command(fmpm_command, base, override, mpi_ranks):
    """Return the argument list running fmpm on ``base`` and ``override``."""
    command = list(fmpm_command) + [str(base), str(override)]
    if mpi_ranks > 1:
        command = ["mpirun", "-np", str(mpi_ranks), "--oversubscribe",
                   "--allow-run-as-root"] + command
    return command


def read_json(path):
    """Return the object in a JSON file, or None if missing/unreadable."""
    try:
        with open(path) as stream:
            data = json.load(stream)
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def is_final_status(status):
    """True for a status that ends a run: completed or failed."""
    return isinstance(status, str) and (status.startswith("completed")
                                        or status.startswith("stopped: step limit")
                                        or status.startswith("failed"))


def run_is_done(run, override_text):
    """True when an earlier invocation finished ``run`` with the same
    parameters (so resuming can skip it)."""
    try:
        if (run.directory / "override.prm").read_text() != override_text:
            return False
    except OSError:
        return False
    summary = read_json(run.directory / "summary.json")
    if summary and is_final_status(summary.get("status")):
        return True
    record = read_json(run.directory / "run.json")
    return bool(record and is_final_status(record.get("runner_status")))


def reference_is_done(run, override_text):
    """True when the reference run completed with the same parameters."""
    try:
        if (run.directory / "override.prm").read_text() != override_text:
            return False
    except OSError:
        return False
    summary = read_json(run.directory / "summary.json") or {}
    return str(summary.get("status", "")).startswith("completed")


class Runner:
    """Executes runs, possibly concurrently, and can kill them all."""

    def __init__(self, fmpm_command, base, timeout=None):
        self.fmpm_command = fmpm_command
        self.base = base
        self.timeout = timeout
        self._active = set()
        self._lock = threading.Lock()
        self.stopping = False

    def execute(self, run, override_text):
        """Run fmpm for ``run`` in a fresh directory; return its record
        (None when the run was killed by :meth:`kill_all`).

        The record (also saved as ``run.json``) holds the command, the exit
        code, the elapsed time and ``runner_status``: None when fmpm wrote a
        summary, else ``failed: timeout``, ``failed: no summary (exit code
        N)`` or ``failed: cannot start (...)``.
        """
        if run.directory.exists():
            shutil.rmtree(run.directory)
        run.directory.mkdir(parents=True)
        override = run.directory / "override.prm"
        override.write_text(override_text)
        command = build_command(self.fmpm_command, self.base, override,
                                run.mpi_ranks)
        record = {"run_id": run.run_id, "command": command,
                  "exit_code": None, "runner_status": None}
        start = time.monotonic()
        with open(run.directory / "log.txt", "wb") as log:
            try:
                process = subprocess.Popen(
                    command, stdout=log, stderr=subprocess.STDOUT,
                    stdin=subprocess.DEVNULL, start_new_session=True)
            except OSError as error:
                process = None
                record["runner_status"] = (f"failed: cannot start "
                                           f"({error.strerror}: {command[0]})")
            if process is not None:
                with self._lock:
                    self._active.add(process)
                try:
                    record["exit_code"] = process.wait(timeout=self.timeout)
                except subprocess.TimeoutExpired:
                    self._kill(process)
                    record["exit_code"] = process.wait()
                    record["runner_status"] = "failed: timeout"
                except BaseException:  # Ctrl-C: do not leave fmpm running
                    self._kill(process)
                    process.wait()
                    raise
                finally:
                    with self._lock:
                        self._active.discard(process)
        if self.stopping:
            return None  # killed by kill_all: no run.json, redone next time
        record["elapsed_seconds"] = round(time.monotonic() - start, 3)
        if record["runner_status"] is None:
            summary = read_json(run.directory / "summary.json") or {}
            if not is_final_status(summary.get("status")):
                record["runner_status"] = (f"failed: no summary (exit code "
                                           f"{record['exit_code']})")
        with open(run.directory / "run.json", "w") as stream:
            json.dump(record, stream, indent=2)
        return record

    @staticmethod
    def _kill(process):
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except OSError:
            pass

    def kill_all(self):
        """Kill every run still going (used on Ctrl-C); their directories
        get no run.json, so a later invocation redoes them."""
        with self._lock:
            self.stopping = True
            for process in list(self._active):
                self._kill(process)


def format_duration(seconds):
    """Human readable duration: ``4.1 s``, ``12 s``, ``3 min 20 s``."""
    if seconds < 10:
        return f"{seconds:.1f} s"
    if seconds < 60:
        return f"{seconds:.0f} s"
    minutes, secs = divmod(int(round(seconds)), 60)
    if minutes < 60:
        return f"{minutes} min {secs} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes} min"


def run_status(run, record):
    """The status of a finished run: the runner's verdict or fmpm's."""
    if record.get("runner_status"):
        return record["runner_status"]
    summary = read_json(run.directory / "summary.json") or {}
    return str(summary.get("status", "unknown"))


def execute_runs(runs, runner, override_texts, jobs, total):
    """Execute ``runs`` with ``jobs`` workers, printing progress lines."""
    started = time.monotonic()
    durations = []
    done = total - len(runs)
    lock = threading.Lock()

    def finished(run, record):
        nonlocal done
        with lock:
            done += 1
            durations.append(record["elapsed_seconds"])
            elapsed = time.monotonic() - started
            remaining = (len(runs) - len(durations)) * (
                sum(durations) / len(durations)) / jobs
            result = (f"{run_status(run, record)} in "
                      f"{format_duration(record['elapsed_seconds'])} "
                      f"(elapsed {format_duration(elapsed)}, about "
                      f"{format_duration(remaining)} left)")
            if jobs == 1:
                print(result, flush=True)
            else:
                print(f"[{done}/{total}] {run.run_id} {run.label()} ... "
                      f"{result}", flush=True)

    def work(run, position):
        if jobs == 1:
            print(f"[{position}/{total}] {run.run_id} {run.label()} ... ",
                  end="", flush=True)
        record = runner.execute(run, override_texts[run.run_id])
        if record is not None:
            finished(run, record)

    if jobs == 1:
        for offset, run in enumerate(runs, start=1):
            work(run, total - len(runs) + offset)
        return
    pool = concurrent.futures.ThreadPoolExecutor(jobs)
    try:
        futures = [pool.submit(work, run, 0) for run in runs]
        for future in concurrent.futures.as_completed(futures):
            future.result()
    except KeyboardInterrupt:
        pool.shutdown(wait=False, cancel_futures=True)
        runner.kill_all()
        raise
    finally:
        pool.shutdown(wait=True)


# ---------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------

def collect_results(study, runs, reference=None):
    """Return one dict per run with the results.csv columns (strings or
    numbers; '' for missing values) plus private ``_run`` and ``_summary``
    entries used by the charts.

    With a ``reference`` run (see :func:`reference_run`) that completed,
    completed runs without an analytical ``error_velocity_l2`` get the
    ``error_reference_<column>`` errors of :func:`reference_errors`."""
    histories = reference_histories(study, reference)
    rows = []
    for run in runs:
        summary = read_json(run.directory / "summary.json") or {}
        record = read_json(run.directory / "run.json") or {}
        row = {"run_id": run.run_id}
        row.update(run.swept)
        for key in SUMMARY_COLUMNS + [study.charts.get("error",
                                                       DEFAULT_ERROR_KEY)]:
            value = summary.get(key, "")
            row[key] = "" if value is None else value
        if record.get("runner_status"):
            row["status"] = record["runner_status"]
        elif not row["status"]:
            row["status"] = ("failed: summary without status" if summary
                             else "not run")
        row["exit_code"] = record.get("exit_code", "")
        if row["exit_code"] is None:
            row["exit_code"] = ""
        row["elapsed_seconds"] = record.get("elapsed_seconds", "")
        for key in study.reference_keys:
            row[key] = ""
        if histories and str(row["status"]).startswith("completed") and (
                to_float(summary.get("error_velocity_l2")) is None):
            row.update(reference_errors(
                study, run.directory / "history.csv", histories))
        row["_run"] = run
        row["_summary"] = summary
        rows.append(row)
    return rows


def result_columns(study):
    """The results.csv header."""
    columns = ["run_id"] + study.swept_paths + SUMMARY_COLUMNS
    columns += [k for k in study.reference_keys if k not in columns]
    error_key = study.charts.get("error", DEFAULT_ERROR_KEY)
    if error_key not in columns:
        columns.append(error_key)
    return columns + RUNNER_COLUMNS


def read_history_series(path, columns):
    """Return {column: ([times], [values])} of a history.csv (rows with a
    missing or non-finite time or value left out), or None."""
    try:
        with open(path, newline="") as stream:
            rows = list(csv.DictReader(stream))
    except OSError:
        return None
    series = {}
    for column in columns:
        pairs = [(to_float(r.get("time")), to_float(r.get(column)))
                 for r in rows]
        pairs = sorted((t, v) for t, v in pairs
                       if t is not None and v is not None)
        if pairs:
            series[column] = ([t for t, _ in pairs], [v for _, v in pairs])
    return series


def relative_l2_difference(times, values, ref_times, ref_values):
    """sqrt(sum (a - r)^2 / sum r^2) over the run's times within the
    reference's time range, r linearly interpolated; None when no time is
    in range or the reference is zero there."""
    if not ref_times:
        return None
    first, last = ref_times[0], ref_times[-1]
    slack = 1e-9 * max(abs(first), abs(last), last - first, 1e-300)
    difference = norm = 0.0
    used = 0
    for t, a in zip(times, values):
        if t < first - slack or t > last + slack:
            continue
        t = min(max(t, first), last)
        i = bisect.bisect_left(ref_times, t)
        if i < len(ref_times) and ref_times[i] == t:
            r = ref_values[i]
        else:
            t0, t1 = ref_times[i - 1], ref_times[i]
            w = (t - t0) / (t1 - t0)
            r = (1 - w) * ref_values[i - 1] + w * ref_values[i]
        difference += (a - r) ** 2
        norm += r ** 2
        used += 1
    if not used or norm <= 0:
        return None
    return math.sqrt(difference / norm)


def reference_histories(study, reference):
    """The reference run's history series, or None (with a message) when
    there is no reference run or it did not complete."""
    if reference is None:
        return None
    summary = read_json(reference.directory / "summary.json") or {}
    status = str(summary.get("status", "not run"))
    series = None
    if status.startswith("completed"):
        series = read_history_series(reference.directory / "history.csv",
                                     study.reference_columns)
        if not series:
            status = "completed, but without a usable history.csv"
    if not series:
        print(f"Reference run {reference.directory}: {status}; no "
              "error_reference_* columns.", file=sys.stderr)
        return None
    return series


def reference_errors(study, history_path, references):
    """{error_reference_<column>: relative L2 difference} of one run's
    history.csv against the reference series ('' where unavailable)."""
    series = read_history_series(history_path, study.reference_columns) or {}
    errors = {}
    for column, key in zip(study.reference_columns, study.reference_keys):
        error = None
        if column in series and column in references:
            error = relative_l2_difference(*series[column],
                                           *references[column])
        errors[key] = "" if error is None else error
    return errors


def write_csv(path, columns, rows):
    """Write dict rows to a CSV file with the given columns."""
    with open(path, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=columns,
                                extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow(row)


def write_plan(path, study, runs):
    """Write runs.csv: the run ids, swept values and directories."""
    columns = ["run_id"] + study.swept_paths + ["mpi_ranks", "directory"]
    rows = []
    for run in runs:
        row = {"run_id": run.run_id, "mpi_ranks": run.mpi_ranks,
               "directory": str(run.directory)}
        row.update(run.swept)
        rows.append(row)
    write_csv(path, columns, rows)


# ---------------------------------------------------------------------------
# Chart data
# ---------------------------------------------------------------------------

def to_float(value):
    """Convert to a finite float, or None."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


class ChartData:
    """Per-run quantities the charts need, derived from the study's
    ``chart`` lines."""

    def __init__(self, study, rows):
        self.study = study
        self.rows = rows
        self.base_values = read_prm(study.base)
        self.error_key = study.charts.get("error", DEFAULT_ERROR_KEY)

    def value(self, row, path):
        """A parameter's value for a run: swept, set, or from the base."""
        run = row["_run"]
        for source in (run.swept, self.study.fixed, self.base_values):
            if path in source:
                return source[path]
        return None

    def method(self, row):
        """The curve label of a run."""
        spec = self.study.charts.get("method")
        if not spec:
            return "all runs"
        parts = [self.value(row, p.strip()) for p in spec.split("+")]
        return " ".join(re.sub(r"\s+", " ", p) if p else "?" for p in parts)

    def methods(self):
        """Curve labels in order of first appearance."""
        return list(dict.fromkeys(self.method(row) for row in self.rows))

    def resolution(self, row):
        """The resolution n of a run, or None."""
        path = self.study.charts.get("x_resolution")
        return first_number(self.value(row, path)) if path else None

    def cell_size(self, row):
        """The cell size h of a run (1/n unless given), or None."""
        n = self.resolution(row)
        if not n:
            return None
        if self.study.cell_size is not None:
            try:
                return evaluate_cell_size(self.study.cell_size, n)
            except (ArithmeticError, ValueError):
                return None
        return 1.0 / n

    def error(self, row, key=None):
        """The error (``key``, default the chart's) of a completed run, if
        positive."""
        if not str(row["status"]).startswith("completed"):
            return None
        key = key or self.error_key
        if key == "energy_loss":  # 1 - E_end / E_0 (no external work)
            summary = row["_summary"]
            initial = to_float(summary.get("initial_total_energy"))
            final = to_float(summary.get("final_total_energy"))
            error = 1 - final / initial if initial and final is not None \
                else None
        else:
            error = to_float(row.get(key, row["_summary"].get(key)))
        return error if error and error > 0 else None


def fit_order(points):
    """Least-squares slope of log(error) against log(h).

    ``points`` is a list of (h, error) with positive entries.  Returns None
    with fewer than two distinct h.
    """
    xs = [math.log(h) for h, _ in points]
    ys = [math.log(e) for _, e in points]
    if len(set(xs)) < 2:
        return None
    mean_x, mean_y = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mean_x) ** 2 for x in xs)
    sxy = sum((x - mean_x) * (y - mean_y) for x, y in zip(xs, ys))
    return sxy / sxx


def convergence_points(data, key=None):
    """Return {method: [(h, error), ...]} sorted by h, for completed runs
    (error ``key``, default the chart's error)."""
    points = {}
    for row in data.rows:
        h, error = data.cell_size(row), data.error(row, key)
        if h and h > 0 and error:
            points.setdefault(data.method(row), []).append((h, error))
    return {m: sorted(p) for m, p in points.items()}


def convergence_orders(data):
    """Return [(method, order or None, n_points)] for every method with
    error data."""
    return [(method, fit_order(points), len(points))
            for method, points in convergence_points(data).items()]


def finest_pair_order(points):
    """Order from the two smallest cell sizes of sorted (h, error) points
    (the asymptotic order when the coarse points are pre-asymptotic)."""
    if len(points) < 2 or points[0][0] == points[1][0]:
        return None
    return fit_order(points[:2])


def convergence_table(data):
    """Rows of convergence_orders.csv: per method the least-squares order
    of the chart's error, the order from the two finest resolutions, and
    the least-squares orders of the other reference errors."""
    others = [k for k in list(ERROR_KEYS) + data.study.reference_keys
              if k != data.error_key]
    extra = {k: convergence_points(data, k) for k in others}
    table = []
    for method, points in convergence_points(data).items():
        row = {"method": method, "order": fit_order(points),
               "n_points": len(points),
               "order_finest_pair": finest_pair_order(points)}
        for key in others:
            other = extra[key].get(method, [])
            row[f"order_{key}"] = fit_order(other) if other else None
        table.append(row)
    return table


def pareto_front(points):
    """Indices of the (time, error) points no other point dominates."""
    front = []
    for i, (t, e) in enumerate(points):
        dominated = any(
            (t2 <= t and e2 <= e) and (t2 < t or e2 < e)
            for j, (t2, e2) in enumerate(points) if j != i)
        if not dominated:
            front.append(i)
    return front


# ---------------------------------------------------------------------------
# Charts
# ---------------------------------------------------------------------------

def import_pyplot():
    """Import matplotlib.pyplot with the Agg backend.

    Falls back to Debian's dist-packages (python3-matplotlib) when this
    interpreter is another build of the same Python version (e.g. pyenv).
    Returns None when matplotlib cannot be imported.
    """
    try:
        import matplotlib
    except ImportError:
        debian = "/usr/lib/python3/dist-packages"
        if not os.path.isdir(debian) or debian in sys.path:
            return None
        sys.path.append(debian)
        try:
            import matplotlib
        except ImportError:
            return None
    try:
        matplotlib.use("Agg")
        import matplotlib.pyplot as pyplot
    except Exception:  # a broken install: report, do not crash the pipeline
        return None
    return pyplot


#: Marker and line style cycles, so that curves on top of each other stay
#: distinguishable.
_MARKERS = ["o", "s", "^", "v", "D", "P", "X", "*", "h", "<", ">", "p"]
_LINESTYLES = ["-", "--", "-.", ":"]


def _style(number, markers=True):
    """Plot keyword arguments of the curve with this index."""
    style = {"color": f"C{number % 10}",
             "linestyle": _LINESTYLES[(number // 10 + number) % 4]
             if not markers else _LINESTYLES[number // 10 % 4]}
    if markers:
        style["marker"] = _MARKERS[number % len(_MARKERS)]
        style["markersize"] = 6 if number < 10 else 5
    return style


def _legend(fig, ax, count):
    """A legend inside the axes for a few curves, else to the right."""
    if count <= 5:
        ax.legend(fontsize=8)
        return
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))


def _error_label(data):
    return f"error ({data.error_key})"


def _title(data, what):
    return f"{data.study.title}\n{what}"


def chart_error_vs_wall_time(plt, data, path):
    """Error against wall time per method, with the Pareto front."""
    series = {}
    for row in data.rows:
        error, wall = data.error(row), to_float(row.get("wall_seconds"))
        if error and wall and wall > 0:
            key = data.resolution(row)
            series.setdefault(data.method(row), []).append(
                (key if key is not None else wall, wall, error, row))
    if not series:
        return f"no completed run with both '{data.error_key}' and wall time"
    fig, ax = plt.subplots(figsize=(7 if len(series) <= 5 else 9, 5))
    everything = []
    for number, (method, points) in enumerate(series.items()):
        points.sort(key=lambda p: p[0])
        ax.plot([p[1] for p in points], [p[2] for p in points],
                label=method, **_style(number))
        everything.extend((p[1], p[2]) for p in points)
    front = sorted(everything[i] for i in pareto_front(everything))
    ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=1,
            zorder=1)
    ax.scatter([p[0] for p in front], [p[1] for p in front], s=160,
               facecolors="none", edgecolors="black", linewidths=1.5,
               label="Pareto front", zorder=3)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel(_error_label(data))
    ax.set_title(_title(data, "error against wall time"))
    ax.grid(True, which="both", alpha=0.3)
    _legend(fig, ax, len(series) + 1)
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return None


def chart_convergence(plt, data, path):
    """Error against cell size per method, with fitted orders."""
    if "x_resolution" not in data.study.charts:
        return "no 'chart x_resolution = ...' in the study"
    points = convergence_points(data)
    if not points:
        return f"no completed run with '{data.error_key}' and a resolution"
    fig, ax = plt.subplots(figsize=(7 if len(points) <= 5 else 9, 5))
    for number, (method, pts) in enumerate(points.items()):
        order = fit_order(pts)
        label = method if order is None else f"{method} (order {order:.2f})"
        line, = ax.plot([p[0] for p in pts], [p[1] for p in pts],
                        label=label, **_style(number))
        if order is not None:
            # Dashed least-squares line through the geometric mean.
            mean_x = sum(math.log(p[0]) for p in pts) / len(pts)
            mean_y = sum(math.log(p[1]) for p in pts) / len(pts)
            hs = [pts[0][0], pts[-1][0]]
            ax.plot(hs, [math.exp(mean_y + order * (math.log(h) - mean_x))
                         for h in hs], "--", color=line.get_color(), lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    h_text = ("h" if data.study.cell_size is not None else "h = 1/n")
    ax.set_xlabel(f"cell size {h_text} (n from "
                  f"{data.study.charts['x_resolution']})")
    ax.set_ylabel(_error_label(data))
    ax.set_title(_title(data, "convergence (thin dashed: least-squares "
                        "fit)"))
    ax.grid(True, which="both", alpha=0.3)
    _legend(fig, ax, len(points))
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return None


def _sorted_values(values):
    """Unique values, numerically sorted when all are numbers."""
    unique = list(dict.fromkeys(values))
    if all(_NUMBER.fullmatch(v.strip()) for v in unique):
        return sorted(unique, key=float)
    return unique


def _failure_time_key(row):
    """Sort key putting the earliest failure first, unknown times last."""
    time_ = to_float(row.get("failure_time"))
    return math.inf if time_ is None else time_


def _failure_note(row):
    """Short annotation of an unstable cell."""
    time_ = to_float(row.get("failure_time"))
    if time_ is not None:
        return f"t={time_:.3g}"
    status = str(row["status"])
    if "timeout" in status:
        return "timeout"
    if "no summary" in status:
        return "crash"
    return "failed"


def stability_cells(data):
    """Group the runs for the stability charts.

    Returns (x_path, y_path, {panel: {(x, y): [rows]}}) or a string saying
    what is missing.  Panels are the methods, unless the method is the
    stability_x or stability_y parameter itself (e.g. ``chart method =
    Label`` and ``chart stability_y = Label``): then there is one panel.
    """
    x_path = data.study.charts.get("stability_x")
    y_path = data.study.charts.get("stability_y")
    if not x_path or not y_path:
        return "no 'chart stability_x' and 'chart stability_y' in the study"
    split = data.study.charts.get("method") not in (x_path, y_path)
    cells = {}
    for row in data.rows:
        x, y = data.value(row, x_path), data.value(row, y_path)
        if x is None or y is None or row["status"] == "not run":
            continue
        panel = data.method(row) if split else ""
        cells.setdefault(panel, {}).setdefault((x, y), []).append(row)
    if not cells:
        return (f"no run has values for both '{x_path}' and '{y_path}' "
                "(sweep or set them)")
    return x_path, y_path, cells


def _is_stable(runs):
    return all(str(r["status"]).startswith("completed") for r in runs)


def stability_limits(data):
    """Per panel and stability_y value, the largest stable stability_x
    below the smallest unstable one (numeric stability_x only).

    Returns a list of dicts (panel, y, largest_stable, smallest_unstable,
    n_runs); empty when the study has no stability chart keys or
    stability_x is not numeric.
    """
    grouped = stability_cells(data)
    if isinstance(grouped, str):
        return []
    _, _, cells = grouped
    limits = []
    for panel, grid in cells.items():
        ys = _sorted_values([y for _, y in grid])
        for y in ys:
            column = {}
            for (x, y2), runs in grid.items():
                if y2 == y:
                    value = to_float(first_number(x)) if _NUMBER.fullmatch(
                        x.strip()) else None
                    if value is None:
                        return []
                    column.setdefault(value, []).extend(runs)
            xs = sorted(column)
            unstable = [x for x in xs if not _is_stable(column[x])]
            first_bad = unstable[0] if unstable else None
            stable = [x for x in xs if _is_stable(column[x])
                      and (first_bad is None or x < first_bad)]
            limits.append({"panel": panel, "y": y,
                           "largest_stable": stable[-1] if stable else None,
                           "smallest_unstable": first_bad,
                           "n_runs": sum(len(r) for r in column.values())})
    return limits


def write_stability_limits(path, data, limits):
    """Write stability_limits.csv (one row per panel and y value)."""
    x_path = data.study.charts["stability_x"]
    y_path = data.study.charts["stability_y"]
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["method", y_path, f"largest stable {x_path}",
                         f"smallest unstable {x_path}", "n_runs"])
        for item in limits:
            writer.writerow([
                item["panel"], item["y"],
                "" if item["largest_stable"] is None
                else f"{item['largest_stable']:g}",
                "" if item["smallest_unstable"] is None
                else f"{item['smallest_unstable']:g}", item["n_runs"]])


def chart_stability_limits(plt, data, path):
    """The stability limit (between the largest stable and the smallest
    unstable stability_x) against stability_y, one line per panel."""
    limits = stability_limits(data)
    if not limits:
        return ("no stability chart keys, or stability_x is not numeric")
    ys = _sorted_values([item["y"] for item in limits])
    numeric_y = all(_NUMBER.fullmatch(y.strip()) for y in ys)
    fig, ax = plt.subplots(figsize=(max(5.0, 1.5 + 0.8 * len(ys)), 4.5))
    panels = list(dict.fromkeys(item["panel"] for item in limits))
    tested = [x for item in limits for x in (item["largest_stable"],
                                             item["smallest_unstable"])
              if x is not None]
    top = max(tested) if tested else 1.0
    for number, panel in enumerate(panels):
        items = [i for i in limits if i["panel"] == panel]
        offset = (number - (len(panels) - 1) / 2) * 0.08
        positions, lows, highs, known = [], [], [], []
        for item in items:
            x = (float(item["y"]) if numeric_y else ys.index(item["y"]))
            positions.append(x if numeric_y else x + offset)
            lows.append(item["largest_stable"] or 0.0)
            highs.append(item["smallest_unstable"])
            known.append(item["largest_stable"] is not None)
        colour = f"C{number % 10}"
        for x, low, high in zip(positions, lows, highs):
            if high is None:  # stable everywhere tested: an arrow up
                ax.annotate("", xy=(x, top * 1.08), xytext=(x, low),
                            arrowprops=dict(arrowstyle="->", color=colour))
            else:
                ax.plot([x, x], [low, high], color=colour, lw=6,
                        alpha=0.5, solid_capstyle="butt")
        # A point between the two values; none where no value was stable
        # (the limit is below the range) or none unstable (above it).
        middle = [0.5 * (lo + hi) if hi is not None and ok else None
                  for lo, hi, ok in zip(lows, highs, known)]
        ax.plot([x for x, m in zip(positions, middle) if m is not None],
                [m for m in middle if m is not None], "o-", color=colour,
                label=panel or "stability limit")
    if not numeric_y:
        ax.set_xticks(range(len(ys)))
        ax.set_xticklabels(ys, rotation=30 if len(ys) > 5 else 0,
                           ha="right" if len(ys) > 5 else "center")
    ax.set_xlabel(data.study.charts["stability_y"])
    ax.set_ylabel(f"critical {data.study.charts['stability_x']}")
    ax.set_ylim(0, top * 1.12)
    ax.set_title(_title(data, "stability limit (bar: between the largest "
                        "stable and the smallest unstable value; arrow: "
                        "stable everywhere)"), fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return None


def chart_stability_map(plt, data, path):
    """Stable/unstable map over two parameters, one subplot per method."""
    grouped = stability_cells(data)
    if isinstance(grouped, str):
        return grouped
    x_path, y_path, cells = grouped
    xs = _sorted_values([k[0] for c in cells.values() for k in c])
    ys = _sorted_values([k[1] for c in cells.values() for k in c])
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch
    colours = ListedColormap(["#d9d9d9", "#4caf50", "#e53935"])
    count = len(cells)
    label_width = 0.08 * max(len(str(y)) for y in ys)
    width = max(4.0, min(14.0, 1.8 + label_width + 0.7 * len(xs)))
    height = max(3.0, 1.6 + 0.45 * len(ys))
    columns = max(1, min(count, 3, int(16 // width)))
    rows_ = math.ceil(count / columns)
    note_size = 8 if len(xs) <= 10 else 6
    fig, axes = plt.subplots(rows_, columns, squeeze=False,
                             figsize=(width * columns, height * rows_ + 1.0))
    for ax, (method, grid) in zip(axes.flat, cells.items()):
        image = [[0] * len(xs) for _ in ys]
        for (x, y), runs in grid.items():
            i, j = ys.index(y), xs.index(x)
            failed = [r for r in runs
                      if not str(r["status"]).startswith("completed")]
            image[i][j] = 2 if failed else 1
            if failed:
                first = min(failed, key=_failure_time_key)
                ax.text(j, i, _failure_note(first), ha="center",
                        va="center", fontsize=note_size, color="white")
        ax.imshow(image, cmap=colours, vmin=0, vmax=2, origin="lower",
                  aspect="auto")
        ax.set_xticks(range(len(xs)))
        ax.set_xticklabels(xs, rotation=45 if len(xs) > 6 else 0)
        ax.set_yticks(range(len(ys)))
        ax.set_yticklabels(ys)
        if not all(_NUMBER.fullmatch(str(y).strip()) for y in ys):
            ax.invert_yaxis()  # labels read top-down in the study's order
        ax.set_xticks([j - 0.5 for j in range(len(xs) + 1)], minor=True)
        ax.set_yticks([i - 0.5 for i in range(len(ys) + 1)], minor=True)
        ax.grid(which="minor", color="white", linewidth=2)
        ax.tick_params(which="minor", length=0)
        ax.set_xlabel(x_path)
        ax.set_ylabel(y_path)
        if method:
            ax.set_title(method)
    for ax in list(axes.flat)[count:]:
        ax.axis("off")
    fig.legend(handles=[Patch(color="#4caf50", label="stable"),
                        Patch(color="#e53935",
                              label="unstable (failure time)"),
                        Patch(color="#d9d9d9", label="no run")],
               loc="lower center", ncol=3, fontsize=8)
    fig.suptitle(_title(data, "stability map"))
    fig.tight_layout(rect=(0, 0.05 / rows_, 1, 1 - 0.06 / rows_))
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return None


def read_history(path, with_dissipation=False):
    """Return (times, total energies) from a history.csv, or None.

    With ``with_dissipation``, return (times, energies, dissipated) where
    dissipated is the list of the ``dissipated_energy`` column (None when
    the history has no such column).
    """
    try:
        with open(path, newline="") as stream:
            rows = list(csv.DictReader(stream))
    except OSError:
        return None
    times, energies, dissipated = [], [], []
    for row in rows:
        t = to_float(row.get("time"))
        energy = to_float(row.get("total_energy"))
        if energy is None:
            parts = [to_float(row.get(k)) for k in ("kinetic_energy",
                                                    "strain_energy")]
            energy = None if None in parts else sum(parts)
        if t is not None and energy is not None:
            times.append(t)
            energies.append(energy)
            dissipated.append(to_float(row.get("dissipated_energy")))
    if not times:
        return None
    if not with_dissipation:
        return times, energies
    if None in dissipated:
        dissipated = None
    return times, energies, dissipated


def chart_energy_history(plt, data, path):
    """Total energy against time, one run per method (finest resolution)."""
    chosen = {}
    wanted = to_float(data.study.charts.get("energy_resolution"))
    for row in data.rows:
        n = data.resolution(row) or 0
        if wanted is not None and n != wanted:
            continue
        history = read_history(row["_run"].directory / "history.csv",
                               with_dissipation=True)
        if history is None or not history[1][0]:
            continue
        method = data.method(row)
        if method not in chosen or n > chosen[method][0]:
            chosen[method] = (n, row, history)
    if not chosen:
        return "no run left a history.csv with time and energies"
    fig, ax = plt.subplots(figsize=(7.5 if len(chosen) <= 5 else 9.5, 5))
    values = [e / energies[0] for _, _, (_, energies, _) in chosen.values()
              for e in energies]
    if min(values) > 0 and max(values) > 1e3 * min(values):
        ax.set_yscale("log")  # a blown-up run would flatten the others
    balance = False
    for number, (method, (n, row, (times, energies, dissipated))) in \
            enumerate(chosen.items()):
        label = method
        if "x_resolution" in data.study.charts:
            label += f", n = {n:g}"
        status = str(row["status"])
        failed_at = to_float(row.get("failure_time"))
        if status.startswith("failed"):
            label += (f" (failed at t = {failed_at:.3g})"
                      if failed_at is not None
                      else f" ({_short_status(status)})")
        e0 = energies[0]
        style = _style(number, markers=False)
        if dissipated is not None:
            style["linestyle"] = "-"
        line, = ax.plot(times, [e / e0 for e in energies], label=label,
                        **style)
        if dissipated is not None:
            balance = True
            ax.plot(times, [(e + d) / e0 for e, d in zip(energies,
                                                         dissipated)],
                    ":", color=line.get_color(), lw=1.2)
    ax.set_xlabel("time [s]")
    ylabel = "total energy (kinetic + strain) / initial"
    if balance:
        ylabel += "\n(dotted: energy + dissipated energy)"
    ax.set_ylabel(ylabel)
    what = "energy history"
    if "x_resolution" in data.study.charts:
        what += (" (finest resolution per method)" if wanted is None
                 else f" (n = {wanted:g})")
    ax.set_title(_title(data, what))
    ax.grid(True, alpha=0.3)
    _legend(fig, ax, len(chosen))
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return None


def _short_status(status, limit=40):
    """A failure status shortened for a legend."""
    return status if len(status) <= limit else status[:limit - 3] + "..."


def prune_run_directories(runs):
    """Delete every file of the run directories except KEPT_RUN_FILES;
    return how many were deleted."""
    removed = 0
    for run in runs:
        if not run.directory.is_dir():
            continue
        for entry in run.directory.iterdir():
            if entry.name in KEPT_RUN_FILES:
                continue
            if entry.is_dir():
                shutil.rmtree(entry)
            else:
                entry.unlink()
            removed += 1
    return removed


def write_convergence_orders(path, table):
    """Write convergence_orders.csv: method, order (least squares, chart
    error), n_points, order_finest_pair, order_<other error key>..."""
    columns = list(table[0]) if table else ["method", "order", "n_points"]
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(columns)
        for row in table:
            writer.writerow([f"{row[c]:.4f}" if isinstance(row[c], float)
                             else ("" if row[c] is None else row[c])
                             for c in columns])


def draw_charts(data, output_dir):
    """Draw every chart the study has data for; return (drawn, skipped)
    where skipped maps file name to reason."""
    plt = import_pyplot()
    if plt is None:
        return [], {name: "matplotlib is not installed "
                    "(apt-get install python3-matplotlib)"
                    for name in CHART_FILES}
    drawers = [chart_error_vs_wall_time, chart_convergence,
               chart_stability_map, chart_stability_limits,
               chart_energy_history]
    drawn, skipped = [], {}
    unwanted = {part.strip().removesuffix(".png") for part in
                data.study.charts.get("skip", "").split(",") if part.strip()}
    for name, drawer in zip(CHART_FILES, drawers):
        target = output_dir / name
        if target.exists():
            target.unlink()  # never leave a stale chart behind
        if name.removesuffix(".png") in unwanted:
            skipped[name] = "'chart skip' in the study"
            continue
        reason = drawer(plt, data, target)
        if reason:
            skipped[name] = reason
        else:
            drawn.append(name)
    return drawn, skipped


# ---------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------

def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="fmpm_study.py",
        description="Run a parameter study of fmpm and draw charts. "
                    "See contrib/studies/README.md for the study file format.")
    parser.add_argument("study", help="the study file")
    parser.add_argument("--output", metavar="DIR", help="output directory "
                        "(default: study_<study file stem> beside the study "
                        "file, with _quick appended in quick mode)")
    parser.add_argument("--fmpm", metavar="PATH", help="fmpm executable, or "
                        "a command such as 'python3 fake.py' (default: fmpm "
                        "on PATH, else build/applications/fmpm/fmpm)")
    parser.add_argument("--quick", action="store_true", help="apply the "
                        "study's 'quick ...' lines (a smaller study)")
    parser.add_argument("--jobs", type=int, default=1, metavar="N",
                        help="runs to execute at once (default 1)")
    parser.add_argument("--plot-only", action="store_true", help="do not "
                        "run; rebuild results.csv and charts")
    parser.add_argument("--timeout", type=float, metavar="SECONDS",
                        help="kill a run after this many seconds")
    parser.add_argument("--no-charts", action="store_true", help="write "
                        "results.csv and convergence_orders.csv only")
    parser.add_argument("--prune", action="store_true", help="after "
                        "collecting the results, delete every file of the "
                        "run directories except " + ", ".join(KEPT_RUN_FILES)
                        + " (fmpm's log, parameter echo, VTU output)")
    arguments = parser.parse_args(argv)
    if arguments.jobs < 1:
        parser.error("--jobs must be at least 1")
    if arguments.timeout is not None and arguments.timeout <= 0:
        parser.error("--timeout must be positive")
    return arguments


def default_output_dir(study_file, quick=False):
    """``study_<stem>`` (``study_<stem>_quick`` with --quick) beside the
    study file: the output directory when --output is not given."""
    study_file = Path(study_file).resolve()
    return study_file.parent / ("study_" + study_file.stem
                                + ("_quick" if quick else ""))


def resolve_fmpm(option):
    """Return the fmpm command as an argument list, or raise ValueError."""
    text = option if option else default_fmpm()
    if not text:
        raise ValueError("fmpm not found on PATH nor in "
                         "build/applications/fmpm/; pass --fmpm PATH")
    command = shlex.split(text)
    if not command:
        raise ValueError("--fmpm is empty")
    program = command[0]
    if os.sep in program:
        if not os.access(program, os.X_OK) or os.path.isdir(program):
            raise ValueError(f"fmpm executable '{program}' not found or not "
                             "executable")
        command[0] = str(Path(program).resolve())
    elif not shutil.which(program):
        raise ValueError(f"'{program}' not found on PATH")
    return command


def _interrupt(signum, frame):
    """Turn SIGTERM into KeyboardInterrupt so that runs are killed too."""
    raise KeyboardInterrupt


def main(argv=None):
    arguments = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        study = parse_study(arguments.study, quick=arguments.quick)
    except StudyError as error:
        print(f"fmpm_study.py: error in study file: {error}", file=sys.stderr)
        return 2

    output_dir = (Path(arguments.output).resolve() if arguments.output else
                  default_output_dir(arguments.study, arguments.quick))
    runs = expand_runs(study, output_dir)
    reference = reference_run(study, output_dir)
    print(f"Study '{study.title}': {len(runs)} runs over "
          f"{len(study.axes)} axes, output in {output_dir}")

    if not arguments.plot_only:
        try:
            fmpm_command = resolve_fmpm(arguments.fmpm)
        except ValueError as error:
            print(f"fmpm_study.py: error: {error}", file=sys.stderr)
            return 2
        output_dir.mkdir(parents=True, exist_ok=True)
        write_plan(output_dir / "runs.csv", study, runs)
        texts = {run.run_id: format_override(
                     run.settings, run.directory,
                     f"Written by fmpm_study.py: {run.run_id} of "
                     f"{study.path.name}") for run in runs}
        todo = [run for run in runs if not run_is_done(run,
                                                       texts[run.run_id])]
        if len(todo) < len(runs):
            print(f"Skipped {len(runs) - len(todo)} of {len(runs)} runs "
                  "already done (delete a run directory to redo it).")
        total = len(runs)
        if reference is not None:
            total += 1
            texts[REFERENCE_ID] = format_override(
                reference.settings, reference.directory,
                f"Written by fmpm_study.py: reference run of "
                f"{study.path.name}")
            if reference_is_done(reference, texts[REFERENCE_ID]):
                print("Skipped the reference run (already completed).")
            else:
                todo.insert(0, reference)  # the longest: start it first
        runner = Runner(fmpm_command, study.base, arguments.timeout)
        signal.signal(signal.SIGTERM, _interrupt)
        try:
            execute_runs(todo, runner, texts, arguments.jobs, total)
        except KeyboardInterrupt:
            print("\nInterrupted; unfinished runs will be redone next time.",
                  file=sys.stderr)
            return 130
    elif not output_dir.is_dir():
        print(f"fmpm_study.py: error: no output directory {output_dir} "
              "to plot from", file=sys.stderr)
        return 1

    rows = collect_results(study, runs, reference)
    write_csv(output_dir / "results.csv", result_columns(study), rows)
    statuses = [str(row["status"]) for row in rows]
    completed = sum(s.startswith("completed") for s in statuses)
    print(f"Results: {completed} completed, {len(rows) - completed} failed "
          f"or not run; written to {output_dir / 'results.csv'}")
    if not any(row["_summary"] for row in rows):
        print("fmpm_study.py: error: no run produced a summary.json "
              "(see the log.txt files in the run directories)",
              file=sys.stderr)
        return 1

    data = ChartData(study, rows)
    table = convergence_table(data)
    if "x_resolution" in study.charts and table:
        write_convergence_orders(output_dir / "convergence_orders.csv",
                                 table)
    limits = stability_limits(data)
    if limits:
        write_stability_limits(output_dir / "stability_limits.csv", data,
                               limits)
    if arguments.prune:
        removed = prune_run_directories(runs + ([reference] if reference
                                                else []))
        print(f"Pruned the run directories ({removed} files removed; kept "
              f"{', '.join(KEPT_RUN_FILES)}).")
    if arguments.no_charts:
        print("Charts not drawn (--no-charts).")
        return 0
    drawn, skipped = draw_charts(data, output_dir)
    print("Charts drawn: " + (", ".join(drawn) if drawn else "none"))
    for name, reason in skipped.items():
        print(f"Chart skipped: {name}: {reason}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
