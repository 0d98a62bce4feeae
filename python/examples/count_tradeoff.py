"""What choosing shape-linear's BIC penalty by count accuracy would buy and cost: the linear fits
for every K are made once a frame (Reconstructor.fits_by_count), and each penalty's K is chosen
from them, on the test split's four-touch frames and on training frames with one to three touches.
(`shape` chooses its K on FEM refits instead, which this script does not make.)

    build/eitbench simulate --preset quick --out quick.h5        # or out/quick/data.h5 of a run
    python3 python/examples/count_tradeoff.py quick.h5 --snr 30

The quick set's validation and test frames all hold four touches, so a penalty chosen there by
count accuracy learns to answer four; the mixed frames show what that costs a sensor whose frames
hold fewer (docs/reconstructors.md).
"""
import argparse

import numpy as np

import eitbench

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("data", help="an eitbench data set with circles and a test split")
parser.add_argument("--snr", type=float, help="add white noise at this SNR (dB), seeded")
parser.add_argument("--mixed", type=int, default=50, help="training frames of each count 1..3")
parser.add_argument("--penalties", default="4,2,1,0.25,0.1,0.03,0.01")
args = parser.parse_args()

data = eitbench.read_dataset(args.data)
frames, split, counts = data["differences"], data["split"], data["circle_count"]
rng = np.random.default_rng(7)


def noisy(x):
    if args.snr is None:
        return x
    return x + rng.normal(0, np.sqrt(np.mean(x**2)) / 10 ** (args.snr / 20), x.shape)


groups = {"four-touch test": np.flatnonzero(split == 2)}
groups["mixed (1-3) training"] = np.concatenate(
    [np.flatnonzero((split == 0) & (counts == k))[: args.mixed] for k in (1, 2, 3)])
shape = eitbench.Reconstructor("shape-linear", background=data["background_conductivity"],
                               contact_impedance=data["contact_impedance"], current=data["current"])
fits = {}  # group -> [(misfit of each K, squared norm, true count)]
for name, rows in groups.items():
    fits[name] = []
    for i in rows:
        x = noisy(frames[i])
        fits[name].append((np.array([rss for rss, _ in shape.fits_by_count(x)]), x @ x, counts[i]))


def chosen_k(rss, norm2, penalty, floor=1e-2, m=104):
    """The method's BIC (docs/reconstructors.md): misfits below the floor count as the floor."""
    k = np.arange(len(rss))
    return int(np.argmin(m * np.log(np.maximum(rss, floor**2 * norm2) / m)
                         + penalty * 4 * k * np.log(m)))


print(f"shape-linear, {'noise-free' if args.snr is None else f'{args.snr:g} dB'}: "
      "share of frames counted right")
print("| penalty | " + " | ".join(groups) + " |")
print("|---" * (len(groups) + 1) + "|")
for penalty in [float(p) for p in args.penalties.split(",")]:
    right = [np.mean([chosen_k(rss, n2, penalty) == truth for rss, n2, truth in fits[name]])
             for name in groups]
    print(f"| {penalty:g} | " + " | ".join(f"{100 * r:.0f} %" for r in right) + " |")
