"""freespace.relations: a log's poses scored against relations (t1 t2 x y z roll pitch yaw)."""

import math
import os
import tempfile
import unittest

import numpy as np

import freespace as fs
from freespace import relations
from common import data_dir


def log_poses(path):
    times, poses = [], []
    for scan in fs.open_log(path):
        times.append(scan.t)
        poses.append(scan.pose)
    return np.array(times), np.array(poses)


def relation(a, b, ta, tb):
    """The line of a relation from pose a to pose b."""
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    yaw = math.remainder(b[2] - a[2], 2 * math.pi)
    return f"{ta:.6f} {tb:.6f} {c * dx + s * dy:.6f} {-s * dx + c * dy:.6f} 0 0 0 {yaw:.6f}\n"


class RelationsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.log = os.path.join(data_dir(), "carmen", "aces.clf")
        cls.times, cls.poses = log_poses(cls.log)
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def write(self, name, text):
        path = os.path.join(self.tmp.name, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return path

    def config(self, scan_match):
        return fs.Config.from_yaml_file(
            os.path.join(os.environ["FREESPACE_SOURCE_DIR"], "configs", "indoor.yaml")
        ).with_overrides({"alignment.scan_match": scan_match})

    def test_the_odometry_scored_against_its_own_motion_errs_nothing(self):
        n = len(self.times)
        pairs = [(i, i + 3) for i in range(0, n - 3, 7)] + [(5, n - 1), (10, n - 2)]
        text = "".join(relation(self.poses[i], self.poses[j], self.times[i], self.times[j])
                       for i, j in pairs)
        path = self.write("own.relations", text)
        off = relations.score_relations(self.log, path, self.config(False), long_s=20.0)
        self.assertEqual(off["scans"], n)
        self.assertEqual(off["rejected"], 0)
        self.assertEqual(off["odometry"]["short"]["relations"] + off["odometry"]["long"]["relations"],
                         len(pairs))
        self.assertGreater(off["odometry"]["long"]["relations"], 0)
        for part in ("short", "long"):
            self.assertLess(off["odometry"][part]["yaw_deg_mean"], 1e-3)
            self.assertLess(off["odometry"][part]["shift_m_mean"], 1e-5)
            # Without the correction the corrected poses are the odometry's.
            self.assertEqual(off["corrected"][part], off["odometry"][part])
        on = relations.score_relations(self.log, path, self.config(True), long_s=20.0)
        self.assertTrue(on["scan_match"])
        self.assertGreater(on["matched"], n // 2)
        # The correction turned the poses away from the odometry's own motion.
        self.assertGreater(on["corrected"]["long"]["yaw_deg_mean"], 1e-3)

    def test_a_time_no_scan_has_is_an_input_error(self):
        t = self.times[3] + 0.05
        path = self.write("off.relations", f"{self.times[1]:.6f} {t:.6f} 0 0 0 0 0 0\n")
        with self.assertRaisesRegex(fs.InputError, "no scan of"):
            relations.score_relations(self.log, path, self.config(False))

    def test_a_line_that_is_not_eight_numbers_is_an_input_error(self):
        path = self.write("bad.relations", "1.0 2.0 0 0 0 0 0 0\n1.0 2.0 x 0 0 0 0 0\n")
        with self.assertRaisesRegex(fs.InputError, "bad.relations:2"):
            relations.read_relations(path)
        path = self.write("nan.relations", "# t1 t2 ...\n\nnan 2.0 0 0 0 0 0 0\n")
        with self.assertRaisesRegex(fs.InputError, "nan.relations:3"):
            relations.score_relations(self.log, path, self.config(False))

    def test_each_time_takes_the_nearest_scan(self):
        times = np.array([3.0, 1.0, 2.0, 2.0005])
        wanted = np.array([1.0004, 2.0004, 1.9999, 3.0])
        self.assertEqual(list(relations._scan_at(times, wanted, "r", "l")), [1, 3, 2, 0])


if __name__ == "__main__":
    unittest.main()
