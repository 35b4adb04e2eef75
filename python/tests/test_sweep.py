"""freespace-sweep on a local Dask cluster of two worker processes over the loopback
interface: its table equals the same cases run one by one in this process, its aggregates
equal seed_summary's over those drives."""

import csv
import importlib.util
import json
import math
import os
import signal
import subprocess
import sys
import tempfile
import unittest

import freespace as fs
from freespace import sweep
from common import data_dir, env_path, source_dir

GRID = """
config: {config}
overrides: {{polygon.shape: inside}}
scenarios: [urban, parking]
seeds: 1-2
duration_s: 2
grid:
  polygon.margin_cells: [0, 1]
logs:
  - {{log: {log}, config: {indoor}, max_scans: 40}}
"""


def _lost_task(case):
    raise RuntimeError("worker gone")


def not_a_number(v):
    return v is None or (isinstance(v, float) and math.isnan(v))  # sweep.json: null


def same(a, b):
    return (not_a_number(a) and not_a_number(b)) or a == b


class SweepTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.TemporaryDirectory()
        cls.grid_path = os.path.join(cls.dir.name, "grid.yaml")
        with open(cls.grid_path, "w") as f:
            f.write(GRID.format(config=os.path.join(source_dir(), "configs", "scala.yaml"),
                                log=os.path.join(data_dir(), "carmen", "intel.clf"),
                                indoor=os.path.join(source_dir(), "configs", "indoor.yaml")))
        cls.out = os.path.join(cls.dir.name, "out")
        cls.proc = subprocess.run(
            [sys.executable, "-m", "freespace.sweep", cls.grid_path, "--workers", "2", "--out",
             cls.out], capture_output=True, text=True)
        if cls.proc.returncode == 0:
            with open(os.path.join(cls.out, "sweep.json")) as f:
                cls.result = json.load(f)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def setUp(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)

    def test_runs_on_two_workers(self):
        self.assertEqual(self.result["timing"]["workers"], 2)
        rows = self.result["cases"]
        self.assertEqual(len(rows), 2 * (2 * 2 + 1))
        self.assertEqual([r["case"] for r in rows], list(range(len(rows))))
        self.assertEqual(len({r["worker"] for r in rows}), 2)
        self.assertTrue(all(r["error"] == "" for r in rows))
        self.assertIn("10 cases", self.proc.stdout)
        self.assertEqual(self.proc.stdout.count("freespace-sweep: ["), 10)  # a line per case

    def test_table_equals_the_cases_run_one_by_one(self):
        cases = sweep.make_cases(sweep.load_grid(self.grid_path))
        rows = self.result["cases"]
        skip = {"wall_s", "worker"} | {f"{s}_us" for s in sweep.STAGES}
        drives = {}
        for case, row in zip(cases, rows):
            if case["kind"] == "sim":
                config = fs.Config.from_yaml(case["config"])
                self.assertTrue(case["keep_sensor"])  # scala.yaml sets the sensor
                drive = fs.evaluate_drive(config, case["scenario"], case["seed"], duration_s=2,
                                          keep_sensor=True)
                key = (case["setting"]["polygon.margin_cells"], case["scenario"])
                drives.setdefault(key, []).append(drive)
                self.assertEqual(row["scans"], drive.scans)
            expected = sweep.run_case(case)
            self.assertEqual(set(row), set(expected))
            for k in set(row) - skip:
                self.assertTrue(same(row[k], expected[k]), f"case {case['case']} {k}: "
                                f"{row[k]} vs {expected[k]}")
        log_rows = [r for r in rows if r["kind"] == "log"]
        self.assertEqual([r["scans"] for r in log_rows], [40, 40])
        self.assertTrue(all(r["coverage"] is None for r in log_rows))  # no truth: null
        aggregates = self.result["aggregates"]
        self.assertEqual(len(aggregates), 4)
        for agg in aggregates:
            summary = fs.seed_summary(drives[(agg["polygon.margin_cells"], agg["scenario"])])[0]
            self.assertEqual(agg["seeds"], 2)
            for m in sweep.METRICS:
                self.assertAlmostEqual(agg[f"{m}_mean"], summary["mean"][m], places=12)
                self.assertEqual(agg[f"{m}_worst"], summary["worst"][m]["value"])
                self.assertEqual(agg[f"{m}_worst_seed"], summary["worst"][m]["seed"])

    def test_writes_csv_and_plot(self):
        with open(os.path.join(self.out, "cases.csv")) as f:
            table = list(csv.DictReader(f))
        self.assertEqual(len(table), len(self.result["cases"]))
        self.assertIn("intrusion_m2", table[0])
        self.assertIn("polygon.margin_cells", table[0])
        with open(os.path.join(self.out, "aggregates.csv")) as f:
            self.assertEqual(len(list(csv.DictReader(f))), 4)
        plot = os.path.join(self.out, "tradeoff.png")
        if importlib.util.find_spec("matplotlib"):
            with open(plot, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        else:
            self.assertFalse(os.path.exists(plot))
            self.assertIn("matplotlib is not installed", self.proc.stdout)

    def test_console_script_runs_a_sweep(self):
        small = os.path.join(self.dir.name, "small.yaml")
        with open(small, "w") as f:
            f.write("scenarios: [highway]\nseeds: [5]\nduration_s: 1\n")
        out = os.path.join(self.dir.name, "small")
        run = subprocess.run([env_path("FREESPACE_SWEEP"), small, "--workers", "1", "--out", out,
                              "--no-plot"], capture_output=True, text=True)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn("no plot: --no-plot", run.stdout)
        self.assertIn("[1/1] case 0 (highway seed 5): ", run.stdout)
        with open(os.path.join(out, "sweep.json")) as f:
            rows = json.load(f)["cases"]
        self.assertEqual([(r["scenario"], r["seed"], r["error"]) for r in rows],
                         [("highway", 5, "")])
        self.assertGreater(rows[0]["scans"], 0)

    def test_an_earlier_sweeps_files_go_and_a_file_in_the_way_is_an_error(self):
        logs_only = os.path.join(self.dir.name, "logs_only.yaml")
        with open(logs_only, "w") as f:
            f.write(f"logs: [{{log: {os.path.join(data_dir(), 'carmen', 'intel.clf')}, "
                    "max_scans: 5}]\n")
        out = os.path.join(self.dir.name, "earlier")
        os.makedirs(out)
        for name in ("aggregates.csv", "tradeoff.png"):
            with open(os.path.join(out, name), "w") as f:
                f.write("an earlier sweep's\n")
        run = subprocess.run([sys.executable, "-m", "freespace.sweep", logs_only, "--workers", "1",
                              "--out", out], capture_output=True, text=True)
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertIn("removed an earlier sweep's aggregates.csv, tradeoff.png", run.stdout)
        self.assertEqual(sorted(os.listdir(out)), ["cases.csv", "sweep.json"])
        self.assertIn(f"wrote {out}/cases.csv, sweep.json (no plot", run.stdout)
        in_the_way = os.path.join(self.dir.name, "a_file")
        with open(in_the_way, "w") as f:
            f.write("x")
        run = subprocess.run([sys.executable, "-m", "freespace.sweep", logs_only, "--out",
                              in_the_way], capture_output=True, text=True)
        self.assertEqual(run.returncode, 2, run.stderr)
        self.assertNotIn("cases on", run.stdout)  # refused before any case ran

    def test_ctrl_c_writes_the_ended_cases_and_marks_the_rest(self):
        from unittest import mock

        cases = sweep.make_cases(sweep.load_grid(self.grid_path))[:3]

        class Task:  # as much of a Dask future as _collect uses
            def __init__(self, key):
                self.key = key

            def result(self):
                return sweep.run_case(cases[0])

        tasks = [Task("k0"), Task("k1"), Task("k2")]

        def interrupted(futures):
            yield tasks[0]
            raise KeyboardInterrupt

        with mock.patch("dask.distributed.as_completed", interrupted):
            rows, stopped = sweep._collect(tasks, cases, quiet=True)
        self.assertTrue(stopped)
        self.assertEqual(sorted(r["case"] for r in rows), [0, 1, 2])
        self.assertEqual(rows[0]["error"], "")
        for r in rows[1:]:
            self.assertIn("interrupted", r["error"])

    def test_ctrl_c_while_the_cluster_starts_marks_every_case(self):
        from unittest import mock

        cases = sweep.make_cases(sweep.load_grid(self.grid_path))[:3]

        closed = []

        class Started:  # as much of a cluster and a client as the start and the close use
            def __init__(self, name):
                self.name = name

            def close(self):
                closed.append(self.name)

        def starting(*args, **kwargs):  # Ctrl-C comes while the cluster starts
            os.kill(os.getpid(), signal.SIGINT)
            return Started("cluster")

        with mock.patch("dask.distributed.LocalCluster", starting), \
                mock.patch("dask.distributed.Client", lambda cluster: Started("client")):
            rows, timing = sweep.run_sweep(cases, workers=1)
        self.assertTrue(timing["interrupted"])
        self.assertEqual(sorted(closed), ["client", "cluster"])  # started whole, then closed
        self.assertEqual([r["case"] for r in rows], [0, 1, 2])
        for r in rows:
            self.assertIn("interrupted (SIGINT) before it started", r["error"])

    def test_an_unreachable_scheduler_is_an_error(self):
        logs_only = os.path.join(self.dir.name, "one_log.yaml")
        with open(logs_only, "w") as f:
            f.write(f"logs: [{{log: {os.path.join(data_dir(), 'carmen', 'intel.clf')}, "
                    "max_scans: 5}]\n")
        env = dict(os.environ, DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="1s")
        run = subprocess.run([sys.executable, "-m", "freespace.sweep", logs_only, "--scheduler",
                              "tcp://127.0.0.1:9", "--out", os.path.join(self.dir.name, "nosched")],
                             capture_output=True, text=True, env=env)
        self.assertEqual(run.returncode, 2, run.stderr)
        self.assertIn("cannot reach the scheduler tcp://127.0.0.1:9", run.stderr)
        self.assertNotIn("Traceback", run.stderr)
        run = subprocess.run([sys.executable, "-m", "freespace.sweep", logs_only, "--scheduler",
                              "127.0.0.1:notaport", "--out", os.path.join(self.dir.name, "nosched")],
                             capture_output=True, text=True, env=env)
        self.assertEqual(run.returncode, 2, run.stderr)
        self.assertIn("cannot reach the scheduler 127.0.0.1:notaport: ValueError", run.stderr)

    def test_a_failed_write_leaves_whole_files_only(self):
        from unittest import mock

        out = os.path.join(self.dir.name, "full_disk")
        os.makedirs(out)
        rows = self.result["cases"]

        def no_space(document, f, **kwargs):
            f.write('{"definitions": ')
            raise OSError(28, "No space left on device")

        with mock.patch("json.dump", no_space):
            with self.assertRaises(OSError):
                sweep.write_outputs(out, {}, rows, [], {})
        self.assertEqual(os.listdir(out), ["cases.csv"])
        with open(os.path.join(out, "cases.csv")) as f:
            self.assertEqual(len(list(csv.DictReader(f))), len(rows))

    def test_task_keys_are_each_sweeps_own(self):
        cases = sweep.make_cases(sweep.load_grid(self.grid_path))
        a, b = sweep.task_keys(cases), sweep.task_keys(cases)
        self.assertEqual(len(set(a)), len(cases))
        self.assertFalse(set(a) & set(b))

    def test_a_logs_malformed_lines_are_counted(self):
        with open(os.path.join(data_dir(), "carmen", "intel.clf")) as f:
            lines = f.readlines()
        cut = os.path.join(self.dir.name, "cut.clf")
        kept = 0
        with open(cut, "w") as f:
            for line in lines:
                if line.startswith("FLASER") and kept < 3:
                    line = line[:40] + "\n"  # cut short
                    kept += 1
                f.write(line)
        case = dict(sweep.make_cases(sweep.load_grid(self.grid_path))[-1], log=cut, max_scans=20)
        row = sweep.run_case(case)
        self.assertEqual(row["error"], "")
        self.assertEqual(row["malformed_lines"], 3)
        self.assertEqual(row["scans"], 20)

    def test_a_task_lost_on_the_cluster_is_a_row_with_its_error(self):
        from dask.distributed import Client, LocalCluster

        cases = sweep.make_cases(sweep.load_grid(self.grid_path))[:2]
        # A cluster of threads in this process (inproc://): the task raises where a worker
        # process would have died.
        with LocalCluster(n_workers=1, processes=False, dashboard_address="127.0.0.1:0") as \
                cluster, Client(cluster) as client:
            futures = client.map(_lost_task, cases, pure=False)
            rows, interrupted = sweep._collect(futures, cases, quiet=True)
        self.assertFalse(interrupted)
        self.assertEqual(sorted(r["case"] for r in rows), [0, 1])
        for r in rows:
            self.assertIn("task failed on the cluster: RuntimeError: worker gone", r["error"])
            self.assertTrue(math.isnan(r["accuracy"]))

    def test_bad_grid_is_an_error_naming_the_key(self):
        bad = os.path.join(self.dir.name, "bad.yaml")
        with open(bad, "w") as f:
            f.write("scenarios: [urban]\nseed: 3\n")
        run = subprocess.run([sys.executable, "-m", "freespace.sweep", bad], capture_output=True,
                             text=True)
        self.assertEqual(run.returncode, 2)
        self.assertIn("unknown key(s) ['seed']", run.stderr)
        with open(bad, "w") as f:
            f.write("scenarios: [urban]\ngrid: {polygon.margin_cels: [1]}\n")
        run = subprocess.run([sys.executable, "-m", "freespace.sweep", bad], capture_output=True,
                             text=True)
        self.assertEqual(run.returncode, 2)
        self.assertIn("unknown field 'polygon.margin_cels'", run.stderr)


class GridFileTest(unittest.TestCase):
    """What a grid file may not do silently: a seed twice or a range without its end, a grid
    on the threads --threads-per-task sets, a fraction of a scan; and a sensor_model field is
    not the sensor (the drive's scanner stays the engine's sensor)."""

    def grid(self, text):
        with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
            f.write(text)
        self.addCleanup(os.unlink, f.name)
        return sweep.load_grid(f.name)

    def test_seeds_are_each_given_once_and_ranges_have_an_end(self):
        self.assertEqual(sweep.parse_seeds("1-3,7"), [1, 2, 3, 7])
        self.assertEqual(len(sweep.parse_seeds("1-100000")), 100000)  # at once, not quadratic
        for bad in ("1-", "1-2,2", "1-5,5-10", [1, 1], [1, True], "a", "007"):
            with self.assertRaises(sweep.GridError, msg=repr(bad)):
                sweep.parse_seeds(bad)

    def test_values_the_sweep_cannot_mean_are_errors(self):
        for text in ("scenarios: [urban]\nduration_s: abc\n",
                     "scenarios: [urban]\nduration_s: -1\n",
                     "scenarios: [urban]\nseeds: -3\n",
                     "scenarios: [urban]\ngrid: [1, 2]\n",
                     "scenarios: [urban]\noverrides: [1, 2]\n",
                     "scenarios: [urban]\ngrid: []\n",
                     "scenarios: [urban]\ngrid: {polygon.margin_cells: [1, 1.0]}\n",
                     "scenarios: [urban]\ngrid: {polygon.margin_cells: [1, 1]}\n"):
            with self.assertRaises(sweep.GridError, msg=text) as caught:
                self.grid(text)
            key = text.split("\n")[1].split(":")[0]
            self.assertIn(key, str(caught.exception))

    def test_sweep_json_has_no_nan(self):
        self.assertEqual(sweep._json_safe({"a": [math.nan, 1.0, math.inf], "b": "x"}),
                         {"a": [None, 1.0, None], "b": "x"})

    def test_threads_and_fractional_scans_are_errors(self):
        for text in ("scenarios: [urban]\ngrid: {backend.threads: [1, 2]}\n",
                     "scenarios: [urban]\noverrides: {backend: {threads: 2}}\n",
                     "scenarios: [urban]\ngrid: {backend: [{threads: 1}, {threads: 2}]}\n",
                     "logs: [{log: x.clf, max_scans: 2.9}]\n",
                     "logs: [{log: x.clf, max_scans: -1}]\n"):
            with self.assertRaises(sweep.GridError, msg=text):
                self.grid(text)

    def test_a_sensor_model_field_keeps_the_drives_sensor(self):
        cases = sweep.make_cases(self.grid(
            "scenarios: [urban]\nduration_s: 1\ngrid: {sensor_model.p_free: [0.4]}\n"))
        self.assertFalse(cases[0]["keep_sensor"])
        cases = sweep.make_cases(self.grid(
            "scenarios: [urban]\nduration_s: 1\ngrid: {sensor.mount_x_m: [3.7]}\n"))
        self.assertTrue(cases[0]["keep_sensor"])


if __name__ == "__main__":
    unittest.main()
