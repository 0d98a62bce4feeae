#!/usr/bin/python3
"""Writes the malformed HDF5 data sets of tests/bad_inputs/datasets/ from a valid one.

Usage (Debian's python3-h5py): /usr/bin/python3 make_bad_datasets.py GOOD.h5
GOOD.h5 comes from `eitbench simulate --preset tiny --density coarse --seed 1`; only its first 4
samples are kept. Each output has one defect, named by the file.
"""
import os
import sys

import h5py
import numpy as np

good = sys.argv[1]
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "datasets")
os.makedirs(out, exist_ok=True)
KEEP = 4


def copy(name, change=None):
    path = os.path.join(out, name)
    with h5py.File(good, "r") as src, h5py.File(path, "w") as dst:
        for key, value in src.attrs.items():
            dst.attrs[key] = value
        for key in src:
            data = src[key][()]
            if data.ndim > 0 and key != "reference":
                data = data[:KEEP]
            dst.create_dataset(key, data=data, compression="gzip")
        if change:
            change(dst)
    return path


def replace(dst, key, data):
    del dst[key]
    dst.create_dataset(key, data=data)


copy("wrong_length.h5", lambda f: replace(f, "differences", f["differences"][()][:, :103]))
copy("nan_difference.h5",
     lambda f: replace(f, "differences", np.where(np.arange(104) == 7, np.nan, f["differences"][()])))
copy("inf_frame.h5", lambda f: replace(f, "frames", np.full(f["frames"].shape, np.inf)))
copy("missing_split.h5", lambda f: f.__delitem__("split"))
copy("bad_split_value.h5", lambda f: replace(f, "split", np.array([0, 1, 7, 2], dtype=np.int32)))
copy("zero_electrodes.h5", lambda f: f.attrs.__setitem__("electrodes", 0))
copy("text_electrodes.h5", lambda f: f.attrs.__setitem__("electrodes", "sixteen"))
copy("labels_wrong_size.h5", lambda f: replace(f, "labels", f["labels"][()][:, :32, :32]))
copy("empty.h5", lambda f: (replace(f, "differences", np.zeros((0, 104))),
                            replace(f, "frames", np.zeros((0, 208))),
                            replace(f, "split", np.zeros(0, dtype=np.int32))))
copy("electrodes_array.h5", lambda f: f.attrs.__setitem__("electrodes", np.array([16, 16, 16])))
copy("image_size_huge.h5", lambda f: f.attrs.__setitem__("image_size", 1e300))
copy("bad_circle_count.h5",
     lambda f: replace(f, "circle_count", np.array([1, 9, 1, 1], dtype=np.int32)))


def huge(f):  # a header that declares 10^12 frames in a file of a few kilobytes
    del f["differences"]
    f.create_dataset("differences", shape=(10**12, 104), dtype="f8", chunks=(1, 104))


copy("huge_dimensions.h5", huge)
path = copy("truncated.h5")
size = os.path.getsize(path)
with open(path, "r+b") as f:
    f.truncate(size // 2)
with open(os.path.join(out, "not_hdf5.h5"), "w") as f:
    f.write("this is text, not HDF5\n")
open(os.path.join(out, "zero_bytes.h5"), "w").close()
