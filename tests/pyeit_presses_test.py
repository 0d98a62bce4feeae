#!/usr/bin/env python3
"""scripts/pyeit_presses.py's own parts, without pyEIT: the presses land on the mesh's electrodes
whichever way the mesh numbers them, and a press is put at the area-weighted centroid of the
elements at or below the threshold."""
import argparse
import contextlib
import io
import os
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import pyeit_presses as pp  # noqa: E402

STEP = 2 * np.pi / 16


def ring(first, turn):
    angles = first + turn * STEP * np.arange(16)
    return np.c_[np.cos(angles), np.sin(angles)]


class PressPositions(unittest.TestCase):
    def test_a_press_at_an_electrode_lands_on_that_electrode(self):
        theta0 = 282.0
        recorded = ring(np.deg2rad(theta0), +1)  # electrode k at theta0 + k * 22.5, counter-clockwise
        for first, turn in [(np.pi, -1), (np.pi, +1), (0.3, -1)]:
            electrodes = ring(first, turn)
            on_mesh = pp.press_positions_on_mesh(recorded, electrodes, theta0)
            np.testing.assert_allclose(on_mesh, electrodes, atol=1e-12)

    def test_the_radius_is_kept(self):
        presses = np.array([[0.3, -0.1], [0.0, 0.5], [-0.2, -0.2]])
        on_mesh = pp.press_positions_on_mesh(presses, ring(np.pi, -1), 282.0)
        np.testing.assert_allclose(np.hypot(*on_mesh.T), np.hypot(*presses.T), atol=1e-12)


class CentreErrors(unittest.TestCase):
    centres = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    areas = np.array([1.0, 3.0, 1.0])

    def test_the_centroid_of_the_elements_at_or_below_the_threshold(self):
        images = np.array([[-1.0, -0.2, 0.1],    # only the first: at (0, 0)
                           [-1.0, -0.5, 0.0]])   # the first two, weighted 1 and 3: at (0.75, 0)
        truth = np.array([[0.0, 0.0], [0.0, 0.0]])
        errors = pp.centre_errors(images, 0.5, self.centres, self.areas, truth)
        np.testing.assert_allclose(errors, [0.0, 0.75], atol=1e-12)

    def test_frames_range(self):
        self.assertEqual(pp.frames_range("400:500"), slice(400, 500))


class Recording(unittest.TestCase):
    """A bad recording is exit 2 with the file and the field named."""

    def read(self, variables, tune="0:2", score="2:3"):
        sio = __import__("scipy.io").io
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "presses.mat")
            sio.savemat(path, variables)
            args = argparse.Namespace(recording=path, tune=pp.frames_range(tune),
                                      score=pp.frames_range(score))
            stderr = io.StringIO()
            with contextlib.redirect_stderr(stderr):
                try:
                    return pp.read_recording(sio, args), 0, ""
                except SystemExit as exit:
                    return None, exit.code, stderr.getvalue()

    def test_good_and_bad_recordings(self):
        good = {"responseups": np.ones((3, 192)), "responsedowns": np.ones((3, 192)),
                "positions": np.zeros((3, 3))}
        (up, down, positions), code, _ = self.read(good)
        self.assertEqual((code, up.shape, positions.shape), (0, (3, 192), (3, 2)))
        for field, value in [("responseups", np.ones((3, 191))), ("positions", np.zeros((2, 3))),
                             ("responseups", np.zeros((3, 192)))]:
            _, code, message = self.read(dict(good, **{field: value}))
            self.assertEqual(code, 2, field)
            self.assertIn("presses.mat", message)
            self.assertIn(field, message)
        _, code, message = self.read(good, score="2:4")
        self.assertEqual(code, 2)
        self.assertIn("2:4", message)


if __name__ == "__main__":
    unittest.main()
