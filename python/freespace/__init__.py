"""freespace: static free-space detection from laser scans on occupancy grid maps.

The engine (C++, docs/design.md) for Python: Config, Estimator (one process() call per scan,
numpy points in, the free-space polygon as a numpy array out, the map as numpy arrays), the
log readers (open_log), the scenario simulator (Simulation), the scorer (TruthScorer,
MetricsSeries, evaluate_drive, seed_summary) and `freespace-sweep` (freespace.sweep), which runs
grids of drives on a Dask cluster. docs/python.md is the guide.
"""

from ._freespace import (
    BackendError,
    Config,
    ConfigError,
    DriveEvaluation,
    Estimator,
    InputError,
    LogReader,
    Map,
    MetricsSeries,
    Result,
    Scan,
    ScanMetrics,
    Simulation,
    StageSeries,
    Truth,
    TruthScorer,
    evaluate_drive,
    open_log,
    opencl_compiled_in,
    read_truth,
    scenario_names,
    seed_summary,
)

import numpy as _np

# The dtype of a structured points array Estimator.process accepts besides an (n, 4) array.
POINT_DTYPE = _np.dtype(
    [("layer", _np.uint8), ("angle", _np.float32), ("range", _np.float32), ("echo", _np.uint8)]
)

__all__ = [
    "BackendError", "Config", "ConfigError", "DriveEvaluation", "Estimator", "InputError",
    "LogReader", "Map", "MetricsSeries", "POINT_DTYPE", "Result", "Scan", "ScanMetrics",
    "Simulation", "StageSeries", "Truth", "TruthScorer", "evaluate_drive", "open_log",
    "opencl_compiled_in", "read_truth", "scenario_names", "seed_summary",
]
