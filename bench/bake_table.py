#!/usr/bin/env python3
"""Turns `bench_bake --benchmark_format=json` output into the README's markdown table.

    build/bench/bench_bake --benchmark_format=json > bake.json && python3 bench/bake_table.py bake.json
"""
import json
import sys

data = json.load(open(sys.argv[1]))
ctx = data["context"]
print(f"Machine: {ctx.get('num_cpus')} x {ctx.get('mhz_per_cpu')} MHz, {ctx.get('date')}\n")
print("| model | map | resolution | samples/texel | threads | time (ms) | Msamples/s | error (bound) | value-weighted RMS | uniform RMS | max error |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for b in data["benchmarks"]:
    name = b["name"]
    if not name.startswith("BakeMap/"):
        continue
    model, kind, n, spt, threads = name.split("/")[1:6]
    label = b.get("label", "")
    print(f"| {label.split()[0]} | {label.split()[1]} | {n} | {spt} | {threads} | {b['real_time']:.1f} | "
          f"{b['samples/s'] / 1e6:.0f} | {b['error']:.2e} | {b['highlight_rms']:.2e} | {b['rms_err']:.2e} | {b['max_err']:.2e} |")
for b in data["benchmarks"]:
    if b["name"].startswith("Target"):
        threads = f", {b['name'].split('/')[1]} threads" if b["name"].startswith("TargetBrdfbake/") else ""
        error = f", error (bound) {b['error']:.2e}" if "error" in b else ""
        print(f"\n{b['name'].split('/')[0]}{threads}: {b['real_time']:.0f} ms wall, {b['cpu_time']:.0f} ms CPU{error}", end="")
print()
