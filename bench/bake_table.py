#!/usr/bin/env python3
"""Turns `bench_bake --benchmark_format=json` output into the README's markdown table: wall and CPU
time (the process's, every thread), samples per CPU second, errors, and the Target rows with the
baker's speed-up over the plain loop in CPU time. With --benchmark_repetitions it prints the
medians (and the spread of the CPU times over the runs).

    build/bench/bench_bake --benchmark_format=json > bake.json && python3 bench/bake_table.py bake.json
"""
import json
import sys

data = json.load(open(sys.argv[1]))
runs = {}  # name -> CPU times of the single runs
for b in data["benchmarks"]:
    if b.get("run_type") != "aggregate":
        runs.setdefault(b.get("run_name", b["name"]), []).append(b["cpu_time"])
if any(b.get("aggregate_name") == "median" for b in data["benchmarks"]):
    data["benchmarks"] = [b for b in data["benchmarks"] if b.get("aggregate_name") == "median"]
else:
    data["benchmarks"] = [b for b in data["benchmarks"] if b.get("run_type") != "aggregate"]


def cpu_range(b):
    times = runs.get(b.get("run_name", b["name"]), [])
    return f" ({min(times):.1f} to {max(times):.1f} over {len(times)} runs)" if len(times) > 1 else ""
ctx = data["context"]
print(f"Machine: {ctx.get('num_cpus')} x {ctx.get('mhz_per_cpu')} MHz, {ctx.get('date')}\n")
print("| model | map | resolution | samples/texel | threads | wall (ms) | CPU (ms) | Msamples per CPU s | error (bound) | value-weighted RMS | uniform RMS | max error |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")


def samples_per_cpu_second(b):
    # samples/s is per wall second (an iteration-invariant rate): samples per iteration = rate * wall time.
    return b["samples/s"] * b["real_time"] / b["cpu_time"]


for b in data["benchmarks"]:
    name = b["name"]
    if not name.startswith("BakeMap/"):
        continue
    model, kind, n, spt, threads = name.split("/")[1:6]
    label = b.get("label", "")
    print(f"| {label.split()[0]} | {label.split()[1]} | {n} | {spt} | {threads} | {b['real_time']:.1f} | {b['cpu_time']:.1f} | "
          f"{samples_per_cpu_second(b) / 1e6:.0f} | {b['error']:.2e} | {b['highlight_rms']:.2e} | {b['rms_err']:.2e} | {b['max_err']:.2e} |")
plain = None
for b in data["benchmarks"]:
    if b["name"].startswith("Target"):
        threads = f", {b['name'].split('/')[1]} threads" if b["name"].startswith("TargetBrdfbake/") else ""
        error = f", error (bound) {b['error']:.2e}" if "error" in b else ""
        ratio = ""
        if b["name"].startswith("TargetPlainLoop"):
            plain = b["cpu_time"]
        elif plain is not None:
            ratio = f", {plain / b['cpu_time']:.1f}x the plain loop in CPU time"
        print(f"\n{b['name'].split('/')[0]}{threads}: {b['real_time']:.0f} ms wall, {b['cpu_time']:.1f} ms CPU{cpu_range(b)}{error}{ratio}", end="")
print()
