"""The grid file of freespace-sweep (docs/python.md, "Sweeps"): reading and checking it, and
the cases it makes. See freespace.sweep for the file's keys."""

import collections
import itertools
import numbers
import os

import yaml

import freespace as fs

GRID_KEYS = {"config", "overrides", "scenarios", "seeds", "duration_s", "odometry_noise", "logs",
             "grid"}
LOG_KEYS = {"log", "config", "truth", "max_scans"}


class GridError(ValueError):
    """The grid file is missing, not YAML, or holds a key or value the sweep does not know."""


def _decimal(text):
    return text.isdigit() and text.isascii() and (text == "0" or not text.startswith("0"))


def parse_seeds(value):
    """"1-8", "1,3,5-7", an integer or a list of integers: the seeds in the order given."""
    if isinstance(value, int) and not isinstance(value, bool) and value >= 0:
        return [value]
    if isinstance(value, list) and not all(isinstance(v, int) and not isinstance(v, bool) and
                                           v >= 0 for v in value):
        raise GridError(f"seeds = {value!r}: give \"1-8\", \"1,3,5-7\" or a list of integers")
    if isinstance(value, str):
        seeds = []
        for part in value.split(","):
            first, dash, last = part.strip().partition("-")
            if not _decimal(first) or (dash and not _decimal(last)):
                raise GridError(f"seeds '{value}': '{part}' is not a seed or a range (decimal "
                                "digits, no leading zero)")
            a, b = int(first), int(last or first)
            if b < a:
                raise GridError(f"seeds '{value}': '{part}' is not a range")
            seeds.extend(range(a, b + 1))
        value = seeds
    if isinstance(value, list) and value:
        repeated = sorted(s for s, n in collections.Counter(value).items() if n > 1)
        if repeated:
            raise GridError(f"seeds: {repeated} given more than once (a mean over seeds would "
                            "count them twice)")
        return value
    raise GridError(f"seeds = {value!r}: give \"1-8\", \"1,3,5-7\" or a list of integers")


def load_grid(path):
    """The grid file as a dict of checked values (paths made absolute)."""
    try:
        with open(path) as f:
            grid = yaml.safe_load(f) or {}
    except OSError as e:
        raise GridError(f"{path}: cannot read: {e.strerror}") from e
    except yaml.YAMLError as e:
        raise GridError(f"{path}: not valid YAML: {e}") from e
    if not isinstance(grid, dict):
        raise GridError(f"{path}: the top level must be a mapping")
    unknown = set(grid) - GRID_KEYS
    if unknown:
        raise GridError(f"{path}: unknown key(s) {sorted(unknown)}; known: {sorted(GRID_KEYS)}")
    here = os.path.dirname(os.path.abspath(path))

    def resolve(p):
        return p if os.path.isabs(p) else os.path.normpath(os.path.join(here, p))

    for key in ("overrides", "grid"):
        if grid.get(key) is not None and not isinstance(grid[key], dict):
            raise GridError(f"{path}: {key} must be a mapping of config fields (field: value"
                            f"{', or field: [values]' if key == 'grid' else ''}); got "
                            f"{grid[key]!r}")
    duration = grid.get("duration_s", 0.0)
    if not isinstance(duration, numbers.Real) or isinstance(duration, bool) or \
            not 0.0 <= duration <= 3600.0:
        raise GridError(f"{path}: duration_s = {duration!r}: give seconds in [0, 3600] (0: each "
                        "scenario's own)")
    out = {
        "config": resolve(grid["config"]) if grid.get("config") else None,
        "overrides": dict(grid.get("overrides") or {}),
        "scenarios": list(grid.get("scenarios") or []),
        "seeds": parse_seeds(grid["seeds"]) if "seeds" in grid else [1],
        "duration_s": float(duration),
        "odometry_noise": str(grid.get("odometry_noise", "none")),
        "logs": [],
        "grid": dict(grid.get("grid") or {}),
    }
    for name in out["scenarios"]:
        if name not in fs.scenario_names():
            raise GridError(f"{path}: scenario '{name}': known are {fs.scenario_names()}")
    for entry in grid.get("logs") or []:
        entry = {"log": entry} if isinstance(entry, str) else dict(entry)
        if "log" not in entry or set(entry) - LOG_KEYS:
            raise GridError(f"{path}: a log entry needs 'log' and may have {sorted(LOG_KEYS)}; "
                            f"got {sorted(entry)}")
        for key in ("log", "config", "truth"):
            if entry.get(key):
                entry[key] = resolve(entry[key])
        out["logs"].append(entry)
    for key, values in out["grid"].items():
        if not isinstance(values, list) or not values:
            raise GridError(f"{path}: grid.{key} must be a non-empty list of values")
        repeated = [v for i, v in enumerate(values) if v in values[:i]]  # 1 and 1.0 alike
        if repeated:
            raise GridError(f"{path}: grid.{key}: {repeated[0]!r} given more than once (its "
                            "drives would count twice in a mean)")
    for key, value in list(out["grid"].items()) + list(out["overrides"].items()):
        values = value if isinstance(value, list) else [value]  # a grid axis: its values
        if key == "backend.threads" or (key == "backend" and any(
                isinstance(v, dict) and "threads" in v for v in values)):
            raise GridError(f"{path}: backend.threads is set by --threads-per-task, not the grid")
    for entry in out["logs"]:
        scans = entry.get("max_scans", 0)
        if not isinstance(scans, int) or isinstance(scans, bool) or scans < 0:
            raise GridError(f"{path}: log {entry['log']}: max_scans = {scans!r}: give an "
                            "integer >= 0 (0: all)")
    if not out["scenarios"] and not out["logs"]:
        raise GridError(f"{path}: no scenarios and no logs: nothing to run")
    return out


def make_cases(grid, threads_per_task=1):
    """Every case of the grid, in order: settings outermost, then scenarios x seeds, then logs.
    Each case carries its whole config as YAML, so that a task needs nothing else."""
    base = fs.Config.from_yaml_file(grid["config"]) if grid["config"] else fs.Config()
    base = base.with_overrides(grid["overrides"])
    keys = list(grid["grid"])
    settings = [dict(zip(keys, combo)) for combo in
                itertools.product(*(grid["grid"][k] for k in keys))]
    cases = []
    for setting in settings:
        threads = {"backend.threads": threads_per_task}
        config = base.with_overrides(setting).with_overrides(threads)
        common = {"setting": setting}
        # As freespace eval and demo: a config that sets the sensor keeps it, else the drive's
        # scanner gives it.
        keep_sensor = (_sets_sensor(grid["config"]) or
                       any(_names_sensor(k) for k in list(grid["overrides"]) + keys))
        for scenario in grid["scenarios"]:
            for seed in grid["seeds"]:
                cases.append(dict(common, kind="sim", scenario=scenario, seed=seed,
                                  duration_s=grid["duration_s"],
                                  odometry_noise=grid["odometry_noise"],
                                  keep_sensor=keep_sensor, config=config.to_yaml()))
        for entry in grid["logs"]:
            log_config = config
            if entry.get("config"):
                log_config = (fs.Config.from_yaml_file(entry["config"])
                              .with_overrides(grid["overrides"]).with_overrides(setting)
                              .with_overrides(threads))
            cases.append(dict(common, kind="log", log=entry["log"], truth=entry.get("truth"),
                              max_scans=int(entry.get("max_scans", 0)),
                              config_sets_sensor=_sets_sensor(entry.get("config")),
                              config=log_config.to_yaml()))
    for i, case in enumerate(cases):
        case["case"] = i
    return cases


def _names_sensor(key):
    """Whether an override key ("sensor", "sensor.mount_x_m") sets the sensor; sensor_model's
    fields do not."""
    return key in ("sensor", "sensors") or key.startswith("sensor.")


def _sets_sensor(path):
    if not path:
        return False
    with open(path) as f:
        sections = yaml.safe_load(f) or {}
    return "sensor" in sections or "sensors" in sections


