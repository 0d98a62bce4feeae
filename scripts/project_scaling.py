#!/usr/bin/env python3
"""A larger run's wall time on N ranks, projected from a sharded run's measured unit costs.

A run made in shards (`mpirun -np N eitbench run ...`, or `run --shard K/N` and `eitbench merge`)
records each shard's set-up and each unit's seconds in RUN/shards/K-of-N/shard.json
(docs/scaling.md). This script scales those costs to a larger run of the same units (the paper
preset's, say) and deals its units to N ranks as `eitbench run` does: unit u to rank u mod N.

- A learned unit costs its trainings' samples times one rate: the measured run's seconds per
  training sample over its learned units together, times --model-cost (the larger run's network's
  seconds per sample over the measured run's, on one core). The larger run's results.json, from
  any device, gives the samples (they do not depend on the device).
- A model-based method's unit (tuning on validation frames, scoring the test frames) scales with the
  validation and test frames. That overstates a method whose cost is mostly fixed (a matrix made
  once), so units measured at the larger size (--measured, shard records such as `run --preset
  paper --data SET --shard K/16` leaves) are taken as measured.
- The set-up (every rank simulates the set) scales with the set's size; the merge (it scores the
  learned models again) with the test frames and --model-cost.

Python's standard library only. Example (docs/scaling.md):

  scripts/project_scaling.py docs/results/scaling-quick docs/results/paper-h100/results.json \\
      --model-cost 2.74 --measured docs/results/scaling-quick/paper-units
"""
import argparse
import glob
import json
import os
import sys


def fail(message):
    sys.exit(f"project_scaling: {message}")


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")


def field(results, path, name):
    try:
        return int(float(results["configuration"][name]))
    except (KeyError, TypeError, ValueError):
        fail(f"{path}: configuration.{name} missing or not a number")


def sizes(results, path):
    """(set size, validation + test frames, test frames) of a run's results.json."""
    train, val, test = (field(results, path, n)
                        for n in ("training_samples", "validation_frames", "test_frames"))
    return train + val + test, val + test, test


def learned_units(results, path):
    """Each learned unit's name, as `eitbench run` names it, and its trainings' samples."""
    train_count = field(results, path, "training_samples")
    try:
        return units_of(results, train_count)
    except (KeyError, TypeError, ValueError) as e:
        fail(f"{path}: training or data_efficiency entries without augment, train_size, budget or "
             f"samples_seen ({e!r})")


def units_of(results, train_count):
    trained = {t["augment"]: t["samples_seen"] for t in results.get("training", [])}
    sweep = {}
    for p in results.get("data_efficiency", []):
        n = p["train_size"]
        if n == train_count and p["budget"] != "equal_steps":
            continue  # the whole set's none and d16 points are the main trainings
        sweep[n] = sweep.get(n, 0) + p["samples_seen"]
    whole = train_count in sweep
    units = [(f"dnn {a}", s) for a, s in trained.items()
             if not (whole and a in ("none", "d16"))]
    if whole:
        joint = trained.get("none", 0) + trained.get("d16", 0) + sweep[train_count]
        units.append((f"dnn none and d16 with the sweep at n={train_count}", joint))
    return units + [(f"sweep n={n}", s) for n, s in sorted(sweep.items()) if n != train_count]


def model_based_methods(results):
    """The model-based methods in the run's order (the order of their rows)."""
    names = []
    for row in results.get("results", []):
        if row.get("augment", "-") == "-" and row["method"] not in names:
            names.append(row["method"])
    return names


def read_shards(run):
    """Every shard record under run/shards/, each checked for the fields used here."""
    records = []
    for path in sorted(glob.glob(os.path.join(run, "shards", "*", "shard.json"))):
        r = load(path)
        try:
            ok = (isinstance(r["index"], int) and float(r["setup_seconds"]) >= 0 and
                  all(isinstance(u["unit"], str) and float(u["seconds"]) >= 0 for u in r["units"]))
        except (KeyError, TypeError, ValueError):
            ok = False
        if not ok:
            fail(f"{path}: not a shard record (index, setup_seconds, units[].unit and .seconds)")
        records.append(r)
    if not records:
        fail(f"{run}: no shards/K-of-N/shard.json (a run made in shards)")
    return records


def unit_seconds(records):
    return {u["unit"]: u["seconds"] for r in records for u in r["units"]}


def project(run, larger_path, model_cost=1.0, measured_at_size=None):
    """The larger run's units in the run's order, each (name, seconds, how), and its set-up, merge."""
    shards = read_shards(run)
    small = load(os.path.join(run, "results.json"))
    large = load(larger_path)
    seconds = unit_seconds(shards)
    at_size = unit_seconds(read_shards(measured_at_size)) if measured_at_size else {}
    small_set, small_frames, small_test = sizes(small, run)
    large_set, large_frames, large_test = sizes(large, larger_path)

    learned = learned_units(small, run)
    missing = [name for name, _ in learned if name not in seconds]
    if missing:
        fail(f"{run}: no shard recorded the unit(s) {', '.join(missing)}")
    per_sample = sum(seconds[n] for n, _ in learned) / sum(s for _, s in learned)

    units = []
    for m in model_based_methods(small):
        if m in at_size:
            units.append((m, at_size[m], "measured"))
        elif m in seconds:
            units.append((m, seconds[m] * large_frames / small_frames, "scaled by frames"))
    units += [(name, per_sample * model_cost * samples, "scaled by samples")
              for name, samples in learned_units(large, larger_path)]
    merge_s = float(small["configuration"]["total_seconds"])
    setup_s = max(r["setup_seconds"] for r in shards)
    return {
        "units": units, "per_sample": per_sample, "frame_ratio": large_frames / small_frames,
        "setup": setup_s * large_set / small_set, "measured_setup": setup_s,
        "merge": merge_s * large_test / small_test * model_cost, "measured_merge": merge_s,
    }


def deal(units, ranks):
    """Unit u to rank u mod N, as `eitbench run --shard K/N` takes its units."""
    return [units[k::ranks] for k in range(ranks)]


def wall(p, ranks):
    """(wall seconds, slowest / mean over the ranks given work) on N ranks."""
    loads = [sum(u[1] for u in mine) for mine in deal(p["units"], ranks)]
    busy = [x for x in loads if x > 0]
    return p["setup"] + max(loads) + p["merge"], max(loads) / (sum(busy) / len(busy))


def duration(seconds):
    if seconds >= 3600:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 60:.0f} min" if seconds >= 60 else f"{seconds:.0f} s"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", help="a run made in shards and merged (results.json, shards/)")
    parser.add_argument("larger", help="the larger run's results.json (its frames and samples)")
    parser.add_argument("--model-cost", type=float, default=1.0,
                        help="the larger run's network's seconds per training sample over the "
                             "measured run's, on one core (default 1: the same network)")
    parser.add_argument("--measured", metavar="RUN",
                        help="shard records of units run at the larger size, taken as measured")
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    args = parser.parse_args()
    if args.model_cost <= 0 or any(n < 1 for n in args.ranks):
        fail("--model-cost must be positive and --ranks at least 1")
    p = project(args.run, args.larger, args.model_cost, args.measured)
    print(f"From {args.run}: set-up {p['measured_setup']:.0f} s, merge {p['measured_merge']:.0f} s, "
          f"{p['per_sample'] * 1e3:.3f} ms a training sample; frames x{p['frame_ratio']:.1f}, "
          f"network x{args.model_cost:g}.\n")
    print("| unit | one core | from |\n|---|---|---|")
    for name, seconds, how in p["units"]:
        print(f"| {name} | {duration(seconds)} | {how} |")
    print(f"| set-up (every rank) | {duration(p['setup'])} | scaled by the set |")
    print(f"| merge | {duration(p['merge'])} | scaled by test frames |\n")
    print("| ranks | wall clock | slowest / mean |\n|---|---|---|")
    for n in args.ranks:
        total, balance = wall(p, n)
        print(f"| {n} | {duration(total)} | {balance:.2f} |")


if __name__ == "__main__":
    main()
