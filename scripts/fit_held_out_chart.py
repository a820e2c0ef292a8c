#!/usr/bin/env python3
"""Held-out error of lobe fits against their number of parameters and their fit time, per Cornell table
(docs/fitting.md, "Held-out error"). Runs `brdfbake fit --json` for each candidate model, reads the held-out
estimate the fit makes itself (fit.held_out: off-mirror 5-fold and each interior incident elevation held out,
as ratios to a per-channel Lambertian fit) and the fit's own time (a second run with --held-out off), writes
docs/images/fit_held_out.csv and draws docs/images/fit_held_out.png with gnuplot.

usage: scripts/fit_held_out_chart.py BRDFBAKE [SHARED_DATA_DIR] [--tables a.astm,/abs/b.brdf] [--only LABEL]
                                     [--per-channel] [--plot-only]
(--only "half_vector varying" reruns that candidate family and keeps the CSV's other rows; a table given
with an absolute path is read from there, so tables outside ../shared can be charted too)
(krylon_blue.brdf holds the numbers of krylon_blue.astm, so the default list leaves it out)
Standard library only. Spectral tables are fitted per wavelength; the per-channel method (--per-channel) only
on RGB tables (its spectral fits take minutes per candidate). The score is the fit's own: the worse of the
off-mirror 5-fold ratio and the ratio pooled over the held-out elevations."""
import json, os, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
TABLES = ["garnet_red.astm", "krylon_blue.astm"]
FAMILIES = [("mirror", "constant"), ("mirror", "varying"), ("half_vector", "constant"), ("half_vector", "varying"),
            ("mixed", "varying"), ("lafortune", "constant")]


def candidates(table, per_channel):
    out = []
    for kind, elevation in FAMILIES:
        for k in (1, 2, 3):
            out.append((f"{kind} {elevation}", ["--method", "shared", "--kind", kind, "--elevation", elevation,
                                                "--lobes", str(k)], k))
    out.append(("half_difference", ["--method", "shared", "--kind", "half_difference"], 0))  # no lobes
    if per_channel and "RGB" in table:
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
    """Free parameters over all channels (as fit.json's candidates count them)."""
    model = fit["channels"]
    if "half_difference" in fit["model"]:  # a half-difference table: K (D + 1) coefficients per channel
        return len(model[0]["half_difference"]) * len(model)
    lafortune = sum("cxy" in lobe for lobe in model[0]["lobes"])
    fresnel = sum("fresnel" in lobe for lobe in model[0]["lobes"])  # half-vector lobes: C and C_F per channel
    shared = fit["fit"]["method"] == "shared"
    varying = fit["model"]["elevation"] == "varying"
    lobes = fit["model"]["lobes"]
    if not shared:
        return (1 + lobes * 2 * (3 if varying else 1)) * len(model)
    # shared: per channel k_d, C (and C_F); shared per lobe n (c_xy; the varying offsets of ln n and ln g)
    return (1 + fresnel + lobes) * len(model) + lobes + lafortune + (4 * lobes if varying else 0)


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
        plot(csv, [os.path.basename(t) for t in tables], os.path.join(REPO, "docs", "images", "fit_held_out.png"))
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
            path = table if os.path.isabs(table) else os.path.join(data, table)
            for label, args, k in candidates(table, "--per-channel" in argv):
                if only and label != only:
                    continue
                held = run(exe, path, [*args, "--held-out", "on"], tmp)["fit"]
                timed = run(exe, path, [*args, "--held-out", "off", "--threads", "1"], tmp)
                h = held["fit"]["held_out"]
                elevations = {round(e["elevation_deg"]): e["ratio_to_lambert"] for e in h["elevations"]}
                rows.append((os.path.basename(table), label, k, parameters(held), timed["seconds"], h["kfold"]["ratio_to_lambert"],
                             elevations.get(30, 0), elevations.get(50, 0), elevations.get(70, 0), h["score"]))
                print(" ".join(str(x) for x in rows[-1]), flush=True)
                with open(csv, "a") as f:
                    f.write(",".join(str(x) for x in rows[-1]) + "\n")
    plot(csv, [os.path.basename(t) for t in tables], os.path.join(REPO, "docs", "images", "fit_held_out.png"))
    return 0


def plot(csv, tables, png):
    lines = ["set terminal pngcairo noenhanced size 1400,%d font ',10'" % (330 * len(tables)), f"set output '{png}'",
             "set datafile separator ','", f"set multiplot layout {len(tables)},2",
             "set logscale x", "set grid", "set key outside right", "set yrange [0:1.2]"]
    present = {}
    for line in open(csv):
        if not line.startswith("#"):
            present.setdefault(line.split(",")[0], set()).add(line.split(",")[1])
    for table in tables:
        for column, xlabel in ((4, "parameters (all channels)"), (5, "fit time, s (1 thread, no held-out estimate)")):
            lines.append(f"set title '{table}: held-out score (ratio to Lambert)'")
            lines.append("set ylabel 'worse of 5-fold and elevation ratios'")
            lines.append(f"set xlabel '{xlabel}'")
            series = []
            for label, style in (("mirror constant", "pt 6 lc 1"), ("mirror varying", "pt 7 lc 1"),
                                 ("half_vector constant", "pt 12 lc 7"), ("half_vector varying", "pt 13 lc 7"),
                                 ("mixed varying", "pt 9 lc 3"), ("lafortune constant", "pt 5 lc 2"),
                                 ("per-channel constant", "pt 8 lc 4"), ("per-channel varying", "pt 11 lc 4"),
                                 ("half_difference", "pt 3 ps 2 lc 8")):
                if label not in present.get(table, ()):
                    continue
                series.append(f"'{csv}' using (strcol(1) eq '{table}' && strcol(2) eq '{label}' ? ${column} : 1/0):10 "
                              f"with linespoints {style} title '{label}'")
            lines.append("plot " + ", ".join(series))
    lines.append("unset multiplot")
    subprocess.run(["gnuplot"], input="\n".join(lines), text=True, check=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
