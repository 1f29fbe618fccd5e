"""The source files a gyro lab hands to `fogpipe import`, written with numpy and h5py: a CSV table
and a MATLAB v7.3 file. Shared by import_test.py and walkthrough_test.py (imported from beside
them)."""
import h5py
import numpy as np


def gyro_deg_h(seed, n, axes=3):
    """White noise + rate random walk + bias per axis, deg/h (navigation-grade levels), [n, axes]."""
    rng = np.random.default_rng(seed)
    white = 0.3 * rng.standard_normal((n, axes))
    walk = np.cumsum(0.001 * rng.standard_normal((n, axes)), axis=0)
    return white + walk + np.array([0.02, -0.05, 15.04])[:axes]


def write_csv(path, data, temperature, rate_hz):
    """Columns t (s, at rate_hz), gx, gy, gz (the three columns of `data`) and temp."""
    t = np.arange(len(data)) / rate_hz
    table = np.column_stack([t, data, temperature])
    # %.17g writes every float64 so that it reads back to the same bits.
    np.savetxt(path, table, fmt="%.17g", delimiter=",", header="t,gx,gy,gz,temp", comments="")


def write_mat(path, name, stored, sample_rate_hz):
    """A MATLAB v7.3 file: variable `name` holding `stored` as HDF5 holds it (MATLAB's N x A matrix
    is HDF5 [A, N], column-major) and the sample rate in variable fs, each with its MATLAB_class,
    behind the 512-byte user block with MATLAB's header."""
    with h5py.File(path, "w", userblock_size=512) as f:
        d = f.create_dataset(name, data=np.ascontiguousarray(stored))
        d.attrs["MATLAB_class"] = np.bytes_("double")
        fs = f.create_dataset("fs", data=np.array([[sample_rate_hz]]))
        fs.attrs["MATLAB_class"] = np.bytes_("double")
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Sun Mar  1 08:00:00 2026 "
                 b"HDF5 schema 1.00 .")
