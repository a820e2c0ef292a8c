#!/usr/bin/env python3
"""Held-out error of lobe fits against their number of parameters and their fit time, per Cornell table
(docs/fitting.md, "Held-out error"). Runs `brdfbake fit --json` for each candidate model, reads the held-out
estimate the fit makes itself (fit.held_out: off-mirror 5-fold and each interior incident elevation held out,
as ratios to a per-channel Lambertian fit) and the fit's own time (a second run with --held-out off), writes
docs/images/fit_held_out.csv and draws docs/images/fit_held_out.png with gnuplot.

usage: scripts/fit_held_out_chart.py BRDFBAKE [SHARED_DATA_DIR] [--tables a.astm,b.astm] [--only LABEL] [--plot-only]
(--only "shared half_vector" reruns that candidate family and keeps the CSV's other rows)
(krylon_blue.brdf holds the numbers of krylon_blue.astm, so the default list leaves it out)
Standard library only. Spectral tables are fitted per wavelength; the per-channel method only on RGB tables
(its spectral fits take minutes per candidate)."""
import json, os, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
TABLES = ["garnet_red_RGB.astm", "krylon_blue_RGB.astm", "garnet_red.astm", "krylon_blue.astm"]


def candidates(table):
    out = []
    for kind in ("mirror", "lafortune", "half_vector"):
        for k in (1, 2, 3):
            out.append((f"shared {kind}", ["--method", "shared", "--kind", kind, "--lobes", str(k)], k))
    if "RGB" in table:
        for elevation, ks in (("constant", (1, 2)), ("varying", (1,))):
            for k in ks:
                out.append((f"per-channel {elevation}", ["--method", "per_channel", "--elevation", elevation, "--lobes", str(k)], k))
    return out


def run(exe, path, args, tmp):
    channels = "rgb" if "RGB" in os.path.basename(path) else "spectral"
    cmd = [exe, "fit", path, "--channels", channels, "--json", "--quiet", *args]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: {r.stderr.strip()[:300]}")
    return json.loads(r.stdout)


def parameters(fit):
    model = fit["channels"]
    lafortune = any("cxy" in lobe for lobe in model[0]["lobes"])
    fresnel = sum("fresnel" in lobe for lobe in model[0]["lobes"])  # half-vector lobes: C and C_F per channel
    shared = fit["fit"]["method"] == "shared"
    count = 1 if fit["model"]["elevation"] == "constant" else 3
    lobes = fit["model"]["lobes"]
    per_channel = 1 + fresnel + lobes * (1 if shared else 2 * count)
    return per_channel * len(model) + (lobes * (2 if lafortune else 1) if shared else 0)


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    exe = argv[1]
    data = argv[2] if len(argv) > 2 and not argv[2].startswith("--") else os.path.join(REPO, "..", "shared", "data", "cornell")
    tables = argv[argv.index("--tables") + 1].split(",") if "--tables" in argv else TABLES
    csv = os.path.join(REPO, "docs", "images", "fit_held_out.csv")
    rows = []
    header = "# table,candidate,lobes,parameters,fit_seconds_1_thread,kfold_ratio,ratio_30,ratio_50,ratio_70,score\n"
    if "--plot-only" in argv:
        plot(csv, tables, os.path.join(REPO, "docs", "images", "fit_held_out.png"))
        return 0
    only = argv[argv.index("--only") + 1] if "--only" in argv else None
    kept = []
    if only and os.path.exists(csv):
        kept = [line for line in open(csv) if not line.startswith("#") and line.split(",")[1] != only]
    with open(csv, "w") as f:
        f.write(header)
        f.writelines(kept)
    with tempfile.TemporaryDirectory() as tmp:
        for table in tables:
            path = os.path.join(data, table)
            for label, args, k in candidates(table):
                if only and label != only:
                    continue
                held = run(exe, path, [*args, "--held-out", "on"], tmp)["fit"]
                timed = run(exe, path, [*args, "--held-out", "off", "--threads", "1"], tmp)
                h = held["fit"]["held_out"]
                elevations = {round(e["elevation_deg"]): e["ratio_to_lambert"] for e in h["elevations"]}
                rows.append((table, label, k, parameters(held), timed["seconds"], h["kfold"]["ratio_to_lambert"],
                             elevations.get(30, 0), elevations.get(50, 0), elevations.get(70, 0), h["score"]))
                print(" ".join(str(x) for x in rows[-1]), flush=True)
                with open(csv, "a") as f:
                    f.write(",".join(str(x) for x in rows[-1]) + "\n")
    plot(csv, tables, os.path.join(REPO, "docs", "images", "fit_held_out.png"))
    return 0


def plot(csv, tables, png):
    lines = ["set terminal pngcairo noenhanced size 1400,%d font ',10'" % (330 * len(tables)), f"set output '{png}'",
             "set datafile separator ','", f"set multiplot layout {len(tables)},2",
             "set logscale x", "set grid", "set key outside right", "set yrange [0:*]"]
    for table in tables:
        for column, xlabel in ((4, "parameters (all channels)"), (5, "fit time, s (1 thread, no held-out estimate)")):
            lines.append(f"set title '{table}: held-out score (ratio to Lambert)'")
            lines.append("set ylabel 'mean of 5-fold and elevation ratios'")
            lines.append(f"set xlabel '{xlabel}'")
            series = []
            for label, style in (("shared mirror", "pt 7 lc 1"), ("shared lafortune", "pt 5 lc 2"),
                                 ("shared half_vector", "pt 13 lc 7"),
                                 ("per-channel constant", "pt 9 lc 3"), ("per-channel varying", "pt 11 lc 4")):
                series.append(f"'{csv}' using (strcol(1) eq '{table}' && strcol(2) eq '{label}' ? ${column} : 1/0):10 "
                              f"with linespoints {style} title '{label}'")
            lines.append("plot " + ", ".join(series))
    lines.append("unset multiplot")
    subprocess.run(["gnuplot"], input="\n".join(lines), text=True, check=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
