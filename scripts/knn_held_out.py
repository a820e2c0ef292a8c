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

usage: knn_held_out.py TABLE [--neighbours K] [--shared DIR]   (numpy; the shared tool for reading tables)
"""
import argparse
import math
import os
import random
import sys

import numpy as np


def half_difference(row):
    """(2 sqrt(theta_h), theta_d, phi_d / 2) of a row [theta_i, phi_i, theta_s, phi_s, ...] (radians)."""
    ti, pi, ts, ps = row[:4]
    wi = np.array([math.sin(ti) * math.cos(pi), math.sin(ti) * math.sin(pi), math.cos(ti)])
    wo = np.array([math.sin(ts) * math.cos(ps), math.sin(ts) * math.sin(ps), math.cos(ts)])
    h = (wi + wo) / np.linalg.norm(wi + wo)
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


def ratio(check, channels, splits, neighbours):
    """sqrt(sum of squared errors / sum of Lambert's), pooled over (train, held) splits."""
    fit = lam = 0.0
    for train, held in splits:
        e = check.logerr(held, predict(train, held, neighbours))
        l = check.logerr(held, [check.lambert_fit(train, channels)] * len(held))
        fit += e * e * len(held)
        lam += l * l * len(held)
    return math.sqrt(fit / lam)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("table")
    parser.add_argument("--neighbours", type=int, default=4)
    parser.add_argument("--shared", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared"))
    args = parser.parse_args()
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
    figures = ["off-mirror 5-fold %.3f" % ratio(check, len(wavelengths), folds, args.neighbours)]
    for theta in (30, 50, 70):
        at = [abs(math.degrees(r[0]) - theta) < 1.0 for r in rows]
        split = ([r for r, a in zip(rows, at) if not a], [r for r, a in zip(rows, at) if a])
        figures.append("%d deg %.3f" % (theta, ratio(check, len(wavelengths), [split], args.neighbours)))
    print(os.path.basename(args.table) + ": " + ", ".join(figures) + " (x Lambert)")


if __name__ == "__main__":
    main()
