"""The readers, the simulator and the scorer from Python: a notebook's loop gives what
`freespace eval` computes, and evaluate_drive / seed_summary give `freespace eval --seeds`."""

import json
import math
import os
import subprocess
import tempfile
import unittest

import numpy as np

import freespace as fs
from common import cli, data_dir


def assert_same(test, a, b, path=""):
    """Equal JSON-like values, NaN equal to NaN."""
    if isinstance(a, dict):
        test.assertEqual(set(a), set(b), path)
        for k in a:
            assert_same(test, a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        test.assertEqual(len(a), len(b), path)
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(test, x, y, f"{path}[{i}]")
    elif isinstance(a, float) and math.isnan(a):
        test.assertTrue(isinstance(b, float) and math.isnan(b), f"{path}: {a} vs {b}")
    else:
        test.assertEqual(a, b, path)


class ReaderTest(unittest.TestCase):
    def test_carmen_log_iterates_scans(self):
        reader = fs.open_log(os.path.join(data_dir(), "carmen", "intel.clf"))
        self.assertEqual(reader.sensor["layers"], 1)
        last_t = -math.inf
        count = 0
        for scan in reader:
            self.assertIsInstance(scan, fs.Scan)
            pts = scan.points
            self.assertEqual(pts.shape, (len(scan), 4))
            self.assertTrue(np.all(pts[:, 0] == 0))
            self.assertTrue(set(np.unique(pts[:, 3])) <= {0.0, 1.0})
            self.assertGreaterEqual(scan.t, last_t - 1.0)
            last_t = scan.t
            count += 1
            if count == 50:
                break
        self.assertEqual(count, 50)
        self.assertGreater(reader.progress, 0.0)
        self.assertIsInstance(reader.issues(), list)

    def test_kitti_frame(self):
        reader = fs.open_log(os.path.join(data_dir(), "kitti", "kitti_00_000000.bin"))
        scans = list(reader)
        self.assertEqual(len(scans), 1)
        self.assertEqual(reader.sensor["layers"], 4)
        self.assertTrue(set(np.unique(scans[0].points[:, 0])) <= {0.0, 1.0, 2.0, 3.0})

    def test_missing_file_and_bad_format(self):
        with self.assertRaisesRegex(fs.InputError, "/no/such.clf"):
            fs.open_log("/no/such.clf")
        with self.assertRaisesRegex(ValueError, "format = 'xml'"):
            fs.open_log(os.path.join(data_dir(), "carmen", "intel.clf"), format="xml")


class DriveTest(unittest.TestCase):
    SECONDS = 3.0

    def test_notebook_loop_equals_evaluate_drive(self):
        config = fs.Config.from_dict({"polygon.shape": "inside", "polygon.margin_cells": 1})
        sim = fs.Simulation("parking", 2, duration_s=self.SECONDS)
        est = fs.Estimator(config.with_overrides({"sensor": sim.sensor}))
        scorer = fs.TruthScorer(sim.truth)
        metrics, times = fs.MetricsSeries(), fs.StageSeries()
        for scan in sim:
            r = est.process(scan)
            self.assertNotEqual(r.status, "rejected")
            times.add(r)
            m = scorer.score(est.map(), r)
            self.assertEqual(m.t, r.timestamp)
            self.assertTrue(0.0 <= m.accuracy <= 1.0)
            self.assertEqual(m.to_dict()["intrusion_m2"], m.intrusion_m2)
            metrics.add(m)
        self.assertEqual(len(metrics), len(sim))
        self.assertEqual(sim.truth.scans, len(sim))
        drive = fs.evaluate_drive(config, "parking", 2, duration_s=self.SECONDS)
        self.assertEqual((drive.scenario, drive.seed, drive.rejected), ("parking", 2, 0))
        self.assertEqual(drive.scans, len(metrics))
        assert_same(self, drive.metrics.summary(), metrics.summary())
        self.assertEqual(set(times.summary()), set(drive.times.summary()))

    def test_seed_summary_equals_freespace_eval_seeds(self):
        drives = [fs.evaluate_drive(fs.Config(), "urban", s, duration_s=self.SECONDS)
                  for s in (1, 2)]
        summary = fs.seed_summary(drives)
        self.assertEqual(summary[0]["seeds"], [1, 2])
        with tempfile.TemporaryDirectory() as out:
            subprocess.run(
                [cli(), "eval", "--seeds", "1-2", "--scenario", "urban", "--duration",
                 str(self.SECONDS), "--out", out, "--quiet"],
                check=True)
            with open(os.path.join(out, "seeds.json")) as f:
                written = json.load(f)["scenarios"]
        for key in ("per_seed", "mean", "worst", "pooled", "aims"):
            assert_same(self, summary[0][key], written[0][key], key)

    def test_truth_file_scores_a_written_drive(self):
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([cli(), "simulate", "--scenario", "highway", "--seed", "4",
                            "--duration", "2", "--out", out], check=True,
                           capture_output=True)
            truth = fs.read_truth(os.path.join(out, "truth.json"))
            reader = fs.open_log(os.path.join(out, "sim.fslog"))
            scans = list(reader)
        self.assertEqual((truth.scenario, truth.seed, truth.scans), ("highway", 4, len(scans)))
        est = fs.Estimator(fs.Config().with_overrides({"sensor": reader.sensor}))
        scorer = fs.TruthScorer(truth)
        series = fs.MetricsSeries()
        for scan in scans:
            r = est.process(scan)
            series.add(scorer.score(est.map(), r))
        self.assertEqual(len(series), len(scans))
        # The log holds the scans the simulation gave: the same scores as the drive in memory.
        drive = fs.evaluate_drive(fs.Config(), "highway", 4, duration_s=2)
        assert_same(self, series.summary(), drive.metrics.summary())

    def test_unknown_scenario(self):
        with self.assertRaisesRegex(ValueError, "nowhere"):
            fs.Simulation("nowhere")
        self.assertEqual(sorted(fs.scenario_names()), ["highway", "parking", "urban"])


if __name__ == "__main__":
    unittest.main()
