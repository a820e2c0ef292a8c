#!/usr/bin/python3
"""A study, not part of the library (docs/fitting.md, "Mystique"): would per-channel colour profiles along
an angle both directions share fix the colour-shifting tables? On the splits of the shared held-out check
(../shared/tools/fit_heldout_check.py, same seed), `brdfbake fit` fits each training part (the lobes'
shapes); then each channel's weights are fitted again with every column (diffuse, each lobe's C and C_F)
times Bernstein weights of DEGREE in a coordinate s (MODES, comma-separated: none = the fit's own model,
mean = the mean of the two elevations, thetad = the angle between light and half vector, thetah = the
half vector's elevation, incident = the light's elevation, not reciprocal), by NNLS on the linearised log
error and Gauss-Newton steps. Prints each mode's four ratios to a Lambertian fit, as the check does.

usage: scripts/colour_profile_study.py BRDFBAKE TABLE [MODES [DEGREE]]   (python3-numpy; the shared tools
from $BRDFBAKE_SHARED, default ../shared next to the repository)"""
import importlib.util, json, math, os, pathlib, random, subprocess, sys, tempfile
import numpy as np

SHARED = pathlib.Path(os.environ.get('BRDFBAKE_SHARED', pathlib.Path(__file__).resolve().parents[1] / '../shared'))
spec = importlib.util.spec_from_file_location('chk', SHARED / 'tools/fit_heldout_check.py')
chk = importlib.util.module_from_spec(spec); spec.loader.exec_module(chk)


def dirs(t, p):
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=1)


def geometry(rows):
    R = np.array([r[:4] for r in rows])
    l, v = dirs(R[:, 0], R[:, 1]), dirs(R[:, 2], R[:, 3])
    h = l + v; h /= np.linalg.norm(h, axis=1, keepdims=True)
    return dict(l=l, v=v, h=h, horiz=l[:, 0] * v[:, 0] + l[:, 1] * v[:, 1], vert=l[:, 2] * v[:, 2])


def columns(model, g):
    """Unit-weight columns of the fitted model's shapes: diffuse, then per lobe C (and C_F)."""
    m = model['model']; chans = model['channels']
    lz, vz = g['l'][:, 2], g['v'][:, 2]
    cols = [np.full(len(lz), 1 / math.pi)]
    lo, hi = m['elevation_range']['min_cos'], m['elevation_range']['max_cos']
    t = np.clip(np.log(np.maximum(vz, 1e-9) / lo) / math.log(hi / lo), 0, 1) if hi > lo else np.zeros_like(vz)
    B = np.stack([(1 - t) ** 2, 2 * t * (1 - t), t ** 2], axis=1)
    for k in range(len(chans[0]['lobes'])):
        ref = max(chans, key=lambda c: c['lobes'][k]['weight'][-1])['lobes'][k]
        ex = np.array(ref['exponent']); w = np.array(ref['weight'])
        if len(ex) == 3:
            n = np.exp(B @ np.log(ex)); gain = np.exp(B @ np.log(np.maximum(w / w[-1], 1e-300)))
        else:
            n = np.full(len(lz), ex[0]); gain = np.ones(len(lz))
        if ref.get('axis') == 'half_vector':
            c = g['h'][:, 2]; scale = 0.25 / (lz * vz)
            sch = (1 - np.sum(g['l'] * g['h'], axis=1)) ** 5
        else:
            cxy = ref.get('c_xy', -1.0); c = cxy * g['horiz'] + g['vert']; scale = 1.0; sch = None
        base = np.where(c > 0, (n + 2) / (2 * math.pi) * np.power(np.maximum(c, 1e-300), n), 0.0) * scale
        cols.append(gain * base)
        if sch is not None: cols.append(base * sch)  # C_F is constant in the model
    return np.stack(cols, axis=1)


def coordinate(g, mode):
    l, v, h = g['l'], g['v'], g['h']
    if mode == 'mean': return (np.arccos(l[:, 2]) + np.arccos(v[:, 2])) / math.pi
    if mode == 'thetad': return np.arccos(np.clip(np.sum(l * h, axis=1), -1, 1)) / (math.pi / 2)
    if mode == 'thetah': return np.arccos(np.clip(h[:, 2], -1, 1)) / (math.pi / 2)
    if mode == 'incident': return np.arccos(l[:, 2]) / (math.pi / 2)
    raise ValueError(mode)


def nnls(A, b, iters=300):
    """Lawson-Hanson active set."""
    n = A.shape[1]; x = np.zeros(n); P = np.zeros(n, bool)
    for _ in range(iters):
        w = A.T @ (b - A @ x)
        if P.all() or w[~P].max(initial=-1) <= 1e-12 * max(1, np.abs(w).max()): break
        j = np.argmax(np.where(P, -np.inf, w)); P[j] = True
        while True:
            z = np.zeros(n); z[P] = np.linalg.lstsq(A[:, P], b, rcond=None)[0]
            if (z[P] > 0).all(): x = z; break
            q = P & (z <= 0); alpha = np.min(x[q] / (x[q] - z[q])); x = x + alpha * (z - x)
            P &= x > 1e-15; x[~P] = 0
    return x


def refit(A, cos, f, steps=4):
    """Per channel: NNLS of the log error linearised at the data, then Gauss-Newton steps."""
    y = np.log1p(cos * np.maximum(f, 0))
    om = cos / (1 + cos * np.maximum(f, 0))
    x = nnls(A * om[:, None], om * np.maximum(f, 0))
    for _ in range(steps):
        m = np.maximum(A @ x, 0); r = np.log1p(cos * m) - y
        om = cos / (1 + cos * m)
        x2 = nnls(A * om[:, None], om * (m - r / om))
        r2 = np.log1p(cos * np.maximum(A @ x2, 0)) - y
        if (r2 ** 2).sum() < (r ** 2).sum(): x = x2
        else: break
    return x


def predict(model, train, held, mode, degree):
    gt, gh = geometry(train), geometry(held)
    At, Ah = columns(model, gt), columns(model, gh)
    if mode != 'none':
        def expand(A, s):
            s = np.clip(s, 0, 1)
            Bs = [math.comb(degree, j) * s ** j * (1 - s) ** (degree - j) for j in range(degree + 1)]
            return np.concatenate([A * b[:, None] for b in Bs], axis=1)
        At, Ah = expand(At, coordinate(gt, mode)), expand(Ah, coordinate(gh, mode))
    ft = np.array([r[4:] for r in train]); cos = np.cos(np.array([r[0] for r in train]))
    pred = np.zeros((len(held), ft.shape[1]))
    for c in range(ft.shape[1]):
        pred[:, c] = np.maximum(Ah @ refit(At, cos, ft[:, c]), 0)
    return pred.tolist()


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    exe, table = sys.argv[1], sys.argv[2]
    modes = sys.argv[3].split(',') if len(sys.argv) > 3 else ['none', 'mean', 'thetad', 'thetah', 'incident']
    degree = int(sys.argv[4]) if len(sys.argv) > 4 else 2
    wls, rows = chk.load_table(table)
    tmp = tempfile.mkdtemp(prefix='proto-')
    rng = random.Random(1)
    cand = [i for i, r in enumerate(rows) if chk.mirror_offset_deg(r) > 5.0]
    rng.shuffle(cand)
    splits = [('kfold', [r for i, r in enumerate(rows) if i not in set(cand[k::5])],
               [r for i, r in enumerate(rows) if i in set(cand[k::5])]) for k in range(5)]
    splits += [(f'{th}', *chk.incidence_split(rows, th)) for th in (30, 50, 70)]
    sums = {}
    for name, train, held in splits:
        chk.write_astm(f'{tmp}/train.astm', wls, train)
        channels = 'spectral' if all(str(w).endswith('nm') for w in wls) else 'rgb'
        subprocess.run([exe, 'fit', f'{tmp}/train.astm', '--channels', channels, '-o', f'{tmp}/fit.json', '--quiet'],
                       check=True)
        model = json.load(open(f'{tmp}/fit.json'))
        lam = chk.lambert_error(wls, train, held)
        for mode in modes:
            e = chk.logerr(held, predict(model, train, held, mode, degree))
            s = sums.setdefault((name, mode), [0.0, 0.0]); s[0] += e * e * len(held); s[1] += lam * lam * len(held)
    for mode in modes:
        out = [math.sqrt(sums[(n, mode)][0] / sums[(n, mode)][1]) for n in ('kfold', '30', '50', '70')]
        print(f"{os.path.basename(table)} {mode:9s} degree {degree}: " + ' / '.join(f'{x:.4f}' for x in out))
    return 0


if __name__ == '__main__':
    sys.exit(main())
