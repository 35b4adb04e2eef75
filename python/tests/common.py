"""What the Python tests share: the paths CTest passes (tests/CMakeLists.txt) and small helpers."""

import os


def env_path(name):
    """The path in environment variable `name`; a test without it fails and says why."""
    value = os.environ.get(name)
    if not value:
        raise RuntimeError(
            f"{name} is not set: run the Python tests through CTest (tests/CMakeLists.txt)"
        )
    return value


def source_dir():
    return env_path("FREESPACE_SOURCE_DIR")


def data_dir():
    return env_path("FREESPACE_DATA_DIR")


def cli():
    return env_path("FREESPACE_CLI")
