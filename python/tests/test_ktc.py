"""eitbench's KTC2023 files and score against the challenge's own tools: scipy.io reads the
submission files `eitbench ktc` writes as the challenge's scoring script does, and the challenge's
scoring function (transcribed from its published Python, run with SciPy) gives the scores eitbench
prints. Needs the training set in ../shared/data/ktc2023 (never committed) and SciPy."""
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

scipy_io = pytest.importorskip("scipy.io")
scipy_signal = pytest.importorskip("scipy.signal")

CLI = os.environ.get("EITBENCH_CLI", "eitbench")
KTC = pathlib.Path(__file__).resolve().parents[3] / "shared" / "data" / "ktc2023"


def ssim(truth, reco):
    """The challenge's SSIM, as its scoring code computes it."""
    c1, c2, r = 1e-4, 9e-4, 80
    ws = np.ceil(2 * r)
    wr = np.arange(-ws, ws + 1)
    X, Y = np.meshgrid(wr, wr)
    ker = (1 / np.sqrt(2 * np.pi)) * np.exp(-0.5 * (np.square(X) + np.square(Y)) / r**2)
    # convolve2d, as the challenge wrote it, by FFT: the same sums to rounding, 1,000x sooner.
    conv = lambda a: scipy_signal.fftconvolve(a, ker, mode="same")
    correction = conv(np.ones(truth.shape))
    gt, gr = conv(truth) / correction, conv(reco) / correction
    sigma_t2 = conv(np.square(truth)) / correction - np.square(gt)
    sigma_r2 = conv(np.square(reco)) / correction - np.square(gr)
    sigma_tr = conv(truth * reco) / correction - gt * gr
    num = (2 * gt * gr + c1) * (2 * sigma_tr + c2)
    den = (np.square(gt) + np.square(gr) + c1) * (sigma_t2 + sigma_r2 + c2)
    return np.mean(num / den)


def ktc_score(truth, reco):
    if reco.shape != (256, 256):
        return 0.0
    masks = lambda image, c: (np.abs(image - c) < 0.1).astype(float)
    return 0.5 * (ssim(masks(truth, 2), masks(reco, 2)) + ssim(masks(truth, 1), masks(reco, 1)))


@pytest.mark.skipif(not (KTC / "ref.mat").exists(), reason=f"no {KTC} (not committed)")
def test_ktc_files_and_scores_are_the_challenges(tmp_path):
    done = subprocess.run([CLI, "ktc", str(KTC), str(tmp_path), "2", "--method", "noser",
                           "--lambda", "0.3", "--density", "coarse", "--pixels", "48"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    printed = {int(n): float(s) for n, s in re.findall(r"^(\d+): .* score ([0-9.]+)$",
                                                       done.stdout, re.M)}
    assert sorted(printed) == [1, 2, 3, 4], done.stdout
    for n, score in printed.items():
        reco = scipy_io.loadmat(tmp_path / f"{n}.mat")["reconstruction"]
        assert reco.dtype == np.uint8 and reco.shape == (256, 256)
        assert set(np.unique(reco)) <= {0, 1, 2}
        truth = scipy_io.loadmat(KTC / f"true{n}.mat")["truth"].astype(float)
        assert abs(ktc_score(truth, reco.astype(float)) - score) < 1e-6, n
