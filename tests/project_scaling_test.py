#!/usr/bin/env python3
"""scripts/project_scaling.py against the measured run it projects from (docs/results/scaling-quick):
projected onto itself, its deal of units to 2 ranks must be the shards' own and its loads their
recorded seconds; one rate a training sample must explain each learned unit; bad input exits
non-zero naming the file."""
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "scripts", "project_scaling.py")
RUN = os.path.join(ROOT, "docs", "results", "scaling-quick")
sys.path.insert(0, os.path.dirname(SCRIPT))
import project_scaling as ps  # noqa: E402


class ProjectScaling(unittest.TestCase):
    def setUp(self):
        self.shards = sorted(ps.read_shards(RUN), key=lambda r: r["index"])
        self.itself = ps.project(RUN, os.path.join(RUN, "results.json"))

    def test_deals_units_as_the_run_dealt_them(self):
        dealt = ps.deal(self.itself["units"], len(self.shards))
        for shard, mine in zip(self.shards, dealt):
            self.assertEqual([u["unit"] for u in shard["units"]], [u[0] for u in mine])
            recorded = sum(u["seconds"] for u in shard["units"])
            self.assertAlmostEqual(sum(u[1] for u in mine) / recorded, 1.0, delta=0.01)

    def test_one_rate_a_sample_explains_each_learned_unit(self):
        seconds = ps.unit_seconds(self.shards)
        rate = self.itself["per_sample"]
        for name, samples in ps.learned_units(ps.load(os.path.join(RUN, "results.json")), RUN):
            self.assertAlmostEqual(seconds[name] / (rate * samples), 1.0, delta=0.03, msg=name)

    def test_more_ranks_never_take_longer_than_the_largest_unit_allows(self):
        largest = max(u[1] for u in self.itself["units"])
        one, _ = ps.wall(self.itself, 1)
        self.assertAlmostEqual(one - self.itself["setup"] - self.itself["merge"],
                               sum(u[1] for u in self.itself["units"]))
        many, _ = ps.wall(self.itself, len(self.itself["units"]))
        self.assertAlmostEqual(many, self.itself["setup"] + largest + self.itself["merge"])

    def test_a_folder_without_shards_is_refused_naming_it(self):
        with tempfile.TemporaryDirectory() as empty:
            r = subprocess.run([sys.executable, SCRIPT, empty, os.path.join(RUN, "results.json")],
                               capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn(empty, r.stderr)

    def test_a_record_without_its_fields_is_refused_naming_it(self):
        with tempfile.TemporaryDirectory() as run:
            record = os.path.join(run, "shards", "0-of-1", "shard.json")
            os.makedirs(os.path.dirname(record))
            with open(record, "w") as f:
                f.write('{"index": 0, "units": [{"unit": "tv"}]}')
            r = subprocess.run([sys.executable, SCRIPT, run, os.path.join(RUN, "results.json")],
                               capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn(record, r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_a_larger_run_without_its_samples_is_refused_naming_it(self):
        with tempfile.TemporaryDirectory() as folder:
            larger = os.path.join(folder, "results.json")
            with open(larger, "w") as f:
                f.write('{"configuration": {"training_samples": "5", "validation_frames": "1", '
                        '"test_frames": "1"}, "training": [{"augment": "none"}]}')
            r = subprocess.run([sys.executable, SCRIPT, RUN, larger], capture_output=True,
                               text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn(larger, r.stderr)
        self.assertNotIn("Traceback", r.stderr)


if __name__ == "__main__":
    unittest.main()
