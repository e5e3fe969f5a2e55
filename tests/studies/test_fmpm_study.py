#!/usr/bin/env python3
"""Tests of contrib/studies/fmpm_study.py, the fmpm study runner.

The runner drives tests/studies/fake_fmpm.py, which writes synthetic
summaries (error = C h^order, known orders, failures above a Courant number
threshold, crashes on request).  Run with

    python3 tests/studies/test_fmpm_study.py
    python3 -m unittest discover -s tests/studies
"""

import csv
import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import textwrap
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
RUNNER = ROOT / "contrib" / "studies" / "fmpm_study.py"
FAKE = HERE / "fake_fmpm.py"
FAKE_COMMAND = f"{shlex.quote(sys.executable)} {shlex.quote(str(FAKE))}"


def load_module(name, path):
    """Import a Python file as a module."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


study = load_module("fmpm_study", RUNNER)
fake = load_module("fake_fmpm", FAKE)

BASE_PRM = """\
set Dimension = 2
subsection Mesh
  set Subdivisions = 8, 1
end
subsection Method
  set Particle update = flip
  set Mass matrix = lumped
end
subsection Time
  set End time = 0.1
  set Courant number = 0.5
end
subsection Output
  set Directory = output
end
"""


def run_cli(directory, counter, *arguments, fmpm=FAKE_COMMAND):
    """Run the runner as a command in ``directory``; the fake fmpm appends
    a line to ``counter`` per invocation."""
    env = dict(os.environ, FAKE_FMPM_COUNTER=str(counter))
    command = [sys.executable, str(RUNNER)] + [str(a) for a in arguments]
    if fmpm:
        command += ["--fmpm", fmpm]
    return subprocess.run(command, cwd=directory, env=env, text=True,
                          capture_output=True, timeout=120)


class TempDirTest(unittest.TestCase):
    """Base class: a temporary directory with a base.prm in it."""

    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory(prefix="fmpm_study_test_")
        self.dir = Path(self._tmp.name)
        (self.dir / "base.prm").write_text(BASE_PRM)
        self.counter = self.dir / "counter.txt"

    def tearDown(self):
        self._tmp.cleanup()

    def write_study(self, body, name="test.study"):
        """Write a study file (dedented) and return its path."""
        path = self.dir / name
        path.write_text(textwrap.dedent(body))
        return path

    def parse(self, body, quick=False):
        return study.parse_study(self.write_study(body), quick=quick)

    def run_cli(self, *arguments, fmpm=FAKE_COMMAND):
        """Run the runner as a command in the temporary directory."""
        return run_cli(self.dir, self.counter, *arguments, fmpm=fmpm)

    def invocations(self, counter=None):
        """How many times the fake fmpm has been started."""
        counter = counter or self.counter
        if not counter.exists():
            return 0
        return len(counter.read_text().splitlines())

    @staticmethod
    def read_csv(path):
        with open(path, newline="") as stream:
            reader = csv.DictReader(stream)
            return reader.fieldnames, list(reader)


class AxisExpansionTest(TempDirTest):
    """Axes expand into a product; linked axes zip; quick mode."""

    def test_product_is_deterministic_and_last_axis_fastest(self):
        parsed = self.parse("""\
            base = base.prm
            axis Method/Particle update = flip | pic
            axis Mesh/Subdivisions = 16, 1 | 32, 2 | 64, 4
            """)
        runs = study.expand_runs(parsed, self.dir / "out")
        self.assertEqual([r.run_id for r in runs],
                         [f"run_{i:04d}" for i in range(1, 7)])
        self.assertEqual(
            [tuple(r.swept.values()) for r in runs],
            [("flip", "16, 1"), ("flip", "32, 2"), ("flip", "64, 4"),
             ("pic", "16, 1"), ("pic", "32, 2"), ("pic", "64, 4")])
        self.assertEqual(runs[4].directory, (self.dir / "out").resolve()
                         / "run_0005")
        self.assertEqual(runs[4].label(), "pic 32,2")
        again = study.expand_runs(study.parse_study(parsed.path),
                                  self.dir / "out")
        self.assertEqual([r.swept for r in runs], [r.swept for r in again])

    def test_linked_axes_vary_together(self):
        parsed = self.parse("""\
            base = base.prm
            linked resolution Mesh/Subdivisions = 16, 1 | 32, 2 | 64, 4
            axis Method/Particle update = flip | pic
            linked resolution Time/Time step = 1e-3 | 5e-4 | 2.5e-4
            """)
        runs = study.expand_runs(parsed, self.dir / "out")
        self.assertEqual(len(runs), 6)  # 3 (zipped) x 2, not 3 x 2 x 3
        pairs = {("16, 1", "1e-3"), ("32, 2", "5e-4"), ("64, 4", "2.5e-4")}
        for run in runs:
            self.assertIn((run.swept["Mesh/Subdivisions"],
                           run.swept["Time/Time step"]), pairs)
        # The group sits where its first member appears: it varies slowest.
        self.assertEqual([r.swept["Method/Particle update"] for r in runs],
                         ["flip", "pic"] * 3)
        self.assertEqual(parsed.swept_paths, [
            "Mesh/Subdivisions", "Time/Time step", "Method/Particle update"])

    def test_fixed_settings_and_mpi_axis(self):
        parsed = self.parse("""\
            base = base.prm
            axis MPI ranks = 1 | 2
            set Time/End time = 0.5
            """)
        runs = study.expand_runs(parsed, self.dir / "out")
        self.assertEqual([r.mpi_ranks for r in runs], [1, 2])
        self.assertEqual(runs[1].settings, {"Time/End time": "0.5"})
        self.assertEqual(study.build_command(["fmpm"], "b.prm", "o.prm", 1),
                         ["fmpm", "b.prm", "o.prm"])
        self.assertEqual(
            study.build_command(["fmpm"], "b.prm", "o.prm", 2),
            ["mpirun", "-np", "2", "--oversubscribe", "--allow-run-as-root",
             "fmpm", "b.prm", "o.prm"])

    def test_quick_mode_replaces_axes_and_adds_settings(self):
        body = """\
            base = base.prm
            axis Method/Particle update = flip | pic | fmpm
            axis Mesh/Subdivisions = 16, 1 | 32, 2 | 64, 4
            linked dt Time/Time step = 1 | 2 | 3
            linked dt Time/End time = 4 | 5 | 6
            quick axis Mesh/Subdivisions = 4, 1
            quick linked dt Time/Time step = 7 | 8
            quick linked dt Time/End time = 9 | 10
            quick set Output/Verbose = false
            """
        full = study.expand_runs(self.parse(body), self.dir)
        self.assertEqual(len(full), 27)
        self.assertNotIn("Output/Verbose", full[0].settings)
        quick = study.expand_runs(self.parse(body, quick=True), self.dir)
        self.assertEqual(len(quick), 3 * 1 * 2)
        self.assertEqual({r.swept["Mesh/Subdivisions"] for r in quick},
                         {"4, 1"})
        self.assertEqual({(r.swept["Time/Time step"], r.swept["Time/End time"])
                          for r in quick}, {("7", "9"), ("8", "10")})
        self.assertEqual(quick[0].settings["Output/Verbose"], "false")

    def test_chart_lines(self):
        parsed = self.parse("""\
            base = base.prm
            chart x_resolution = Mesh/Subdivisions
            chart cell size = 2 / n
            chart method = Method/Particle update + Method/Mass matrix
            """)
        self.assertEqual(parsed.charts["method"],
                         "Method/Particle update + Method/Mass matrix")
        self.assertAlmostEqual(
            study.evaluate_cell_size(parsed.cell_size, 8.0), 0.25)
        self.assertEqual(study.first_number("32, 2"), 32.0)


class OverrideFileTest(TempDirTest):
    """Override files nest subsections and read back with fmpm's syntax."""

    def test_round_trip_through_the_fake_parser(self):
        settings = {
            "Dimension": "3",
            "Method/Particle update": "fmpm",
            "Mesh/Subdivisions": "32, 2",
            "Material 0/Linear elastic/Young's modulus": "1e6",
            "Material 0/Density": "1000",
            "Method/Mass matrix": "consistent",
        }
        text = study.format_override(settings, "study_out/run_0001",
                                     comment="test")
        parsed = fake.parse_prm_text(text)
        self.assertEqual(parsed, dict(settings, **{
            "Output/Directory": "study_out/run_0001"}))
        self.assertIn("subsection Material 0\n  set Density = 1000\n"
                      "  subsection Linear elastic\n"
                      "    set Young's modulus = 1e6\n  end\nend", text)
        self.assertEqual(text.count("subsection Method"), 1)

    def test_override_wins_over_base(self):
        override = self.dir / "override.prm"
        override.write_text(study.format_override(
            {"Method/Particle update": "pic"}, "out/run_0002"))
        values = fake.parse_prm_files([self.dir / "base.prm", override])
        self.assertEqual(values["Method/Particle update"], "pic")
        self.assertEqual(values["Method/Mass matrix"], "lumped")
        self.assertEqual(values["Output/Directory"], "out/run_0002")


class BadStudyFileTest(TempDirTest):
    """Errors name the file and the line."""

    def assert_error(self, body, line, *phrases):
        with self.assertRaises(study.StudyError) as caught:
            self.parse(body)
        message = str(caught.exception)
        self.assertIn(f"test.study:{line}:", message)
        for phrase in phrases:
            self.assertIn(phrase, message)

    def test_unknown_keyword(self):
        self.assert_error("""\
            base = base.prm
            # comment
            sweep Method/Particle update = flip
            """, 3, "unknown keyword 'sweep'", "allowed: base, title, axis")

    def test_missing_base(self):
        with self.assertRaises(study.StudyError) as caught:
            self.parse("axis Method/Particle update = flip\n")
        self.assertIn("missing 'base", str(caught.exception))
        self.assert_error("title = x\nbase =\n", 2, "'base' has no value")
        self.assert_error("\nbase = nowhere.prm\n", 2, "nowhere.prm",
                          "not found")

    def test_axis_without_values(self):
        self.assert_error("""\
            base = base.prm
            axis Method/Particle update =
            """, 2, "has no values")
        self.assert_error("base = base.prm\naxis A = 1 | | 2\n", 2,
                          "empty value")

    def test_other_errors(self):
        self.assert_error("""\
            base = base.prm
            linked g A = 1 | 2
            linked g B = 1 | 2 | 3
            """, 3, "linked group 'g'")
        self.assert_error("base = base.prm\nchart colour = red\n", 2,
                          "unknown chart key", "x_resolution")
        self.assert_error("base = base.prm\nchart cell size = exit(n)\n", 2,
                          "bad cell size")
        self.assert_error("base = base.prm\naxis MPI ranks = 1 | two\n", 2,
                          "positive integer")
        self.assert_error("base = base.prm\naxis A = 1\nset A = 2\n", 3,
                          "both set and swept")
        with self.assertRaises(study.StudyError) as caught:
            self.parse("base = base.prm\naxis A = 1\nquick axis B = 2\n",
                       quick=True)
        self.assertIn("test.study:3:", str(caught.exception))

    def test_command_line_reports_error(self):
        self.write_study("base = base.prm\nfoo = 1\n")
        result = self.run_cli("test.study")
        self.assertEqual(result.returncode, 2)
        self.assertIn("test.study:2:", result.stderr)
        self.assertIn("unknown keyword 'foo'", result.stderr)
        self.assertFalse((self.dir / "study_test").exists())


CONVERGENCE_STUDY = """\
# Convergence of the fake methods.
base = base.prm
title = Fake convergence
axis Method/Particle update = flip | pic | fmpm
axis Mesh/Subdivisions = 4, 1 | 8, 1 | 16, 1 | 32, 1
set Time/Courant number = 0.5
quick axis Mesh/Subdivisions = 4, 1 | 8, 1
chart x_resolution = Mesh/Subdivisions
chart method = Method/Particle update
chart error = error_velocity_l2
"""


class ConvergenceStudyTest(TempDirTest):
    """A full study run once through the command line (shared by the tests
    of this class, which must not change it)."""

    @classmethod
    def setUpClass(cls):
        cls._shared_tmp = tempfile.TemporaryDirectory(prefix="fmpm_study_")
        cls.shared = Path(cls._shared_tmp.name)
        (cls.shared / "base.prm").write_text(BASE_PRM)
        (cls.shared / "conv.study").write_text(CONVERGENCE_STUDY)
        cls.shared_counter = cls.shared / "counter.txt"
        cls.result = run_cli(cls.shared, cls.shared_counter, "conv.study",
                             "--output", "out")
        cls.out = cls.shared / "out"

    @classmethod
    def tearDownClass(cls):
        cls._shared_tmp.cleanup()

    def test_plan_results_and_progress(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        _, plan = self.read_csv(self.out / "runs.csv")
        self.assertEqual(len(plan), 12)
        self.assertEqual(self.invocations(self.shared_counter), 12)
        self.assertRegex(self.result.stdout, re.compile(
            r"^\[1/12\] run_0001 flip 4,1 \.\.\. completed in [\d.]+ s "
            r"\(elapsed [\d.]+ s, about [\d.]+ s left\)$", re.M))
        self.assertIn("[12/12] run_0012 fmpm 32,1 ... completed",
                      self.result.stdout)

        columns, rows = self.read_csv(self.out / "results.csv")
        self.assertEqual(columns[:3], ["run_id", "Method/Particle update",
                                       "Mesh/Subdivisions"])
        for column in ("status", "failure_step", "failure_time",
                       "n_particles", "n_cells", "n_steps", "wall_seconds",
                       "particle_steps_per_second", "error_velocity_l2",
                       "error_displacement_l2", "energy_error",
                       "final_kinetic_energy", "final_strain_energy"):
            self.assertIn(column, columns)
        self.assertEqual([r["run_id"] for r in rows],
                         [f"run_{i:04d}" for i in range(1, 13)])
        self.assertEqual({r["status"] for r in rows}, {"completed"})
        pic_16 = rows[6]
        self.assertEqual((pic_16["Method/Particle update"],
                          pic_16["Mesh/Subdivisions"]), ("pic", "16, 1"))
        self.assertAlmostEqual(float(pic_16["error_velocity_l2"]), 0.5 / 16)
        self.assertEqual(pic_16["failure_step"], "")

    def test_convergence_orders_and_charts(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        _, orders = self.read_csv(self.out / "convergence_orders.csv")
        found = {row["method"]: float(row["order"]) for row in orders}
        self.assertEqual(set(found), set(fake.ORDER))
        for method, order in fake.ORDER.items():
            self.assertAlmostEqual(found[method], order, delta=0.05)
        self.assertEqual({row["n_points"] for row in orders}, {"4"})
        for name in ("error_vs_wall_time.png", "convergence.png",
                     "energy_history.png"):
            path = self.out / name
            self.assertTrue(path.is_file(), name)
            self.assertGreater(path.stat().st_size, 1000, name)
            self.assertEqual(path.read_bytes()[:4], b"\x89PNG")
        self.assertFalse((self.out / "stability_map.png").exists())
        self.assertIn("Chart skipped: stability_map.png", self.result.stdout)

    def test_plot_only_rebuilds_without_running(self):
        shutil.copytree(self.out, self.dir / "out")
        shutil.copy(self.shared / "conv.study", self.dir)
        for name in ("results.csv", "convergence.png"):
            (self.dir / "out" / name).unlink()
        result = self.run_cli("conv.study", "--output", "out", "--plot-only",
                              fmpm=None)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(self.invocations(), 0)
        self.assertEqual(
            (self.dir / "out" / "results.csv").read_text(),
            (self.out / "results.csv").read_text().replace(
                str(self.shared), str(self.dir)))
        self.assertGreater(
            (self.dir / "out" / "convergence.png").stat().st_size, 1000)

    def test_resume_skips_finished_runs(self):
        self.write_study(CONVERGENCE_STUDY, "conv.study")
        first = self.run_cli("conv.study", "--no-charts")
        self.assertEqual(first.returncode, 0, first.stderr)
        out = self.dir / "study_conv"
        summary = out / "run_0005" / "summary.json"
        before = summary.stat().st_mtime_ns
        again = self.run_cli("conv.study", "--no-charts")
        self.assertEqual(again.returncode, 0, again.stderr)
        self.assertIn("Skipped 12 of 12 runs", again.stdout)
        self.assertEqual(self.invocations(), 12)
        self.assertEqual(summary.stat().st_mtime_ns, before)

        # An interrupted run (no summary) is redone, and only that one.
        (out / "run_0003" / "summary.json").unlink()
        (out / "run_0003" / "run.json").unlink()
        again = self.run_cli("conv.study", "--no-charts")
        self.assertIn("Skipped 11 of 12 runs", again.stdout)
        self.assertEqual(self.invocations(), 13)
        self.assertIn("run_0003", self.counter.read_text().splitlines()[-1])

        # Runs whose parameters changed are redone.
        self.write_study(CONVERGENCE_STUDY.replace("32, 1", "64, 1"),
                         "conv.study")
        again = self.run_cli("conv.study", "--no-charts")
        self.assertIn("Skipped 9 of 12 runs", again.stdout)
        self.assertEqual(self.invocations(), 16)

    def test_default_directory_is_beside_the_study_file(self):
        # Run from another directory: the output goes beside the study
        # file, not into the current directory; --output is relative to
        # the current directory.
        (self.dir / "studies").mkdir()
        (self.dir / "elsewhere").mkdir()
        (self.dir / "studies" / "conv.study").write_text(
            CONVERGENCE_STUDY.replace("base = base.prm",
                                      "base = ../base.prm"))
        result = run_cli(self.dir / "elsewhere", self.counter,
                         "../studies/conv.study", "--quick", "--no-charts")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = self.dir / "studies" / "study_conv_quick"
        _, rows = self.read_csv(out / "results.csv")
        self.assertEqual(len(rows), 6)
        self.assertEqual(list((self.dir / "elsewhere").iterdir()), [])
        self.assertIn(f"output in {out}", result.stdout)
        result = run_cli(self.dir / "elsewhere", self.counter,
                         "../studies/conv.study", "--quick", "--no-charts",
                         "--output", "mine")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertTrue(
            (self.dir / "elsewhere" / "mine" / "results.csv").is_file())
        self.assertEqual(study.default_output_dir(
            self.dir / "studies" / "conv.study"), self.dir / "studies" /
            "study_conv")

    def test_quick_mode_default_directory(self):
        self.write_study(CONVERGENCE_STUDY, "conv.study")
        result = self.run_cli("conv.study", "--quick", "--no-charts")
        self.assertEqual(result.returncode, 0, result.stderr)
        _, rows = self.read_csv(self.dir / "study_conv_quick" / "results.csv")
        self.assertEqual(len(rows), 6)
        self.assertEqual(self.invocations(), 6)


class FailureTest(TempDirTest):
    """Failed, crashed and timed out runs are recorded, not fatal."""

    def test_unstable_runs_and_stability_map(self):
        self.write_study("""\
            base = base.prm
            axis Method/Particle update = flip | pic
            axis Time/Courant number = 0.4 | 0.8 | 1.2
            axis Body 0/Points per cell = 2 | 4
            chart method = Method/Particle update
            chart stability_x = Time/Courant number
            chart stability_y = Body 0/Points per cell
            """)
        result = self.run_cli("test.study", "--jobs", "2")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = self.dir / "study_test"
        _, rows = self.read_csv(out / "results.csv")
        self.assertEqual(len(rows), 12)
        for row in rows:
            method = row["Method/Particle update"]
            courant = float(row["Time/Courant number"])
            if courant > fake.THRESHOLD[method]:
                self.assertEqual(row["status"], "failed: energy growth")
                step = int(row["failure_step"])
                self.assertGreater(step, 0)
                self.assertAlmostEqual(float(row["failure_time"]),
                                       step * 0.1 / 20)
                self.assertEqual(row["error_velocity_l2"], "")
                self.assertEqual(row["exit_code"], "1")
            else:
                self.assertEqual(row["status"], "completed")
                self.assertEqual(row["failure_step"], "")
        self.assertEqual(sum(r["status"] != "completed" for r in rows), 6)
        self.assertGreater((out / "stability_map.png").stat().st_size, 1000)
        self.assertIn("Chart skipped: convergence.png", result.stdout)

    def test_crash_and_timeout(self):
        self.write_study("""\
            base = base.prm
            axis Test/Crash = false | true
            axis Test/Sleep = 0 | 20
            """)
        result = self.run_cli("test.study", "--timeout", "1", "--jobs", "2",
                              "--no-charts")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = self.dir / "study_test"
        _, rows = self.read_csv(out / "results.csv")
        statuses = [r["status"] for r in rows]
        self.assertEqual(statuses, [
            "completed", "failed: timeout",
            "failed: no summary (exit code 3)", "failed: timeout"])
        self.assertEqual(rows[2]["exit_code"], "3")
        self.assertIn("crashing as asked",
                      (out / "run_0003" / "log.txt").read_text())
        # Crashes and timeouts are results too: resuming does not redo them.
        again = self.run_cli("test.study", "--timeout", "1", "--no-charts")
        self.assertIn("Skipped 4 of 4 runs", again.stdout)
        self.assertEqual(self.invocations(), 4)

    def test_no_summary_at_all_is_an_error(self):
        self.write_study("base = base.prm\nset Test/Crash = true\n")
        result = self.run_cli("test.study")
        self.assertEqual(result.returncode, 1)
        self.assertIn("no run produced a summary", result.stderr)

    def test_missing_fmpm_is_reported(self):
        self.write_study("base = base.prm\n")
        result = self.run_cli("test.study", fmpm=str(self.dir / "nothing"))
        self.assertEqual(result.returncode, 2)
        self.assertIn("not found", result.stderr)


class ExtensionTest(TempDirTest):
    """The Label pseudo-parameter, stability limits, the extra convergence
    columns and --prune."""

    LABEL_STUDY = """\
        base = base.prm
        linked method Label = FLIP | PIC | FMPM
        linked method Method/Particle update = flip | pic | fmpm
        axis Time/Courant number = 0.4 | 0.7 | 0.9 | 1.2
        chart method = Label
        chart stability_x = Time/Courant number
        chart stability_y = Label
        """

    def test_label_is_not_written_to_the_parameter_file(self):
        parsed = self.parse(self.LABEL_STUDY)
        runs = study.expand_runs(parsed, self.dir / "out")
        self.assertEqual(len(runs), 12)
        self.assertEqual(runs[0].swept["Label"], "FLIP")
        self.assertNotIn("Label", runs[0].settings)
        text = study.format_override(runs[0].settings, runs[0].directory)
        self.assertNotIn("Label", text)
        self.assertIn("set Particle update = flip", text)
        self.assertEqual(runs[0].label(), "FLIP 0.4")

    def test_stability_limits_in_one_panel_and_prune(self):
        self.write_study(self.LABEL_STUDY)
        result = self.run_cli("test.study", "--jobs", "2", "--prune")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = self.dir / "study_test"
        _, rows = self.read_csv(out / "stability_limits.csv")
        limits = {r["Label"]: (r["largest stable Time/Courant number"],
                               r["smallest unstable Time/Courant number"])
                  for r in rows}
        # fake thresholds: flip 0.6, pic 1.0, fmpm 0.8
        self.assertEqual(limits, {"FLIP": ("0.4", "0.7"),
                                  "PIC": ("0.9", "1.2"),
                                  "FMPM": ("0.7", "0.9")})
        self.assertEqual({r["method"] for r in rows}, {""})
        for name in ("stability_map.png", "stability_limits.png"):
            self.assertGreater((out / name).stat().st_size, 1000, name)
        self.assertIn("Pruned the run directories", result.stdout)
        kept = sorted(p.name for p in (out / "run_0001").iterdir())
        self.assertEqual(kept, sorted(["override.prm", "run.json",
                                       "summary.json", "history.csv"]))
        # Resuming after pruning still skips the finished runs.
        again = self.run_cli("test.study", "--no-charts")
        self.assertIn("Skipped 12 of 12 runs", again.stdout)

    def test_chart_skip(self):
        self.write_study(self.LABEL_STUDY + "chart skip = stability_limits, "
                         "energy_history.png\n")
        result = self.run_cli("test.study")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = self.dir / "study_test"
        self.assertTrue((out / "stability_map.png").is_file())
        self.assertFalse((out / "stability_limits.png").exists())
        self.assertFalse((out / "energy_history.png").exists())
        self.assertIn("Chart skipped: stability_limits.png: 'chart skip'",
                      result.stdout)
        # The CSV file is still written.
        self.assertTrue((out / "stability_limits.csv").is_file())

    def test_stable_everywhere_has_no_unstable_value(self):
        self.write_study(self.LABEL_STUDY.replace("| 1.2", ""))
        result = self.run_cli("test.study", "--no-charts")
        self.assertEqual(result.returncode, 0, result.stderr)
        _, rows = self.read_csv(self.dir / "study_test" /
                                "stability_limits.csv")
        pic = [r for r in rows if r["Label"] == "PIC"][0]
        self.assertEqual(pic["largest stable Time/Courant number"], "0.9")
        self.assertEqual(pic["smallest unstable Time/Courant number"], "")

    def test_convergence_table_has_finest_pair_and_displacement(self):
        self.write_study(CONVERGENCE_STUDY, "conv.study")
        result = self.run_cli("conv.study", "--no-charts")
        self.assertEqual(result.returncode, 0, result.stderr)
        columns, rows = self.read_csv(self.dir / "study_conv" /
                                      "convergence_orders.csv")
        self.assertEqual(columns, ["method", "order", "n_points",
                                   "order_finest_pair",
                                   "order_error_displacement_l2"])
        for row in rows:
            expected = fake.ORDER[row["method"]]
            self.assertAlmostEqual(float(row["order_finest_pair"]),
                                   expected, delta=0.05)
            self.assertAlmostEqual(
                float(row["order_error_displacement_l2"]), expected,
                delta=0.05)


REFERENCE_STUDY = """\
base = base.prm
axis Method/Particle update = flip | fmpm
axis Mesh/Subdivisions = 8, 1 | 16, 1 | 32, 1
set Test/No analytical = true
reference = Mesh/Subdivisions = 1024, 1 | Time/Courant number = 0.2
reference columns = kinetic_energy, total_energy
chart x_resolution = Mesh/Subdivisions
chart method = Method/Particle update
chart error = error_reference_kinetic_energy
"""


class ReferenceRunTest(TempDirTest):
    """Without an analytical solution, errors against a fine reference."""

    @staticmethod
    def expected_error(method, n, n_ref=1024):
        """The relative L2 kinetic-energy difference of the fake's run at
        resolution n against its (exact) reference at n_ref."""
        order, constant = fake.ORDER[method], fake.CONSTANT[method]
        ref_term = fake.CONSTANT["flip"] * (1 / n_ref) ** fake.ORDER["flip"]
        steps = 2 * n + 1
        difference = norm = 0.0
        for step in range(steps + 1):
            s = study.math.sin(2 * study.math.pi * step / steps)
            ref = 1 + ref_term * s
            difference += (1 + constant * (1 / n) ** order * s - ref) ** 2
            norm += ref ** 2
        return (difference / norm) ** 0.5

    def test_errors_against_the_reference_run(self):
        self.write_study(REFERENCE_STUDY, "ref.study")
        result = self.run_cli("ref.study", "--output", "out")
        self.assertEqual(result.returncode, 0, result.stderr)
        out = self.dir / "out"
        self.assertEqual(self.invocations(), 7)
        self.assertIn("[1/7] reference reference ... completed",
                      result.stdout)
        override = (out / "reference" / "override.prm").read_text()
        self.assertIn("set Subdivisions = 1024, 1", override)
        self.assertIn("set Courant number = 0.2", override)
        self.assertIn("set No analytical = true", override)

        columns, rows = self.read_csv(out / "results.csv")
        self.assertIn("error_reference_kinetic_energy", columns)
        self.assertIn("error_reference_total_energy", columns)
        self.assertNotIn("error_reference_strain_energy", columns)
        self.assertEqual(len(rows), 6)  # the reference is no study run
        for row in rows:
            method = row["Method/Particle update"]
            n = int(row["Mesh/Subdivisions"].split(",")[0])
            self.assertEqual(row["error_velocity_l2"], "")
            self.assertAlmostEqual(
                float(row["error_reference_kinetic_energy"]),
                self.expected_error(method, n), delta=1e-3 *
                self.expected_error(method, n))
            self.assertLess(float(row["error_reference_total_energy"]),
                            1e-12)
        _, orders = self.read_csv(out / "convergence_orders.csv")
        found = {row["method"]: float(row["order"]) for row in orders}
        self.assertEqual(set(found), {"flip", "fmpm"})
        for method, order in found.items():
            self.assertAlmostEqual(order, fake.ORDER[method], delta=0.05)
        self.assertTrue((out / "convergence.png").is_file())
        self.assertTrue((out / "error_vs_wall_time.png").is_file())

        # Resuming skips the completed reference; --plot-only reuses it.
        again = self.run_cli("ref.study", "--output", "out")
        self.assertEqual(again.returncode, 0, again.stderr)
        self.assertIn("Skipped the reference run", again.stdout)
        self.assertEqual(self.invocations(), 7)
        plot = self.run_cli("ref.study", "--output", "out", "--plot-only",
                            "--no-charts")
        self.assertEqual(plot.returncode, 0, plot.stderr)
        _, replotted = self.read_csv(out / "results.csv")
        self.assertEqual(replotted, rows)

        # Without a completed reference there are no reference errors.
        shutil.rmtree(out / "reference")
        plot = self.run_cli("ref.study", "--output", "out", "--plot-only",
                            "--no-charts")
        self.assertEqual(plot.returncode, 0, plot.stderr)
        self.assertIn("no error_reference_* columns", plot.stderr)
        _, rows = self.read_csv(out / "results.csv")
        self.assertEqual({r["error_reference_kinetic_energy"] for r in rows},
                         {""})

    def test_analytical_errors_take_precedence(self):
        self.write_study(REFERENCE_STUDY.replace(
            "set Test/No analytical = true\n", ""), "ref.study")
        result = self.run_cli("ref.study", "--output", "out", "--no-charts")
        self.assertEqual(result.returncode, 0, result.stderr)
        _, rows = self.read_csv(self.dir / "out" / "results.csv")
        for row in rows:
            self.assertNotEqual(row["error_velocity_l2"], "")
            self.assertEqual(row["error_reference_kinetic_energy"], "")

    def test_parsing(self):
        parsed = self.parse("""\
            base = base.prm
            set Time/End time = 0.5
            reference = Mesh/Subdivisions=80, 80 | Time/Courant number=0.2
            """)
        self.assertEqual(parsed.reference, {"Mesh/Subdivisions": "80, 80",
                                            "Time/Courant number": "0.2"})
        self.assertEqual(parsed.reference_columns,
                         study.DEFAULT_REFERENCE_COLUMNS)
        run = study.reference_run(parsed, self.dir / "out")
        self.assertEqual(run.directory, (self.dir / "out" /
                                         "reference").resolve())
        self.assertEqual(run.settings["Time/End time"], "0.5")
        self.assertEqual(run.settings["Mesh/Subdivisions"], "80, 80")
        for body, message in (
                ("reference = Mesh/Subdivisions", "not 'PATH = VALUE'"),
                ("reference = Output/Directory = x", "cannot be set"),
                ("reference columns =", "no history.csv column"),
                ("reference = A = 1\nreference = B = 2", "given twice")):
            with self.assertRaises(study.StudyError) as caught:
                self.parse("base = base.prm\n" + body + "\n")
            self.assertIn(message, str(caught.exception))

    def test_relative_l2_difference_interpolates(self):
        ref_t, ref_v = [0.0, 1.0, 2.0], [1.0, 3.0, 5.0]  # r(t) = 1 + 2t
        value = study.relative_l2_difference([0.5, 1.5, 3.0],
                                             [2.0, 4.0 + 0.4, 99.0],
                                             ref_t, ref_v)
        self.assertAlmostEqual(value, (0.16 / (4.0 + 16.0)) ** 0.5)
        self.assertIsNone(study.relative_l2_difference([3.0], [1.0],
                                                       ref_t, ref_v))


class HelperTest(unittest.TestCase):
    """Small pure functions."""

    def test_pareto_front(self):
        points = [(1.0, 1.0), (2.0, 0.5), (3.0, 0.6), (0.5, 2.0), (2.0, 2.0)]
        self.assertEqual(study.pareto_front(points), [0, 1, 3])

    def test_fit_order(self):
        points = [(h, 3.0 * h ** 1.5) for h in (0.5, 0.25, 0.125)]
        self.assertAlmostEqual(study.fit_order(points), 1.5)
        self.assertIsNone(study.fit_order([(0.5, 1.0), (0.5, 2.0)]))

    def test_finest_pair_order(self):
        points = [(0.125, 0.125 ** 2), (0.25, 0.25 ** 2), (0.5, 1.0)]
        self.assertAlmostEqual(study.finest_pair_order(points), 2.0)
        self.assertIsNone(study.finest_pair_order(points[:1]))


if __name__ == "__main__":
    unittest.main()
