#!/usr/bin/python3
"""Writes the importer fixtures with the tools that write such files in the wild.

Run from tests/data with Debian's python3-numpy, python3-scipy and python3-h5py:
    /usr/bin/python3 make_fixtures.py
Input: frames.csv (3 frames of 208 values, rotating order) and reference.csv (1 frame), both made
by `eitbench forward` on the medium mesh. The outputs are committed, so the tests need no Python.
"""
import numpy as np
import scipy.io
import h5py

L = 16
frames = np.loadtxt("frames.csv", delimiter=",", ndmin=2)      # 3 x 208, rotating
reference = np.loadtxt("reference.csv", delimiter=",", ndmin=1)  # 208

# Index maps of SPEC section 1.
rot = [(d, (d + 2 + k) % L) for d in range(L) for k in range(L - 3)]
asc = [(d, m) for d in range(L) for m in range(L) if m not in ((d - 1) % L, d, (d + 1) % L)]
red = [(d, m) for d in range(L) for m in range(d + 2, L) if not (d == 0 and m == L - 1)]
pos = {p: i for i, p in enumerate(rot)}
ascending = frames[:, [pos[p] for p in asc]]
reduced = frames[:, [pos[p] for p in red]]
square = np.zeros((frames.shape[0], L * L))  # L^2 layout: (d, m) at d * L + m, unused entries zero
for i, (d, m) in enumerate(rot):
    square[:, d * L + m] = frames[:, i]

np.save("frames_rotating.npy", frames)                      # float64, C order, (3, 208)
np.save("frames_ascending_f4.npy", ascending.astype(np.float32))
np.save("frames_fortran.npy", np.asfortranarray(frames))    # fortran_order: True
np.save("reference.npy", reference)                         # 1-D (208,)
np.savez_compressed("frames_compressed.npz", frames=frames, reference=reference)
np.savez("frames_plain.npz", reduced=reduced)
np.savetxt("frames_square.csv", square, delimiter=",")
np.savetxt("frames_reduced.csv", reduced, delimiter=",")
np.savetxt("frames_ascending.csv", ascending, delimiter=",")

# MATLAB v5, compressed, as EIDORS and instruments write it: one frame a column.
scipy.io.savemat("frames_v5.mat", {"vv": frames.T, "vh": reference.reshape(-1, 1)}, do_compression=True)
scipy.io.savemat("frames_v5_plain.mat", {"data": frames}, do_compression=False)

# MATLAB v7.3: HDF5 with a 512-byte user block holding MATLAB's header, arrays stored transposed,
# and a MATLAB_class attribute on each variable.
with h5py.File("frames_v73.mat", "w", userblock_size=512) as f:
    d = f.create_dataset("vv", data=frames)  # MATLAB reads this as 208 x 3: one frame a column
    d.attrs["MATLAB_class"] = np.bytes_("double")
    r = f.create_dataset("vh", data=reference.reshape(1, -1))
    r.attrs["MATLAB_class"] = np.bytes_("double")
header = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Sat Nov 21 11:00:00 2026 HDF5 schema 1.00 ."
with open("frames_v73.mat", "r+b") as f:
    f.write(header.ljust(116, b" ") + b"\x00" * 8 + b"\x00\x02" + b"IM" + b"\x00" * (512 - 128))
print("wrote fixtures")

# Bad inputs written by the same tools: the importer must name what is wrong.
scipy.io.savemat("bad_struct.mat", {"vv": {"meas": frames.T}}, do_compression=True)  # a struct, not a matrix
np.save("bad_bigendian.npy", frames.astype(">f8"))
nan_frames = frames.copy()
nan_frames[1, 7] = np.nan
np.save("bad_nan.npy", nan_frames)
np.save("bad_length.npy", frames[:, :103])
np.savez("bad_two_arrays.npz", a=frames, b=frames)
print("wrote bad fixtures")
