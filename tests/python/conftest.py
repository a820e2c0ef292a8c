"""Fixtures of the Python module's tests: the brdfbake tool to compare with, the sample data, and
the real measured tables of ../shared/data (tests that need them skip with a message without).

ctest sets PYTHONPATH to build/python and BRDFBAKE_CLI, BRDFBAKE_SOURCE_DIR, BRDFBAKE_SHARED_DIR
(tests/python/CMakeLists.txt); by hand:
    PYTHONPATH=build/python BRDFBAKE_CLI=build/cli/brdfbake /usr/bin/python3 -m pytest tests/python
"""

import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("BRDFBAKE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SHARED_DIR = pathlib.Path(os.environ.get("BRDFBAKE_SHARED_DIR", SOURCE_DIR.parent / "shared"))


@pytest.fixture(scope="session")
def source_dir() -> pathlib.Path:
    return SOURCE_DIR


@pytest.fixture(scope="session")
def cli() -> str:
    """The brdfbake tool, to compare the module's results with."""
    path = os.environ.get("BRDFBAKE_CLI", str(SOURCE_DIR / "build" / "cli" / "brdfbake"))
    if not os.access(path, os.X_OK):
        pytest.skip(f"the brdfbake tool is not built ({path}); set BRDFBAKE_CLI")
    return path


def run_cli(cli: str, *args, cwd=None) -> dict:
    """Runs `brdfbake ARGS --json` and returns what it printed."""
    done = subprocess.run([cli, *map(str, args), "--json"], cwd=cwd, capture_output=True, text=True)
    assert done.returncode == 0, f"brdfbake {' '.join(map(str, args))}: {done.stderr}"
    return json.loads(done.stdout)


@pytest.fixture(scope="session")
def cornell() -> pathlib.Path:
    """The folder of the real Cornell tables (../shared/data/cornell)."""
    folder = SHARED_DIR / "data" / "cornell"
    if not (folder / "garnet_red.astm").exists():
        pytest.skip(f"the real measured tables are not present ({folder})")
    return folder


def without_keys(value, keys):
    """`value` (JSON) without the given keys, nor timings (keys ending in "seconds", which differ from
    run to run), at any depth."""
    if isinstance(value, dict):
        return {k: without_keys(v, keys) for k, v in value.items() if k not in keys and not k.endswith("seconds")}
    if isinstance(value, list):
        return [without_keys(v, keys) for v in value]
    return value


PHONG_EYE = {
    "output": "phong_eye.exr",
    "parameterization": "sphere",
    "resolution": 256,
    "samples_per_texel": 16,
    "material": {"model": "phong", "specular": [1, 1, 1], "exponent": 50},
    "lights": [{"direction": "eye", "color": [1, 1, 1]}],
}
