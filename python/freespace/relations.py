"""How far a log's poses err against reference relations, before and after the engine's
heading correction (alignment.scan_match).

A relations file (the Freiburg SLAM evaluation's format, e.g. ../shared/data/carmen/
aces.relations) holds one line per pair of scan times: `t1 t2 x y z roll pitch yaw`, the true
pose at t2 in the frame of the pose at t1. `score_relations` runs the estimator over the log and
compares the relative motion between the two scans three ways: the relation, the log's odometry
poses, and the odometry corrected by the engine (`Result.pose_correction`). Errors are reported
separately for the relations shorter and longer than `long_s` seconds: the short ones measure
the odometry's local error, the long ones (the robot back where it was minutes before) the drift
the correction is there to hold.

    /usr/bin/python3 -m freespace.relations LOG RELATIONS --config configs/indoor.yaml \\
        --set alignment.scan_match=true --set alignment.heading_drift_dps=1
"""

import argparse
import json
import math
import sys

import numpy as np
import yaml

from . import Config, Estimator, InputError, open_log

TIME_TOLERANCE_S = 1e-3


def read_relations(path):
    """The relations as an (n, 5) array of t1, t2, x, y, yaw. Raises InputError naming the line
    that is not eight finite numbers."""
    rows = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            fields = line.split()
            if not fields or fields[0].startswith("#"):
                continue
            try:
                values = [float(v) for v in fields]
            except ValueError:
                values = []
            if len(values) != 8 or not all(math.isfinite(v) for v in values):
                raise InputError(
                    f"{path}:{number}: expected t1 t2 x y z roll pitch yaw: {line.strip()}")
            rows.append([values[0], values[1], values[2], values[3], values[7]])
    if not rows:
        raise InputError(f"{path}: no relations")
    return np.array(rows)


def _scan_at(times, wanted, relations_path, log_path):
    """The index of the scan nearest each wanted time (the log's times in any order). Raises
    InputError when none lies within TIME_TOLERANCE_S."""
    order = np.argsort(times, kind="stable")
    sorted_times = times[order]
    right = np.clip(np.searchsorted(sorted_times, wanted), 0, len(times) - 1)
    left = np.clip(right - 1, 0, len(times) - 1)
    nearer = np.where(np.abs(sorted_times[left] - wanted) <= np.abs(sorted_times[right] - wanted),
                      left, right)
    missing = np.abs(sorted_times[nearer] - wanted) > TIME_TOLERANCE_S
    if missing.any():
        raise InputError(
            f"{relations_path}: no scan of {log_path} at t = {wanted[np.argmax(missing)]:.6f}")
    return order[nearer]


def _relative(a, b):
    """Pose b in the frame of pose a, both (x, y, yaw) arrays of shape (n, 3)."""
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    yaw = np.remainder(b[:, 2] - a[:, 2] + math.pi, 2 * math.pi) - math.pi
    return np.stack([c * dx + s * dy, -s * dx + c * dy, yaw], axis=1)


def _compose(a, b):
    """a o b for (n, 3) pose arrays."""
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    return np.stack([a[:, 0] + c * b[:, 0] - s * b[:, 1], a[:, 1] + s * b[:, 0] + c * b[:, 1],
                     a[:, 2] + b[:, 2]], axis=1)


def _errors(poses, i, j, relations):
    motion = _relative(poses[i], poses[j])
    yaw = np.abs(np.remainder(motion[:, 2] - relations[:, 4] + math.pi, 2 * math.pi) - math.pi)
    shift = np.hypot(motion[:, 0] - relations[:, 2], motion[:, 1] - relations[:, 3])
    return np.degrees(yaw), shift


def _summary(yaw_deg, shift_m):
    if len(yaw_deg) == 0:
        return {"relations": 0}
    return {"relations": int(len(yaw_deg)),
            "yaw_deg_mean": float(yaw_deg.mean()), "yaw_deg_median": float(np.median(yaw_deg)),
            "shift_m_mean": float(shift_m.mean()), "shift_m_median": float(np.median(shift_m))}


def score_relations(log_path, relations_path, config, long_s=10.0, keep_sensor=False):
    """Runs `config` over the log, with the sensor the log implies unless `keep_sensor`, and
    scores the odometry and the corrected poses against the relations, each at the scan nearest
    its time. Raises InputError when the relations file is malformed (before the log is run) or
    a relation names a time no scan of the log has."""
    relations = read_relations(relations_path)
    reader = open_log(log_path)
    if not keep_sensor:
        config = config.with_overrides({"sensor": reader.sensor})
    estimator = Estimator(config)
    times, odometry, correction, matched, rejected = [], [], [], 0, 0
    for scan in reader:
        result = estimator.process(scan)
        rejected += result.status == "rejected"
        matched += bool(result.pose_matched)
        times.append(scan.t)
        odometry.append(tuple(scan.pose))
        correction.append(tuple(result.pose_correction))
    if not times:
        raise InputError(f"{log_path}: no scans")
    times, odometry, correction = np.array(times), np.array(odometry), np.array(correction)
    index = [_scan_at(times, relations[:, column], relations_path, log_path) for column in (0, 1)]
    long = (relations[:, 1] - relations[:, 0]) >= long_s
    report = {"log": log_path, "relations_file": relations_path, "scans": int(len(times)),
              "rejected": int(rejected), "matched": int(matched), "long_s": long_s,
              "scan_match": bool(config.to_dict()["alignment"]["scan_match"]),
              "heading_drift_dps": float(config.to_dict()["alignment"]["heading_drift_dps"])}
    for name, poses in (("odometry", odometry), ("corrected", _compose(correction, odometry))):
        yaw, shift = _errors(poses, index[0], index[1], relations)
        report[name] = {"short": _summary(yaw[~long], shift[~long]),
                        "long": _summary(yaw[long], shift[long])}
    return report


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python3 -m freespace.relations",
        description="Score a log's odometry and the engine's corrected poses against relations.")
    parser.add_argument("log")
    parser.add_argument("relations")
    parser.add_argument("--config", help="YAML config (default: the engine's defaults)")
    parser.add_argument("--set", action="append", default=[], metavar="FIELD=VALUE",
                        help="a config override, e.g. alignment.scan_match=true (repeatable)")
    parser.add_argument("--long-s", type=float, default=10.0,
                        help="relations at least this long are the long ones (default 10 s)")
    args = parser.parse_args(argv)
    config = Config.from_yaml_file(args.config) if args.config else Config()
    keep_sensor = False
    if args.config:
        with open(args.config, encoding="utf-8") as f:
            keep_sensor = "sensor" in (yaml.safe_load(f) or {})
    for item in args.set:
        field, sep, value = item.partition("=")
        if not sep:
            parser.error(f"--set {item}: expected FIELD=VALUE")
        if field == "sensor" or field.startswith("sensor."):
            parser.error(f"--set {item}: the sensor comes from the log or the --config file")
        # The text as the engine's own --set reads it (010 is no octal 8, 'true' a bool only for
        # a boolean field).
        config = config.with_overrides({field: value})
    report = score_relations(args.log, args.relations, config, args.long_s, keep_sensor)
    print(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
