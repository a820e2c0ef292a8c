#!/usr/bin/python3
"""How predictable a Cornell table's held-out rows are without any lobe model: a yardstick for the fits.

Predicts each held-out row from the training rows by inverse-distance weighting of ln f over its k nearest
neighbours in Rusinkiewicz 1998's half/difference coordinates (theta_h, theta_d, phi_d; the table is taken
as isotropic and reciprocal, so phi_d is folded into [0, 90] degrees), scaled as 2 sqrt(theta_h), theta_d,
phi_d / 2 so that the highlight is resolved finer. The splits and the error are those of
`../shared/tools/fit_heldout_check.py` (imported from there): 5-fold over rows more than 5 degrees from the
mirror, and each of the 30, 50 and 70 degree incident elevations held out whole; cosine-weighted log error
as a ratio to a per-channel Lambertian fit. Where this predictor beats the lobe fits, the table is
predictable and the lobe family is what falls short (docs/fitting.md, issue 26's sixth part).

Each held-out elevation's figure is also given without its one sample nearest the mirror direction, with that
sample's measured and predicted values: a Cornell table samples a sharp highlight once per elevation, at an
offset from its peak that the table's angles do not resolve, and that one sample can hold most of the
split's error, for a fit and for Lambert alike (docs/fitting.md, issue 26's seventh part). With --brdfbake
the same figures are given for `brdfbake fit` (default arguments, or those after --).

A second predictor without lobes, a smooth table: ln f of each channel as a tensor product of 12 hat
functions of sqrt(theta_h / 90 degrees) and the degree-6 Bernstein polynomials of theta_d / 90 degrees,
fitted by least squares to ln f of the training rows with a penalty on the second differences of the
coefficients along both coordinates (1e-2 of the mean diagonal of the normal equations). It uses theta_h and
theta_d alone (isotropic, no phi_d): the candidate family for tables such as Mystique (issue 26's seventh
part).

usage: knn_held_out.py TABLE [--neighbours K] [--shared DIR] [--brdfbake EXE [-- FIT ARGUMENTS]]
       (numpy; the shared tool for reading tables)
"""
import argparse
import math
import os
import random
import subprocess
import sys
import tempfile

import numpy as np


def light_view_half(row):
    """Unit light, view and half-vector of a row [theta_i, phi_i, theta_s, phi_s, ...] (radians)."""
    ti, pi, ts, ps = row[:4]
    wi = np.array([math.sin(ti) * math.cos(pi), math.sin(ti) * math.sin(pi), math.cos(ti)])
    wo = np.array([math.sin(ts) * math.cos(ps), math.sin(ts) * math.sin(ps), math.cos(ts)])
    return wi, wo, (wi + wo) / np.linalg.norm(wi + wo)


def half_difference(row):
    """(2 sqrt(theta_h), theta_d, phi_d / 2) of a row (radians)."""
    wi, _, h = light_view_half(row)
    theta_h, phi_h = math.acos(min(1.0, h[2])), math.atan2(h[1], h[0])
    c, s = math.cos(-phi_h), math.sin(-phi_h)  # wi rotated by -phi_h about z, then -theta_h about y
    d = np.array([c * wi[0] - s * wi[1], s * wi[0] + c * wi[1], wi[2]])
    c, s = math.cos(-theta_h), math.sin(-theta_h)
    d = np.array([c * d[0] + s * d[2], d[1], -s * d[0] + c * d[2]])
    theta_d = math.acos(max(-1.0, min(1.0, d[2])))
    phi_d = math.atan2(d[1], d[0]) % math.pi
    return np.array([2.0 * math.sqrt(theta_h), theta_d, 0.5 * min(phi_d, math.pi - phi_d)])


def predict(train, held, neighbours):
    x = np.array([half_difference(r) for r in train])
    log_f = np.log(np.maximum(np.array([r[4:] for r in train]), 1e-6))
    out = []
    for r in held:
        distance = np.linalg.norm(x - half_difference(r), axis=1)
        nearest = np.argsort(distance)[:neighbours]
        w = 1.0 / (distance[nearest] + 1e-3)
        out.append(list(np.exp((w[:, None] * log_f[nearest]).sum(0) / w.sum())))
    return out


def half_and_difference_angles(row):
    """(theta_h, theta_d) of a row (radians): the half-vector's angle to the normal, and the light's to it."""
    wi, _, h = light_view_half(row)
    return math.acos(min(1.0, h[2])), math.acos(max(-1.0, min(1.0, float(wi @ h))))


def table_design(rows, hats=12, degree=6):
    """Rows of the tensor-product basis: hat_k(sqrt(theta_h / 90 deg)) B_j(theta_d / 90 deg), index k (degree + 1) + j."""
    design = np.zeros((len(rows), hats * (degree + 1)))
    for i, row in enumerate(rows):
        theta_h, theta_d = half_and_difference_angles(row)
        u = math.sqrt(theta_h / (math.pi / 2)) * (hats - 1)
        k = min(int(u), hats - 2)
        hat = np.zeros(hats)
        hat[k], hat[k + 1] = k + 1 - u, u - k
        s = min(theta_d / (math.pi / 2), 1.0)
        bernstein = np.array([math.comb(degree, j) * s ** j * (1 - s) ** (degree - j) for j in range(degree + 1)])
        design[i] = np.outer(hat, bernstein).ravel()
    return design


def table_predict(train, held, hats=12, degree=6, penalty=1e-2):
    """The smooth table in (theta_h, theta_d) fitted to ln f of the training rows (see the file's comment)."""
    a = table_design(train, hats, degree)
    n = a.shape[1]
    differences = []  # second differences along theta_h (step degree + 1) and along theta_d (step 1)
    for k in range(hats):
        for j in range(degree + 1):
            index = k * (degree + 1) + j
            for step, inside in ((degree + 1, k + 2 < hats), (1, j + 2 <= degree)):
                if inside:
                    row = np.zeros(n)
                    row[index], row[index + step], row[index + 2 * step] = 1.0, -2.0, 1.0
                    differences.append(row)
    d = np.array(differences)
    gram = a.T @ a
    scale = np.trace(gram) / n
    gram += penalty * scale * (d.T @ d) + 1e-9 * scale * np.eye(n)
    coefficients = np.linalg.solve(gram, a.T @ np.log(np.maximum(np.array([r[4:] for r in train]), 1e-6)))
    return np.exp(np.clip(table_design(held, hats, degree) @ coefficients, -50.0, 50.0)).tolist()


def errors(check, train, held, predicted):
    """Squared cosine-weighted log errors per held-out row (summed over channels) of a prediction and of
    the Lambertian fit to the training rows."""
    lambert = check.lambert_fit(train, len(held[0]) - 4)
    squares = lambda row, p: sum((math.log1p(max(q, 0.0) * math.cos(row[0]))
                                  - math.log1p(max(m, 0.0) * math.cos(row[0]))) ** 2 for m, q in zip(row[4:], p))
    return [squares(r, p) for r, p in zip(held, predicted)], [squares(r, lambert) for r in held]


def ratio(check, splits, predictor):
    """sqrt(sum of squared errors / sum of Lambert's), pooled over (train, held) splits."""
    fit = lam = 0.0
    for train, held in splits:
        e, l = errors(check, train, held, predictor(train, held))
        fit, lam = fit + sum(e), lam + sum(l)
    return math.sqrt(fit / lam)


def elevation_figures(check, train, held, predicted):
    """The split's ratio, the ratio without the sample nearest the mirror, and that sample (channel means)."""
    e, l = errors(check, train, held, predicted)
    m = min(range(len(held)), key=lambda i: check.mirror_offset_deg(held[i]))
    ratio_of = lambda fit, lam: "%.3f" % math.sqrt(fit / lam) if lam > 0.0 else "n/a"
    mean = lambda values: sum(values) / len(values)
    return "%s (%s without the mirror sample: %.3g measured, %.3g predicted, %.0f%% of Lambert's error)" % (
        ratio_of(sum(e), sum(l)), ratio_of(sum(e) - e[m], sum(l) - l[m]), mean(held[m][4:]), mean(predicted[m]),
        100.0 * l[m] / sum(l) if sum(l) > 0.0 else 0.0)


def brdfbake_predictor(check, exe, wavelengths, fit_args):
    """Predicts held-out rows with `brdfbake fit` on the training rows and `brdfbake eval`, as the shared
    tool does (a table whose channel names end in "nm" is fitted with --channels spectral, others with
    --channels rgb)."""
    channels = "spectral" if all(str(w).endswith("nm") for w in wavelengths) else "rgb"

    def run(command):
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            raise RuntimeError("%s failed: %s" % (" ".join(command[:2]), (result.stderr or result.stdout).strip()[:300]))
        return result.stdout

    def predict_with_fit(train, held):
        with tempfile.TemporaryDirectory(prefix="knn-held-out-") as tmp:
            check.write_astm(tmp + "/train.astm", wavelengths, train)
            run([exe, "fit", tmp + "/train.astm", "--channels", channels, "-o", tmp + "/fit.json", "--quiet", *fit_args])
            with open(tmp + "/pairs.txt", "w") as pairs:
                pairs.writelines(" ".join("%.6f" % x for x in row[:4]) + "\n" for row in held)
            out = run([exe, "eval", tmp + "/fit.json", "--pairs", tmp + "/pairs.txt"])
            values = [[float(x) for x in line.replace(",", " ").split()] for line in out.strip().splitlines()]
            return [v[-len(wavelengths):] for v in values]
    return predict_with_fit


def main():
    argv = sys.argv[1:]
    fit_args = tuple(argv[argv.index("--") + 1:]) if "--" in argv else ()
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("table", help="a Cornell table (.astm, spectral or RGB, or pbrt-v2 .brdf)")
    parser.add_argument("--neighbours", type=int, default=4, help="neighbours averaged (default 4)")
    parser.add_argument("--shared", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared"),
                        help="the shared folder, for tools/fit_heldout_check.py (default ../shared)")
    parser.add_argument("--brdfbake", help="also measure `brdfbake fit` with this executable")
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    sys.path.insert(0, os.path.join(args.shared, "tools"))
    import fit_heldout_check as check

    wavelengths, rows = check.load_table(args.table)
    rows = [r for r in rows if math.cos(r[0]) > 0.0 and math.cos(r[2]) > 0.0]
    off_mirror = [i for i, r in enumerate(rows) if check.mirror_offset_deg(r) > 5.0]
    random.Random(1).shuffle(off_mirror)
    folds = []
    for k in range(5):
        held = set(off_mirror[k::5])
        folds.append(([r for i, r in enumerate(rows) if i not in held], [rows[i] for i in sorted(held)]))
    predictors = [("nearest neighbours", lambda train, held: predict(train, held, args.neighbours)),
                  ("smooth table in (theta_h, theta_d)", table_predict)]
    if args.brdfbake:
        if "--lobes" not in fit_args:  # as fit_heldout_check.py: --lobes auto unless given
            fit_args = ("--lobes", "auto", *fit_args)
        predictors.append(("brdfbake fit", brdfbake_predictor(check, args.brdfbake, wavelengths, fit_args)))
    print("%s (x Lambert):" % os.path.basename(args.table))
    for name, predictor in predictors:
        print("  %s: off-mirror 5-fold %.3f" % (name, ratio(check, folds, predictor)))
        for theta in (30, 50, 70):
            train, held = check.incidence_split(rows, theta)
            if not held:
                print("    %d deg: no rows" % theta)
                continue
            print("    %d deg held out %s" % (theta, elevation_figures(check, train, held,
                                                                       predictor(train, held))))


if __name__ == "__main__":
    try:
        main()
    except (OSError, RuntimeError, subprocess.CalledProcessError) as error:
        sys.exit("knn_held_out.py: %s" % error)
