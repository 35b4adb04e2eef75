"""freespace.Estimator from numpy: points in every accepted form, the result, the map arrays,
errors as exceptions, and the same polygons as `freespace run` writes for a recorded log."""

import json
import os
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import numpy as np

import freespace as fs
from common import cli, data_dir, source_dir


def drive(seconds=2.0, scenario="urban", seed=3):
    """The scans of a short simulated drive and the config with its sensor."""
    sim = fs.Simulation(scenario, seed, duration_s=seconds)
    config = fs.Config().with_overrides({"sensor": sim.sensor})
    return config, list(sim)


class EstimatorTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.config, cls.scans = drive()

    def test_scan_array_and_structured_points_give_the_same_results(self):
        by_scan, by_array, by_struct = (fs.Estimator(self.config) for _ in range(3))
        for scan in self.scans:
            a = by_scan.process(scan)
            points = scan.points
            b = by_array.process(points, scan.pose, scan.t)
            s = np.zeros(len(points), dtype=fs.POINT_DTYPE)
            for k, name in enumerate(("layer", "angle", "range", "echo")):
                s[name] = points[:, k]
            c = by_struct.process(s, scan.pose, scan.t)
            for r in (b, c):
                self.assertEqual(r.status, a.status)
                np.testing.assert_array_equal(r.polygon, a.polygon)
                np.testing.assert_array_equal(r.edge_cells, a.edge_cells)
        np.testing.assert_array_equal(by_array.map().log_odds, by_scan.map().log_odds)

    def test_result_fields(self):
        est = fs.Estimator(self.config)
        self.assertEqual(est.backend_name, "tbb")
        for i, scan in enumerate(self.scans):
            r = est.process(scan)
            self.assertEqual(r.scan_index, i)
            self.assertEqual(r.timestamp, scan.t)
            self.assertEqual(r.status, "ok")
            # The simulated scanner sweeps (sensor.sweep_s): every scan after the first is
            # placed from the sensor's motion.
            self.assertEqual(r.sweep_corrected, i > 0)
            self.assertEqual(r.stats["points"], len(scan))
            self.assertGreater(r.stats["kept"], 0)
            self.assertGreaterEqual(r.times["total_us"], r.times["polygon_us"])
            self.assertGreater(est.last_call_us, 0.0)
            if r.polygon_status == "ok":
                self.assertEqual(r.polygon.shape[1], 2)
                self.assertEqual(r.polygon.dtype, np.float64)
                self.assertTrue(3 <= len(r.polygon) <= 32)
                # Counter-clockwise: positive shoelace area.
                x, y = r.polygon[:, 0], r.polygon[:, 1]
                self.assertGreater(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y), 0)
        self.assertEqual(r.polygon_status, "ok")

    def test_map_arrays(self):
        est = fs.Estimator(self.config)
        for scan in self.scans:
            est.process(scan)
        m = est.map()
        self.assertEqual((m.height, m.width), (300, 300))
        self.assertEqual(m.log_odds.shape, (300, 300))
        self.assertEqual(m.log_odds.dtype, np.int16)
        self.assertEqual(m.free.dtype, np.uint8)
        self.assertFalse(m.log_odds.flags.writeable)
        self.assertFalse(m.log_odds.flags.owndata)  # a view of the estimator's map
        with self.assertRaises(ValueError):
            m.log_odds[0, 0] = 1
        self.assertTrue(set(np.unique(m.free)) <= {0, 1})
        self.assertGreater(int(m.free.sum()), 1000)
        self.assertGreater(int((m.log_odds > 0).sum()), 100)
        occ = m.occupancy
        self.assertEqual(occ.dtype, np.int8)
        np.testing.assert_array_equal(occ == -1, m.log_odds == 0)
        self.assertTrue(np.all(occ[m.log_odds > 0] > 50))
        self.assertTrue(np.all((occ[m.log_odds < 0] < 50) & (occ[m.log_odds < 0] >= 0)))
        p = 1.0 / (1.0 + np.exp(-m.log_odds.astype(float) / 256.0))
        known = m.log_odds != 0
        np.testing.assert_array_equal(occ[known], np.round(100 * p[known]).astype(np.int8))
        free_cells = m.free == 1
        self.assertTrue(np.all(m.log_odds[free_cells] < 0))  # free needs p < 0.5
        c = est.map(copy=True)
        self.assertTrue(c.log_odds.flags.owndata)
        np.testing.assert_array_equal(c.log_odds, m.log_odds)
        np.testing.assert_array_equal(c.free, m.free)
        est.reset()
        self.assertEqual(int(np.count_nonzero(est.map().log_odds)), 0)
        self.assertGreater(int(np.count_nonzero(c.log_odds)), 0)  # the copy kept its cells

    def test_bad_input_raises_with_the_reason(self):
        est = fs.Estimator(self.config)
        pts = self.scans[0].points
        with self.assertRaisesRegex(ValueError, r"\(n, 4\)"):
            est.process(pts[:, :3], (0, 0, 0), 0.0)
        bad = pts.copy()
        bad[3, 0] = 1.5
        with self.assertRaisesRegex(ValueError, r"points\[3\]: layer = 1.5"):
            est.process(bad, (0, 0, 0), 0.0)
        bad = pts.copy()
        bad[7, 3] = 2
        with self.assertRaisesRegex(ValueError, r"points\[7\]: echo = 2"):
            est.process(bad, (0, 0, 0), 0.0)
        with self.assertRaisesRegex(ValueError, r"pose: must be \(x m, y m, yaw rad\)"):
            est.process(pts, (0, 0), 0.0)
        s = np.zeros(3, dtype=[("layer", "u1"), ("angle", "f4"), ("range", "f4")])
        with self.assertRaisesRegex(ValueError, r"without 'echo'"):
            est.process(s, (0, 0, 0), 0.0)
        # Bad scan content is the engine's to judge: a result, not an exception.
        est.process(pts, (0, 0, 0), 10.0)  # 10 s later than the next: beyond the jitter
        r = est.process(pts, (0, 0, 0), 0.0)
        self.assertEqual(r.status, "rejected")
        self.assertEqual(r.reject_reason, "timestamp_not_increasing")
        self.assertIn("timestamp", r.message)

    def test_backend_errors_carry_the_message(self):
        c = fs.Config.from_dict({"backend.kind": "opencl", "backend.opencl_platform": "no-such"})
        self.assertIsInstance(fs.opencl_compiled_in, bool)
        # A build without the OpenCL backend (e.g. the sanitizer build) says so instead of
        # looking for the platform.
        cause = "no-such" if fs.opencl_compiled_in else "has no OpenCL backend"
        with self.assertRaisesRegex(fs.BackendError, cause):
            fs.Estimator(c)

    def seen_inside(self, call):
        """Whether the main thread saw a worker thread inside call(points, pose, t). With a
        switch interval of 100 s the interpreter never takes the GIL from a thread between
        bytecodes: the main thread runs while the worker is inside only if call lets go of
        the GIL."""
        state = {"in_call": False, "seen": False}
        arrays = [(s.points, s.pose, s.t) for s in self.scans]

        def work():
            for points, pose, t in arrays:
                state["in_call"] = True
                call(points, pose, t)
                state["in_call"] = False

        old = sys.getswitchinterval()
        sys.setswitchinterval(100.0)
        try:
            worker = threading.Thread(target=work)
            worker.start()
            while worker.is_alive():
                state["seen"] |= state["in_call"]
                time.sleep(1e-4)  # gives the worker the GIL
            worker.join()
        finally:
            sys.setswitchinterval(old)
        return state["seen"]

    def test_process_releases_the_gil(self):
        self.assertTrue(self.seen_inside(fs.Estimator(self.config).process))
        self.assertFalse(self.seen_inside(fs.Scan))  # the control: Scan() holds the GIL

    def test_estimators_on_threads_match_one_by_one(self):
        ref = fs.Estimator(self.config)
        expected = [ref.process(s).polygon for s in self.scans]
        got = [[], []]

        def work(k):
            est = fs.Estimator(self.config)
            got[k] = [est.process(s).polygon for s in self.scans]

        threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for k in range(2):
            self.assertEqual(len(got[k]), len(expected))
            for a, b in zip(got[k], expected):
                np.testing.assert_array_equal(a, b)

    def test_rig_cycle(self):
        # Two sensors at one mount, each seeing the same wall: each scan of the cycle is fused
        # once, so every cell holds twice what one scan gives it.
        config = fs.Config.from_yaml("sensors:\n  - name: a\n  - name: b\n")
        angles = np.radians(np.arange(-30.0, 30.25, 0.25))
        points = np.column_stack([np.zeros_like(angles), angles, 12.0 / np.cos(angles),
                                  np.ones_like(angles)])
        a = fs.Scan(points, (0.0, 0.0, 0.0), 0.0, sensor=0)
        b = fs.Scan(points, (0.0, 0.0, 0.0), 0.0, sensor=1)
        self.assertEqual(b.sensor, 1)
        rig = fs.Estimator(config)
        r = rig.process_cycle([b, a])
        self.assertEqual(r.status, "ok")
        one = fs.Estimator(fs.Config())
        one.process(a)
        np.testing.assert_array_equal(rig.map().log_odds, 2 * one.map().log_odds.astype(np.int32))
        self.assertEqual(rig.process_cycle([a, a]).reject_reason, "bad_cycle")


class SameAsCliTest(unittest.TestCase):
    """Every polygon of a recorded log equals the one `freespace run` writes."""

    def test_intel_log(self):
        log = os.path.join(data_dir(), "carmen", "intel.clf")
        config_path = os.path.join(source_dir(), "configs", "indoor.yaml")
        scans = 150
        with tempfile.TemporaryDirectory() as out:
            subprocess.run(
                [cli(), "run", "--log", log, "--config", config_path, "--out", out,
                 "--max-scans", str(scans), "--quiet"],
                check=True, capture_output=True)
            with open(os.path.join(out, "polygons.jsonl")) as f:
                lines = [json.loads(line) for line in f]
        reader = fs.open_log(log)
        config = fs.Config.from_yaml_file(config_path).with_overrides({"sensor": reader.sensor})
        est = fs.Estimator(config)
        results = []
        for scan in reader:
            r = est.process(scan)
            if r.status != "rejected":
                results.append(r)
            if r.scan_index + 1 == scans:
                break
        self.assertEqual(len(results), len(lines))
        for r, line in zip(results, lines):
            self.assertEqual(r.polygon_status, line["polygon_status"])
            self.assertAlmostEqual(r.timestamp, line["t_s"], places=5)
            want = np.array(line["polygon"], dtype=float).reshape(-1, 2)
            if len(want):  # the file's ring is closed: its first vertex repeated at the end
                np.testing.assert_array_equal(want[0], want[-1])
                want = want[:-1]
            self.assertEqual(r.polygon.shape, want.shape)
            np.testing.assert_allclose(r.polygon, want, rtol=0, atol=5.1e-5)


if __name__ == "__main__":
    unittest.main()
