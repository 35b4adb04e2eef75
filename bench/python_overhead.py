#!/usr/bin/env python3
"""Per-scan overhead of Estimator.process from Python over the C++ call it wraps.

For every scan of simulated drives (300 x 300 cells at 0.2 m unless --map says otherwise) it
times the Python call (time.perf_counter_ns around estimator.process) and subtracts the time of
the C++ Estimator::Process inside it (estimator.last_call_us, a steady clock around that call
alone): what is left is the conversion of the points, the GIL hand-over, the copy of the
Result and pybind11's dispatch. Prints and writes (--out) the median and p90 over all scans.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py --passes 3
"""

import argparse
import json
import os
import platform
import statistics
import sys
import time

import freespace as fs


def cpu_name():
    """The model name of /proc/cpuinfo, else the platform's machine type."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.machine()


def quantile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, max(0, int(round(q * (len(v) - 1)))))]


def measure(est, scans, passes, form):
    overhead, cpp = [], []
    arrays = [(s.points, s.pose, s.t) for s in scans]
    for _ in range(passes):
        est.reset()
        for scan, (points, pose, t) in zip(scans, arrays):
            if form == "array":
                a = time.perf_counter_ns()
                est.process(points, pose, t)
                b = time.perf_counter_ns()
            else:
                a = time.perf_counter_ns()
                est.process(scan)
                b = time.perf_counter_ns()
            call = est.last_call_us
            overhead.append((b - a) / 1000.0 - call)
            cpp.append(call)
    return overhead, cpp


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scenario", default="urban")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--map", type=int, default=300, help="map cells per side (default 300)")
    p.add_argument("--passes", type=int, default=3, help="times each drive is replayed")
    p.add_argument("--threads", type=int, default=0, help="backend.threads (0: all cores)")
    p.add_argument("--out", help="write the numbers to this JSON file")
    args = p.parse_args()

    sim = fs.Simulation(args.scenario, args.seed)
    scans = list(sim)
    config = fs.Config().with_overrides(
        {"sensor": sim.sensor, "map.width_cells": args.map, "map.height_cells": args.map,
         "backend.threads": args.threads})
    est = fs.Estimator(config)
    measure(est, scans[:50], 1, "array")  # warm up: caches, the TBB arena, the allocator
    report = {"scenario": args.scenario, "seed": args.seed, "map_cells": args.map,
              "scans": len(scans), "passes": args.passes, "backend": est.backend_name,
              "points_per_scan_median": statistics.median(len(s) for s in scans),
              "python": sys.version.split()[0], "cpu": cpu_name(), "cores": os.cpu_count(),
              "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
              "load_average_start": os.getloadavg()[0]}
    for form in ("array", "scan"):
        overhead, cpp = measure(est, scans, args.passes, form)
        report[form] = {"overhead_us_median": statistics.median(overhead),
                        "overhead_us_p90": quantile(overhead, 0.9),
                        "cpp_process_us_median": statistics.median(cpp),
                        "samples": len(overhead)}
        print(f"process({'points, pose, t' if form == 'array' else 'scan'}): overhead median "
              f"{report[form]['overhead_us_median']:.2f} us, p90 "
              f"{report[form]['overhead_us_p90']:.2f} us over {len(overhead)} scans; C++ "
              f"Process median {report[form]['cpp_process_us_median']:.0f} us")
    report["load_average_end"] = os.getloadavg()[0]
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        with open(args.out, "w") as f:
            json.dump(report, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
