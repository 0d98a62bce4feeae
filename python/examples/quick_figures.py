"""The README's figure from Python: the quick set's first test samples, the true touch in the top
row, then one row per method (model-based methods at their default hyperparameter, the shape fit,
and the learned reconstructor when a model file is given).

    build/eitbench simulate --preset quick --out quick.h5        # or out/quick/data.h5 of a run
    python3 python/examples/quick_figures.py quick.h5 --model out/quick/models/dnn_d16.pt --out quick.png

Needs matplotlib (Debian: python3-matplotlib) and the eitbench module (README: Python).
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import eitbench

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("data", help="an eitbench data set with a test split")
parser.add_argument("--model", help="a learned model (eitbench train --out)")
parser.add_argument("--samples", type=int, default=6)
parser.add_argument("--out", default="quick_figures.png")
args = parser.parse_args()

data = eitbench.read_dataset(args.data)
test = np.flatnonzero(data["split"] == 2)[: args.samples]
frames, labels = data["differences"][test], data["labels"][test]
rows = [("truth", labels)]
for method in ["tikhonov", "noser", "laplace", "greit", "tv", "shape"]:
    r = eitbench.Reconstructor(method, background=data["background_conductivity"],
                               contact_impedance=data["contact_impedance"], current=data["current"])
    rows.append((method, r.reconstruct(frames)))
if args.model:
    model = eitbench.load_model(args.model)
    rows.append((f"dnn ({model.augment})", model.reconstruct(frames)))

fig, axes = plt.subplots(len(rows), len(test), figsize=(1.6 * len(test), 1.6 * len(rows)))
for row, (name, images) in zip(axes, rows):
    for ax, image in zip(row, images):
        ax.imshow(image, cmap="viridis", vmin=min(0.0, image.min()), vmax=max(image.max(), 1e-9))
        ax.set_xticks([]), ax.set_yticks([])
    row[0].set_ylabel(name, rotation=0, ha="right", va="center")
fig.suptitle("First test samples: the true touch, then one row per method")
fig.tight_layout()
fig.savefig(args.out, dpi=120)
print(f"wrote {args.out}")
