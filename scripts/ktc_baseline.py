"""The KTC2023 organisers' one-step baseline, their own code, on a folder of training samples at every
level, scored by their own scoring function (docs/ktc.md#the-organisers-baseline-on-the-same-samples):
a reference to compare with, not part of eitbench.

CODES is the challenge's Codes_Python folder (main.py, KTCFwd.py, KTCScoring.py, ... and
Mesh_sparse.mat; with their requirements: NumPy, SciPy, Matplotlib). DATA holds ref.mat, dataN.mat
and trueN.mat. Their main.py runs unchanged but for two things that leave every figure as it is: it
reads the data files in name order (it numbers its outputs in the order it finds them), and it
computes the Jacobian at its fixed linearisation point once a level instead of once a file; their
scoring function's convolutions are done by FFT (the same sums to rounding).
A level's figure is 3 times the mean of the samples' scores (the challenge had three a level).

Usage: python3 ktc_baseline.py CODES DATA [--levels 1-7] [--out FOLDER]
"""
import argparse
import glob
import os
import shutil
import sys
import tempfile
import time
import types


def level_range(text):
    first, _, last = text.partition('-')
    levels = list(range(int(first), int(last or first) + 1))
    if not levels or levels[0] < 1 or levels[-1] > 7:
        raise argparse.ArgumentTypeError(f'levels {text}: the challenge has levels 1 to 7')
    return levels


def samples_in(data):
    """The sample numbers with a dataN.mat and a trueN.mat, and ref.mat checked."""
    def fail(what):
        print(f'ktc_baseline.py: {data}: {what}', file=sys.stderr)
        sys.exit(2)
    if not os.path.isfile(os.path.join(data, 'ref.mat')):
        fail('no ref.mat')
    numbers = sorted(sample_number(p) for p in glob.glob(os.path.join(data, 'data*.mat'))
                     if os.path.basename(p)[4:-4].isdigit())
    if not numbers:
        fail('no dataN.mat')
    for n in numbers:
        if not os.path.isfile(os.path.join(data, f'true{n}.mat')):
            fail(f'data{n}.mat has no true{n}.mat to score against')
    return numbers


def load_baseline(codes):
    for name in ('main.py', 'KTCFwd.py', 'KTCScoring.py', 'Mesh_sparse.mat'):
        if not os.path.isfile(os.path.join(codes, name)):
            print(f'ktc_baseline.py: {codes}: no {name}: not the challenge\'s Codes_Python folder',
                  file=sys.stderr)
            sys.exit(2)
    sys.path.insert(0, codes)
    os.chdir(codes)  # main.py reads Mesh_sparse.mat from the working folder
    import main as baseline
    import KTCFwd
    import KTCScoring
    find = glob.glob  # main.py's own `glob` replaced, not the module every caller shares
    baseline.glob = types.SimpleNamespace(glob=lambda pattern: sorted(find(pattern), key=sample_number))
    jacobian = KTCFwd.EITFEM.Jacobian

    def jacobian_once(solver, sigma, z):  # main.py's sigma and z do not change between files
        if not hasattr(solver, 'jacobian_at_the_linearisation_point'):
            solver.jacobian_at_the_linearisation_point = jacobian(solver, sigma, z)
        return solver.jacobian_at_the_linearisation_point
    KTCFwd.EITFEM.Jacobian = jacobian_once
    # Their SSIM convolves with a 321 x 321 window directly, minutes a score: the same sums by FFT.
    import scipy.signal
    KTCScoring.sps = types.SimpleNamespace(convolve2d=scipy.signal.fftconvolve)
    return baseline, KTCScoring


def sample_number(path):
    return int(os.path.basename(path)[4:-4])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('codes', help="the challenge's Codes_Python folder")
    parser.add_argument('data', help='ref.mat, dataN.mat and trueN.mat')
    parser.add_argument('--levels', type=level_range, default=level_range('1-7'))
    parser.add_argument('--out', help='keep the N.mat files here, a folder a level (default: not kept)')
    args = parser.parse_args()
    data = os.path.abspath(args.data)
    out_root = os.path.abspath(args.out) if args.out else None
    numbers = samples_in(data)
    baseline, scoring = load_baseline(os.path.abspath(args.codes))
    import scipy.io as sio

    total = 0.0
    for level in args.levels:
        started = time.time()
        with tempfile.TemporaryDirectory() as folder:
            for name in ['ref.mat'] + [f'data{n}.mat' for n in numbers]:
                shutil.copy(os.path.join(data, name), folder)
            out = os.path.join(out_root, f'level{level}') if out_root else os.path.join(folder, 'out')
            baseline.main(folder, out, level)
            scores = [scoring.scoringFunction(sio.loadmat(os.path.join(data, f'true{n}.mat'))['truth'],
                                              sio.loadmat(os.path.join(out, f'{i}.mat'))['reconstruction'])
                      for i, n in enumerate(numbers, 1)]
        figure = 3 * sum(scores) / len(scores)
        total += figure
        print(f'level {level}: ' + ' '.join(f'{s:.3f}' for s in scores) +
              f' -> {figure:.2f} of 3 ({time.time() - started:.0f} s)', flush=True)
    print(f'total over levels {args.levels[0]}-{args.levels[-1]}: {total:.2f}')


if __name__ == '__main__':
    main()
