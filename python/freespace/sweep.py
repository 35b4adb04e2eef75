"""freespace-sweep: quality and timing over a grid of simulated drives, recorded logs and config
overrides, every case a task on a Dask cluster (docs/python.md, "Sweeps").

    freespace-sweep GRID.yaml --out out/sweep --workers 2
    freespace-sweep GRID.yaml --scheduler tcp://HOST:8786
    python3 -m freespace.sweep GRID.yaml ...

GRID.yaml (paths relative to the file):

    config: ../configs/scala.yaml   # the base config (default: the engine's defaults)
    overrides: {polygon.epsilon_m: 0.12}  # applied to the base for every case
    scenarios: [urban, highway, parking]
    seeds: 1-8                      # "1-8", "1,3,5-7" or a list of integers
    duration_s: 0                   # 0: each scenario's own
    odometry_noise: none            # none, typical or poor
    logs:                           # recorded or simulated logs (optional)
      - {log: ../../shared/data/carmen/intel.clf, config: ../configs/indoor.yaml, max_scans: 0}
      - {log: out/sim/sim.fslog, truth: out/sim/truth.json}
    grid:                           # every combination of these overrides is a setting
      polygon.margin_cells: [0, 1, 2]

Cases: every setting x (every scenario x seed, and every log). Each task builds its own
Estimator. A simulated drive keeps the config's sensor when the config sets one (a `sensor`
section or override), else takes its scanner's; a log takes the sensor it implies unless its own
config sets one. Writes OUT/cases.csv, OUT/aggregates.csv, OUT/sweep.json and,
with matplotlib, OUT/tradeoff.png.
"""

import argparse
import csv
import json
import math
import os
import signal
import socket
import sys
import threading
import time
import uuid

import freespace as fs
from freespace.sweep_grid import (GRID_KEYS, LOG_KEYS, GridError, load_grid,  # noqa: F401
                                   make_cases, parse_seeds)

# Per-drive means of the scores (docs/metrics.md), as seed_summary's per_seed rows hold them.
METRICS = ("accuracy", "false_free_rate", "intrusion_m2", "intrusion_moving_m2",
           "intrusion_mask_m2", "intrusion_geometric_m2", "coverage", "coverage_seen")
STAGES = ("preprocess", "align", "rasterize", "fuse", "classify", "mask", "insight", "polygon",
          "total")


def _row(case, drive_metrics, stage_us, scans, rejected, started, malformed=0):
    row = {"case": case["case"], "kind": case["kind"], "scenario": case.get("scenario", ""),
           "seed": case.get("seed", ""), "log": case.get("log", "")}
    row.update({k: v for k, v in case["setting"].items()})
    row.update({"scans": scans, "rejected": rejected, "malformed_lines": malformed})
    row.update({m: drive_metrics.get(m, math.nan) for m in METRICS})
    row.update({f"{s}_us": stage_us[s] for s in STAGES})
    row.update({"wall_s": time.perf_counter() - started,
                "worker": f"{socket.gethostname()}:{os.getpid()}", "error": ""})
    return row


def _run_sim(case, config, started):
    drive = fs.evaluate_drive(config, case["scenario"], case["seed"],
                              duration_s=case["duration_s"],
                              odometry_noise=case["odometry_noise"],
                              keep_sensor=case["keep_sensor"])
    summary = fs.seed_summary([drive])[0]
    return _row(case, summary["per_seed"][0], summary["stage_us"], drive.scans, drive.rejected,
                started)


def _run_log(case, config, started):
    reader = fs.open_log(case["log"])
    if not case["config_sets_sensor"]:
        config = config.with_overrides({"sensor": reader.sensor})
    est = fs.Estimator(config)
    scorer = fs.TruthScorer(fs.read_truth(case["truth"])) if case["truth"] else None
    metrics, times = fs.MetricsSeries(), fs.StageSeries()
    scans = rejected = 0
    for scan in reader:
        r = est.process(scan)
        scans += 1
        if r.status == "rejected":
            rejected += 1
        else:
            times.add(r)
            if scorer:
                metrics.add(scorer.score(est.map(), r))
        if case["max_scans"] and scans == case["max_scans"]:
            break
    # The reader's skipped lines so far, counted as `freespace run` counts them (not its notes).
    malformed = sum(not i.startswith("note: ") for i in reader.issues())
    means = {}
    if scorer:
        summary = metrics.summary()
        means = {m: summary[m]["mean"] for m in METRICS}
    stage_us = {s: times.quantile(s, 0.5) for s in STAGES}
    return _row(case, means, stage_us, scans, rejected, started, malformed)


def run_case(case):
    """One case, start to end, in this process: its own Estimator, a row of the table. An
    error is the row's `error` (the sweep reports it and exits 1), never a lost case."""
    started = time.perf_counter()
    try:
        config = fs.Config.from_yaml(case["config"], f"case {case['case']}")
        if case["kind"] == "sim":
            return _run_sim(case, config, started)
        return _run_log(case, config, started)
    except Exception as e:  # noqa: BLE001 (reported in the row)
        row = _row(case, {}, {s: math.nan for s in STAGES}, 0, 0, started)
        row["error"] = f"{type(e).__name__}: {e}"
        return row


def _median(values):
    """Nearest-rank median, as the engine's Quantile(values, 0.5)."""
    v = sorted(values)
    return v[min(len(v) - 1, math.ceil(0.5 * len(v)) - 1)] if v else 0.0


def _worse_is_larger(metric):
    return metric.startswith("intrusion") or metric == "false_free_rate"


def aggregate(rows):
    """Per setting and scenario, over seeds: the mean and the worst seed of each score (as
    seed_summary), the median of the drives' median stage times, and the mean task time."""
    groups = {}
    for row in rows:
        if row["kind"] != "sim" or row["error"]:
            continue
        key = (json.dumps(_setting_of(row), sort_keys=True), row["scenario"])
        groups.setdefault(key, []).append(row)
    out = []
    for (setting, scenario), members in groups.items():
        agg = {"scenario": scenario, **json.loads(setting), "seeds": len(members)}
        for m in METRICS:
            values = [r[m] for r in members]
            agg[f"{m}_mean"] = sum(values) / len(values)
            at = 0
            for i, v in enumerate(values):
                if (v > values[at]) if _worse_is_larger(m) else (v < values[at]):
                    at = i
            agg[f"{m}_worst"] = values[at]
            agg[f"{m}_worst_seed"] = members[at]["seed"]
        for s in STAGES:
            agg[f"{s}_us"] = _median([r[f"{s}_us"] for r in members])
        agg["wall_s_mean"] = sum(r["wall_s"] for r in members) / len(members)
        out.append(agg)
    return out


_ROW_FIXED = {"case", "kind", "scenario", "seed", "log", "scans", "rejected", "malformed_lines",
              "wall_s", "worker", "error"} | set(METRICS) | {f"{s}_us" for s in STAGES}


def _setting_of(row):
    return {k: v for k, v in row.items() if k not in _ROW_FIXED}


def write_whole(path, write, mode="w", newline=None):
    """Writes a file through write(f) under a temporary name, then renames it: the file is
    whole or absent (a failed write removes the temporary file and raises)."""
    temporary = path + ".part"
    try:
        with open(temporary, mode, newline=newline) as f:
            write(f)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.remove(temporary)
        raise


def _write_csv(path, rows):
    columns = []
    for row in rows:
        columns += [k for k in row if k not in columns]

    def write(f):
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)

    write_whole(path, write, newline="")


def _progress_line(row, done, total):
    what = f"{row['scenario']} seed {row['seed']}" if row["kind"] == "sim" else row["log"]
    if row["error"]:
        return f"freespace-sweep: [{done}/{total}] case {row['case']} ({what}): {row['error']}"
    skipped = (f", {row['malformed_lines']} malformed line(s) skipped"
               if row["malformed_lines"] else "")
    return (f"freespace-sweep: [{done}/{total}] case {row['case']} ({what}): {row['scans']} scans"
            f"{skipped}, accuracy {row['accuracy']:.4f}, intrusion {row['intrusion_m2']:.4f} m2, "
            f"coverage {row['coverage']:.4f}, {row['wall_s']:.1f} s")


def _error_row(case, error):
    row = _row(case, {}, {s: math.nan for s in STAGES}, 0, 0, time.perf_counter())
    row.update({"wall_s": math.nan, "worker": "", "error": error})
    return row


def _collect(futures, cases, quiet):
    """Each case's row as its task ends. A task that ends without a row (its worker lost, the
    cluster gone) gives a row whose error says so: no case is dropped. Ctrl-C stops waiting: the
    cases not ended by then are rows whose error says so, and the second value is True."""
    from dask.distributed import as_completed

    by_key = {f.key: c for f, c in zip(futures, cases)}
    rows = []
    try:
        for future in as_completed(futures):
            try:
                row = future.result()
            except Exception as e:  # noqa: BLE001 (reported in the row)
                row = _error_row(by_key[future.key],
                                 f"task failed on the cluster: {type(e).__name__}: {e}")
            rows.append(row)
            if not quiet:
                print(_progress_line(row, len(rows), len(cases)), flush=True)
    except KeyboardInterrupt:
        ended = {r["case"] for r in rows}
        rows += [_error_row(c, "not run to its end: the sweep was interrupted (SIGINT)")
                 for c in cases if c["case"] not in ended]
        return rows, True
    return rows, False


class ClusterError(Exception):
    """The scheduler could not be reached, or the local cluster did not start."""


def _close(client, cluster):
    if client is not None:
        client.close()
    if cluster is not None:
        cluster.close()


def task_keys(cases):
    """The cases' Dask keys, this sweep's own: another sweep on the scheduler never shares one."""
    sweep_id = uuid.uuid4().hex
    return [f"freespace-case-{sweep_id}-{c['case']}" for c in cases]


class _SigintHeld:
    """Holds Ctrl-C (SIGINT) back while the cluster starts or closes, so that neither is left
    half done; `caught` says whether one came. Outside the main thread, where no handler can be
    set, it holds nothing back."""

    def __enter__(self):
        self.caught = False
        self._previous = None
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._note)
        return self

    def _note(self, signum, frame):
        self.caught = True

    def __exit__(self, *exc):
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
        return False


def _start(workers, scheduler):
    """The client, and the local cluster (None with a scheduler); ClusterError when the
    scheduler cannot be reached or the cluster does not start."""
    from dask.distributed import Client, LocalCluster

    client = cluster = None
    try:
        if scheduler:
            client = Client(scheduler)
        else:
            # Every socket of the cluster on the loopback interface, the HTTP servers on free
            # ports.
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", dashboard_address="127.0.0.1:0",
                                   worker_dashboard_address="127.0.0.1:0")
            client = Client(cluster)
    except (OSError, TimeoutError, ValueError) as e:  # ValueError: a malformed address
        _close(client, cluster)
        where = f"cannot reach the scheduler {scheduler}" if scheduler else \
            "the local cluster did not start"
        raise ClusterError(f"{where}: {type(e).__name__}: {e}") from e
    return client, cluster


def run_sweep(cases, workers=2, scheduler=None, quiet=True):
    """Runs every case as a Dask task: on the cluster at `scheduler` (tcp://HOST:PORT), or on a
    local cluster of `workers` processes, one thread each, on the loopback interface. Returns
    the rows in case order and the timing {"startup_s", "run_s", "workers", "interrupted", ...};
    unless `quiet`, prints a line per case as it ends. The tasks' keys are this sweep's own, so
    that sweeps sharing a scheduler never share a task. Ctrl-C (SIGINT) while the cluster starts
    or closes waits for that to end: every case is a row, those not run saying so."""
    # Worker processes import freespace from where this one did.
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(fs.__file__)))
    paths = [package_parent] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    os.environ["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(paths))
    load_start = os.getloadavg()[0]
    started = ready = done = time.perf_counter()
    n_workers, futures, rows, interrupted = 0, [], None, False
    with _SigintHeld() as held:
        client, cluster = _start(workers, scheduler)
        if held.caught:
            _close(client, cluster)
    if held.caught:
        interrupted = True
        ready = done = time.perf_counter()
        rows = [_error_row(c, "not run: the sweep was interrupted (SIGINT) before it started")
                for c in cases]
    else:
        try:
            n_workers = len(client.scheduler_info()["workers"])
            ready = time.perf_counter()
            futures = client.map(run_case, cases, key=task_keys(cases), pure=False)
            rows, interrupted = _collect(futures, cases, quiet)
        except KeyboardInterrupt:  # outside _collect's wait: no row came back
            interrupted = True
            rows = [_error_row(c, "not run to its end: the sweep was interrupted (SIGINT)")
                    for c in cases]
        finally:
            done = time.perf_counter()
            with _SigintHeld():
                if interrupted and futures:
                    client.cancel(futures)
                _close(client, cluster)
    rows.sort(key=lambda r: r["case"])
    return rows, {"startup_s": ready - started, "run_s": done - ready, "workers": n_workers,
                  "interrupted": interrupted, "scheduler": scheduler or "local (127.0.0.1)",
                  "load_average_start": load_start, "load_average_end": os.getloadavg()[0]}


OUTPUTS = ("cases.csv", "aggregates.csv", "sweep.json", "tradeoff.png")


def prepare_out(out):
    """Makes the output folder before any case runs and removes an earlier sweep's files from
    it, so that none of them is left looking like this sweep's; the names of those removed."""
    os.makedirs(out, exist_ok=True)
    removed = []
    for name in OUTPUTS + tuple(n + ".part" for n in OUTPUTS):
        path = os.path.join(out, name)
        if os.path.isfile(path) or os.path.islink(path):
            os.remove(path)
            removed.append(name)
    return removed


def _json_safe(value):
    """NaN and infinities as null, as the engine's JSON writes them (JSON has no NaN)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    return value


def write_outputs(out, grid, rows, aggregates, timing):
    """The files written: cases.csv, aggregates.csv (with simulated drives), sweep.json."""
    written = ["cases.csv"]
    _write_csv(os.path.join(out, "cases.csv"), rows)
    if aggregates:
        _write_csv(os.path.join(out, "aggregates.csv"), aggregates)
        written.append("aggregates.csv")
    document = _json_safe({"definitions": "docs/metrics.md, docs/python.md", "grid": grid,
                           "timing": timing, "cases": rows, "aggregates": aggregates})
    write_whole(os.path.join(out, "sweep.json"),
                 lambda f: json.dump(document, f, indent=1, allow_nan=False))
    written.append("sweep.json")
    return written


def parse_args(argv):
    p = argparse.ArgumentParser(prog="freespace-sweep", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("grid", help="the grid file (YAML; see python3 -m pydoc freespace.sweep)")
    p.add_argument("--out", default="out/sweep", help="output folder (default out/sweep)")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                   help="worker processes of the local cluster (default: this machine's cores)")
    p.add_argument("--scheduler", help="tcp://HOST:PORT of an existing Dask scheduler")
    p.add_argument("--threads-per-task", type=int, default=1,
                   help="TBB threads of each task's estimator (backend.threads; default 1, so "
                        "that N workers keep N cores busy)")
    p.add_argument("--no-plot", action="store_true", help="write no tradeoff.png")
    p.add_argument("--quiet", action="store_true", help="print nothing but errors")
    args = p.parse_args(argv)
    if args.workers < 1 or args.threads_per_task < 0:
        p.error("--workers must be >= 1 and --threads-per-task >= 0")
    return args


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        grid = load_grid(args.grid)
        cases = make_cases(grid, args.threads_per_task)
        removed = prepare_out(args.out)
    except (GridError, fs.ConfigError, TypeError, OSError) as e:
        print(f"freespace-sweep: {e}", file=sys.stderr)
        return 2
    if not args.quiet:
        if removed:
            print(f"freespace-sweep: removed an earlier sweep's {', '.join(removed)} from "
                  f"{args.out}", flush=True)
        where = args.scheduler or f"a local cluster of {args.workers} workers"
        print(f"freespace-sweep: {len(cases)} cases on {where}", flush=True)
    try:
        rows, timing = run_sweep(cases, args.workers, args.scheduler, args.quiet)
    except ClusterError as e:
        print(f"freespace-sweep: {e}", file=sys.stderr)
        return 2
    aggregates = aggregate(rows)
    try:
        written = write_outputs(args.out, grid, rows, aggregates, timing)
    except OSError as e:
        whole = [n for n in OUTPUTS if os.path.isfile(os.path.join(args.out, n))]
        print(f"freespace-sweep: the {len(rows)} cases ran, but writing {args.out} failed: {e} "
              f"(written whole: {', '.join(whole) or 'none'})", file=sys.stderr)
        return 1
    if timing["interrupted"]:
        done = sum(not r["error"].startswith("not run") for r in rows)
        print(f"freespace-sweep: interrupted by SIGINT after {done} of {len(rows)} cases; wrote "
              f"{', '.join(os.path.join(args.out, w) for w in written)} with the rest marked "
              "as not run", file=sys.stderr)
        return 130
    failed = [r for r in rows if r["error"]]
    for r in failed:
        print(f"freespace-sweep: case {r['case']} failed: {r['error']}", file=sys.stderr)
    plot = None
    if not args.no_plot and aggregates:
        from freespace.sweep_plot import plot_tradeoff
        try:
            plot = plot_tradeoff(os.path.join(args.out, "tradeoff.png"), aggregates, grid)
        except OSError as e:
            print(f"freespace-sweep: wrote {args.out}/{', '.join(written)}, but not the plot: {e}",
                  file=sys.stderr)
            return 1
    if not args.quiet:
        if plot:
            plotted = ", " + os.path.basename(plot)
        elif not aggregates:
            plotted = " (no plot: no simulated drives)"
        else:
            plotted = " (no plot: " + ("--no-plot" if args.no_plot else
                                       "matplotlib is not installed") + ")"
        print(f"freespace-sweep: {len(rows)} cases in {timing['run_s']:.1f} s on "
              f"{timing['workers']} workers (cluster start {timing['startup_s']:.1f} s); wrote "
              f"{args.out}/{', '.join(written)}{plotted}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
