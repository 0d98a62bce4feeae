#!/usr/bin/env python3
"""scripts/ktc_baseline.py's own parts, without the challenge's code: the levels it accepts, and a
data folder it refuses (exit 2, the folder and what is missing named)."""
import contextlib
import io
import os
import sys
import tempfile
import unittest
import argparse

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import ktc_baseline as kb  # noqa: E402


class Levels(unittest.TestCase):
    def test_ranges_and_single_levels(self):
        self.assertEqual(kb.level_range("1-7"), list(range(1, 8)))
        self.assertEqual(kb.level_range("3"), [3])
        for bad in ["0-2", "5-8", "4-3"]:
            with self.assertRaises(argparse.ArgumentTypeError):
                kb.level_range(bad)


class DataFolder(unittest.TestCase):
    def refused(self, names):
        with tempfile.TemporaryDirectory() as folder:
            for name in names:
                open(os.path.join(folder, name), "w").close()
            stderr = io.StringIO()
            with contextlib.redirect_stderr(stderr):
                try:
                    return kb.samples_in(folder), None
                except SystemExit as exit:
                    self.assertEqual(exit.code, 2)
                    self.assertIn(folder, stderr.getvalue())
                    return None, stderr.getvalue()

    def test_samples_in_name_order(self):
        names = ["ref.mat"] + [f"data{n}.mat" for n in (10, 2, 1)] + [f"true{n}.mat" for n in (1, 2, 10)]
        self.assertEqual(self.refused(names)[0], [1, 2, 10])

    def test_what_is_missing_is_named(self):
        self.assertIn("ref.mat", self.refused(["data1.mat", "true1.mat"])[1])
        self.assertIn("dataN.mat", self.refused(["ref.mat"])[1])
        self.assertIn("true2.mat", self.refused(["ref.mat", "data1.mat", "true1.mat", "data2.mat"])[1])


if __name__ == "__main__":
    unittest.main()
