"""pyEIT's Jacobian method on a recording of real presses, tuned and scored as eitbench's one-step rows are
(docs/real-presses.md#pyeit-on-the-same-presses): a reference to compare with, not part of eitbench.

The recording is a MAT file with `responseups`, `responsedowns` (N x 192 magnitudes, opposite drive,
adjacent measurement: pyEIT's protocol.create(16, dist_exc=8, step_meas=1)) and `positions` (N x 3,
metres). Each press's frame is the signed difference down - up (each magnitude times the sign of
pyEIT's homogeneous voltage); pyEIT's JAC (kotre prior, diag(JᵀJ)^p) reconstructs it on pyEIT's own
mesh, and the press is put at the area-weighted centroid of the elements at or below `thr` times the
image's most negative value (a press lowers the conductivity). p, λ and thr are chosen for the lowest
mean centre error on the tuning presses; the scored presses take no part in any choice.

Needs pyEIT (pip install pyeit; eitbench itself does not use it) with NumPy and SciPy.
Usage: python3 pyeit_presses.py superpose50.mat [--tune 0:500] [--score 500:550] [--theta0 282]
                                [--radius-mm 70] [--h0 0.1]
"""
import argparse
import sys

import numpy as np

P_GRID = [0.0, 0.2, 0.5, 1.0]  # kotre's exponent: 0 the identity, 1 NOSER's diag(JᵀJ)
LAMBDA_GRID = [10.0 ** (k / 2) for k in range(-4, 7)]  # 0.01 ... 1000, relative (below)
THRESHOLDS = [0.3, 0.4, 0.5, 0.6, 0.7, 0.8]


def frames_range(text):
    a, b = (int(v) for v in text.split(':'))
    return slice(a, b)


def press_positions_on_mesh(positions, electrodes, theta0_deg):
    """The presses in the mesh's frame: electrode k lies at theta0 + k * 22.5 degrees counter-clockwise
    in the recording's frame, and pyEIT's mesh numbers its electrodes clockwise or counter-clockwise."""
    angles = np.unwrap(np.arctan2(electrodes[:, 1], electrodes[:, 0]))
    turn = 1.0 if np.median(np.diff(angles)) > 0 else -1.0
    radius = np.hypot(positions[:, 0], positions[:, 1])
    from_electrode0 = np.arctan2(positions[:, 1], positions[:, 0]) - np.deg2rad(theta0_deg)
    angle = angles[0] + turn * from_electrode0
    return np.c_[radius * np.cos(angle), radius * np.sin(angle)]


def centre_errors(images, threshold, centres, areas, truth):
    """Distance from each press to the area-weighted centroid of its image's elements at or below
    threshold times the image's minimum."""
    mask = images <= threshold * images.min(axis=1, keepdims=True)
    weights = mask * areas
    found = weights @ centres / weights.sum(axis=1, keepdims=True)
    return np.linalg.norm(found - truth, axis=1)


def read_recording(sio, args):
    """The recording's three variables, checked: a message naming the file and field, exit 2."""
    def fail(what):
        print(f'pyeit_presses.py: {args.recording}: {what}', file=sys.stderr)
        sys.exit(2)
    try:
        data = sio.loadmat(args.recording)
    except (OSError, ValueError) as error:
        fail(f'cannot be read as a MAT file ({error})')
    shapes = {'responseups': 192, 'responsedowns': 192, 'positions': 3}
    for name, columns in shapes.items():
        if name not in data or data[name].ndim != 2 or data[name].shape[1] != columns:
            fail(f'`{name}` must be an N x {columns} matrix')
    n = len(data['positions'])
    if len(data['responseups']) != n or len(data['responsedowns']) != n:
        fail('`responseups`, `responsedowns` and `positions` must have one row a press')
    for part in (args.tune, args.score):
        if not 0 <= part.start < part.stop <= n:
            fail(f'presses {part.start}:{part.stop} are not within its {n}')
    up = data['responseups'].astype(float)
    if not np.all(up > 0):
        fail('`responseups` must hold positive magnitudes')
    return up, data['responsedowns'].astype(float), data['positions'][:, :2].astype(float)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('recording')
    parser.add_argument('--tune', type=frames_range, default=frames_range('0:500'))
    parser.add_argument('--score', type=frames_range, default=frames_range('500:550'))
    parser.add_argument('--theta0', type=float, default=282.0, help='electrode 0 angle, degrees')
    parser.add_argument('--radius-mm', type=float, default=70.0)
    parser.add_argument('--h0', type=float, default=0.1, help="pyEIT mesh size (its default 0.1)")
    parser.add_argument('--relative', action='store_true',
                        help='the relative change (down - up) / up and a Jacobian divided by the homogeneous voltage')
    args = parser.parse_args()
    import scipy.io as sio  # here, so that tests/pyeit_presses_test.py needs neither SciPy nor pyEIT
    import pyeit.mesh as mesh
    import pyeit.eit.protocol as protocol
    import pyeit.eit.jac as jac

    up, down, positions = read_recording(sio, args)
    positions = positions / (args.radius_mm / 1000.0)

    np.random.seed(0)  # distmesh draws its initial points
    m = mesh.create(16, h0=args.h0)
    solver = jac.JAC(m, protocol.create(16, dist_exc=8, step_meas=1, parser_meas='std'))
    solver.setup(p=0.2, lamb=0.01, method='kotre', perm=1)
    sign = np.sign(solver.v0)
    frames = sign * (down - up)
    J = solver.J
    if args.relative:  # pyEIT's jac_normalized with solve(..., normalize=True)
        frames = (down - up) / up * sign
        J = J / np.abs(solver.v0)[:, None]
    truth = press_positions_on_mesh(positions, m.node[m.el_pos][:, :2], args.theta0)
    corners = m.node[m.element][:, :, :2]
    centres = corners.mean(axis=1)
    edges1, edges2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    areas = 0.5 * np.abs(edges1[:, 0] * edges2[:, 1] - edges1[:, 1] * edges2[:, 0])
    gram = J.T @ J
    diagonal = np.diag(gram)
    print(f'pyEIT mesh h0 {args.h0}: {len(m.node)} nodes, {len(m.element)} elements; '
          f'tune on presses {args.tune.start}:{args.tune.stop}, score {args.score.start}:{args.score.stop}')

    rows = []
    for p in P_GRID:
        # λ relative to the prior's size, so one grid serves every p: pyEIT's lamb = λ * scale.
        scale = diagonal.mean() / (diagonal ** p).mean()
        for lam in LAMBDA_GRID:
            solver.H = solver._compute_h(J, p, lam * scale, 'kotre')
            images = -frames @ solver.H.T  # pyEIT's solve: ds = -H (v1 - v0)
            for thr in THRESHOLDS:
                err = centre_errors(images, thr, centres, areas, truth) * args.radius_mm
                tune, score = err[args.tune], err[args.score]
                rows.append((tune.mean(), p, lam, lam * scale, thr, np.median(tune),
                             np.median(score), score.mean()))
    rows.sort(key=lambda r: r[0])
    print('chosen on the tuning presses (lowest mean) first; centre error in mm, median / mean')
    print('     p   λ (rel)   pyEIT lamb   thr | tuning         | scored')
    for mean, p, lam, lamb, thr, median, s_median, s_mean in rows[:8]:
        print(f'{p:6.1f} {lam:9.3g} {lamb:12.3g} {thr:5.1f} | {median:5.1f} / {mean:5.1f} | '
              f'{s_median:5.1f} / {s_mean:5.1f}')
    rank, best = min(enumerate(rows, 1), key=lambda r: r[1][7])
    print(f'best on the scored presses (not a choice: it reads their labels): p {best[1]}, '
          f'pyEIT lamb {best[3]:.3g}, thr {best[4]}: {best[6]:.1f} / {best[7]:.1f}, '
          f'ranked {rank} of {len(rows)} on the tuning presses')


if __name__ == '__main__':
    main()
