"""consumer_python: `cmake --install` puts the package into the interpreter's site-packages layout
under the prefix, and the installed module imports and works from elsewhere, loading the installed
libraries (not the build tree's)."""

import os
import pathlib
import subprocess
import sys

import pytest


def test_the_installed_module_imports_and_bakes(tmp_path):
    build, cmake = os.environ.get("BRDFBAKE_BUILD_DIR"), os.environ.get("BRDFBAKE_CMAKE")
    install_dir = os.environ.get("BRDFBAKE_PYTHON_INSTALL_DIR")
    if not (build and cmake and install_dir):
        pytest.skip("run by ctest (BRDFBAKE_BUILD_DIR, BRDFBAKE_CMAKE, BRDFBAKE_PYTHON_INSTALL_DIR)")
    prefix = tmp_path / "prefix"
    done = subprocess.run([cmake, "--install", build, "--prefix", prefix], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    site = pathlib.Path(install_dir) if os.path.isabs(install_dir) else prefix / install_dir
    assert (site / "brdfbake" / "__init__.py").exists() and (site / "brdfbake" / "_core.pyi").exists()
    script = """
import brdfbake, pathlib, sys
spec = {"maps": [{"output": "phong.exr", "parameterization": "sphere", "resolution": 256,
                  "material": {"model": "phong", "specular": [1, 1, 1], "exponent": 50},
                  "lights": [{"direction": "eye", "color": [1, 1, 1]}]}]}
brdfbake.bake(spec, out_dir="out", progress=False)
value = brdfbake.read_map("out/phong.exr").sample([0, 0, 1])
print(brdfbake.__file__)
print(value[0])
print("\\n".join(line.split()[-1] for line in open("/proc/self/maps") if "libbrdfbake_run" in line))
"""
    env = dict(os.environ, PYTHONPATH=str(site))
    env.pop("LD_LIBRARY_PATH", None)
    done = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert pathlib.Path(lines[0]).is_relative_to(site)
    # max(0, r_z)^50 at r = +z is 1; the four texels around the centre of a 256^2 map hold the lobe's
    # mean over footprints within 0.5 degrees of +z, where it is above cos(0.5 deg)^50 = 0.998.
    assert abs(float(lines[1]) - 1.0) < 0.01
    libraries = set(lines[2:])
    if os.environ.get("BRDFBAKE_SHARED_LIBS") == "ON":
        assert libraries
    assert all(pathlib.Path(lib).resolve().is_relative_to(prefix.resolve()) for lib in libraries)
