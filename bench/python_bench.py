#!/usr/bin/env python3
"""Times the Python module's vectorised calls (docs/python.md, "Speed"): Map.sample and Fit.evaluate on
10^6 directions, and a live matcap preview (256^2, max_error 0.05) on a prepared Environment, medians
of 5 runs, with the machine and the date. Not a test.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_bench.py [--count N]
"""
import argparse
import datetime
import os
import pathlib
import platform
import statistics
import tempfile
import time

import numpy as np

import brdfbake

SOURCE = pathlib.Path(__file__).resolve().parents[1]


def median_seconds(call, runs=5):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times), max(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=1_000_000)
    args = parser.parse_args()
    print(f"{platform.node()}: {os.cpu_count()} CPUs, {platform.processor() or platform.machine()}, "
          f"load {os.getloadavg()[0]:.1f}, {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC")
    rng = np.random.default_rng(0)
    dirs = rng.normal(size=(args.count, 3))
    with tempfile.TemporaryDirectory() as folder:
        for parameterization in ("sphere", "paraboloid", "cube", "latlong"):
            spec = {"maps": [{"output": "m.exr", "parameterization": parameterization, "resolution": 256,
                              "samples_per_texel": 4, "material": {"model": "phong", "exponent": 50},
                              "lights": [{"direction": [1, 1, 1]}]}]}
            brdfbake.bake(spec, out_dir=folder, progress=False)
            m = brdfbake.read_map(os.path.join(folder, "m.exr"))
            median, low, high = median_seconds(lambda: m.sample(dirs))
            print(f"Map.sample {parameterization:10s} {args.count} directions: {median:.3f} s ({low:.3f} to {high:.3f})")
            os.remove(os.path.join(folder, "m.exr"))
    fit = brdfbake.fit(SOURCE / "data_samples" / "tables" / "synthetic_two_lobes.astm", held_out=False, progress=False)
    wo = rng.normal(size=(args.count, 3))
    median, low, high = median_seconds(lambda: fit.evaluate(dirs, wo))
    print(f"Fit.evaluate ({fit.model['lobes']} lobes) {args.count} pairs: {median:.3f} s ({low:.3f} to {high:.3f})")
    environment = brdfbake.Environment(SOURCE / "data_samples" / "environments" / "sky_latlong.exr")
    material = SOURCE / "data_samples" / "materials" / "copper.json"
    median, low, high = median_seconds(lambda: brdfbake.matcap(material, environment, 256, max_error=0.05))
    print(f"matcap copper 256^2 at 5 % (prepared Environment): {median * 1e3:.1f} ms ({low * 1e3:.1f} to {high * 1e3:.1f})")


if __name__ == "__main__":
    main()
