#!/usr/bin/python3
"""The hostile-input corpus: recordings that once crashed, hung, exhausted memory, read outside
the input or gave misleading verdicts, each with the error kind fogpipe must name. Written with
h5py + numpy (seeded) into a folder, so the corpus is generated, never stored.

    hostile_corpus.py FOLDER        writes the corpus and prints "file<TAB>kind" lines

Imported by hostile_inputs_test.py and scripts/fuzz_campaign.py.
"""
import os
import struct
import stat
import sys

import h5py
import numpy as np


def write_valid(path, seed, n=2000, rate_hz=100.0, axes=1, units="deg/h"):
    """White noise plus a slow random walk, in deg/h: analysable in well under a second."""
    rng = np.random.default_rng(seed)
    cols = [0.3 * rng.standard_normal(n) + np.cumsum(0.01 * rng.standard_normal(n)) + 0.02 * a
            for a in range(axes)]
    data = np.stack(cols, axis=1) if axes > 1 else cols[0]
    with h5py.File(path, "w") as f:
        f.attrs["sample_rate_hz"] = rate_hz
        d = f.create_dataset("rate", data=data)
        d.attrs["units"] = units


def corrupt_units_heap(path, offset=26, value=0xFF):
    """Overwrites one byte of the global heap object that holds the variable-length `units`
    string (h5py writes str attributes as variable-length strings, kept in a global heap
    collection, signature "GCOL"). The object header is: index (2 bytes), reference count (2),
    reserved (4), size (8) at GCOL + 16; the first object's size is at GCOL + 24..31. A size byte
    of 0xFF at GCOL + 26 makes HDF5 1.10.8's H5HG_read copy 16 MiB past the collection: SIGSEGV
    under H5T__conv_vlen <- H5Aread. A size of 0 at GCOL + 24 makes it loop forever."""
    with open(path, "r+b") as f:
        data = bytearray(f.read())
        at = data.find(b"GCOL")
        assert at >= 0, path + ": no global heap"
        data[at + offset] = value
        f.seek(0)
        f.write(data)


def heap_objects(data):
    """(index, offset) of every object of the first global heap collection ("GCOL"): each object
    header is index (2 bytes), reference count (2), reserved (4), size (8), then the data padded to
    8 bytes; the collection's own size is at GCOL + 8."""
    at = data.find(b"GCOL")
    if at < 0:
        return []
    end = at + struct.unpack("<Q", data[at + 8:at + 16])[0]
    objects, p = [], at + 16
    while p + 16 <= end:
        index = struct.unpack("<H", data[p:p + 2])[0]
        size = struct.unpack("<Q", data[p + 8:p + 16])[0]
        if index == 0:
            break
        objects.append((index, p))
        p += 16 + (size + 7) // 8 * 8
    return objects


def write_corpus(folder):
    """Returns {path: expected error kind}. Valid files are not in the map."""
    bad = {}

    def name(n):
        return os.path.join(folder, n)

    # 1. one corrupted byte in the units attribute's global heap: crash, then a hang.
    p = name("heap_crash.h5")
    write_valid(p, 101)
    corrupt_units_heap(p)
    bad[p] = "reader_crashed"
    p = name("heap_loop.h5")
    write_valid(p, 102)
    corrupt_units_heap(p, offset=24, value=0)
    bad[p] = "reader_timeout"

    # 2. poison dims: declared and never written; dims beyond limits; more than the file holds.
    p = name("poison_unwritten.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", shape=(2**30, 2**31 // 1024), dtype="f8", chunks=(1024, 1))
        d.attrs["units"] = "deg/h"
    bad[p] = "implausible_shape"
    p = name("poison_contiguous_unwritten.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", shape=(5000,), dtype="f8")
        d.attrs["units"] = "deg/h"
    bad[p] = "unwritten_dataset"
    p = name("poison_2e60.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", shape=(2**60,), dtype="f8", chunks=(1024,))
        d[:1024] = np.random.default_rng(3).standard_normal(1024)
        d.attrs["units"] = "deg/h"
    bad[p] = "implausible_shape"
    p = name("poison_3e8.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", shape=(300_000_000,), dtype="f8", chunks=(1000,))
        d[:1000] = np.random.default_rng(4).standard_normal(1000)
        d.attrs["units"] = "deg/h"
    bad[p] = "implausible_shape"

    # 4. denormal and extreme magnitudes.
    for label, scale in (("denormal", 1e-310), ("tiny", 1e-300), ("huge", 1e300),
                         ("riccati_overflow", 1e90)):
        p = name(f"magnitude_{label}.h5")
        write_valid(p, 5)
        with h5py.File(p, "a") as f:
            f["rate"][...] = np.random.default_rng(6).standard_normal(2000) * scale
        bad[p] = "extreme_magnitude"

    # 5. a FIFO named *.h5, and /rate stored externally in a FIFO.
    p = name("fifo.h5")
    os.mkfifo(p)
    bad[p] = "not_regular_file"
    fifo_data = name("raw_fifo.bin")
    os.mkfifo(fifo_data)
    p = name("external_fifo.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", shape=(2000,), dtype="f8", external=[(fifo_data, 0, 16000)])
        d.attrs["units"] = "deg/h"
    bad[p] = "external_data"

    # 6. reads outside the input: external links, a virtual dataset, external raw storage.
    outside = os.path.join(folder, "outside")
    os.makedirs(outside, exist_ok=True)
    secret = os.path.join(outside, "secret.dat")
    write_valid(secret, 7)
    p = name("elink_absolute.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        f["rate"] = h5py.ExternalLink(os.path.abspath(secret), "/rate")
    bad[p] = "external_data"
    p = name("elink_relative_aux.h5")
    write_valid(p, 8)
    with h5py.File(p, "a") as f:
        f["aux"] = h5py.ExternalLink("outside/secret.dat", "/")
    bad[p] = "external_data"
    p = name("elink_behind_soft.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        f["hidden"] = h5py.ExternalLink(os.path.abspath(secret), "/rate")
        f["rate"] = h5py.SoftLink("/hidden")
    bad[p] = "external_data"
    p = name("soft_cycle.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        f["a"] = h5py.SoftLink("/rate")
        f["rate"] = h5py.SoftLink("/a")
    bad[p] = "wrong_type"
    p = name("virtual.h5")
    layout = h5py.VirtualLayout(shape=(2000,), dtype="f8")
    layout[:] = h5py.VirtualSource(os.path.abspath(secret), "rate", shape=(2000,))
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_virtual_dataset("rate", layout)
        d.attrs["units"] = "deg/h"
    bad[p] = "external_data"
    passwd = os.path.join(outside, "passwd_copy.bin")
    with open(passwd, "wb") as out:
        out.write(os.urandom(16000))
    p = name("external_raw.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", shape=(2000,), dtype="f8", external=[(passwd, 0, 16000)])
        d.attrs["units"] = "deg/h"
    bad[p] = "external_data"

    # 10. misleading verdicts: a sample rate of 5e-324 Hz, a transposed (64, 2000) matrix.
    p = name("rate_5e-324.h5")
    write_valid(p, 9)
    with h5py.File(p, "a") as f:
        f.attrs["sample_rate_hz"] = 5e-324
    bad[p] = "bad_sample_rate"
    p = name("transposed.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", data=np.random.default_rng(10).standard_normal((64, 2000)))
        d.attrs["units"] = "deg/h"
    bad[p] = "wrong_shape"
    # A chunked /rate of which only the first chunk was written (a recording cut short): the
    # rest would read as fill-value zeros.
    p = name("partly_written.h5")
    with h5py.File(p, "w") as f:
        f.attrs["sample_rate_hz"] = 100.0
        d = f.create_dataset("rate", shape=(2000,), dtype="f8", chunks=(100,))
        d[:100] = np.random.default_rng(11).standard_normal(100)
        d.attrs["units"] = "deg/h"
    bad[p] = "unwritten_dataset"
    return bad


if __name__ == "__main__":
    os.makedirs(sys.argv[1], exist_ok=True)
    for path, kind in sorted(write_corpus(sys.argv[1]).items()):
        print(f"{path}\t{kind}")


def write_suspects(folder):
    """Valid files whose samples are suspect: analysed, and flagged with a warning naming where.
    Returns {path: a phrase the warning must contain}."""
    suspect = {}

    def name(n):
        return os.path.join(folder, n)

    # One chunk, or contiguous storage, only partly filled: nothing in the metadata shows it, the
    # unwritten tail reads as the fill value (0, or what the writer set).
    for label, chunks, fill in (("one_chunk", (2000,), None), ("contiguous", None, None),
                                ("one_chunk_fill_7", (2000,), 7.0)):
        p = name(f"partly_filled_{label}.h5")
        with h5py.File(p, "w") as f:
            f.attrs["sample_rate_hz"] = 100.0
            d = f.create_dataset("rate", shape=(2000,), dtype="f8", chunks=chunks, fillvalue=fill)
            d[:1500] = np.random.default_rng(12).standard_normal(1500)
            d.attrs["units"] = "deg/h"
        suspect[p] = "samples 1500..1999 (t = 15..20 s) all equal"
    # A frozen output in the middle of the record.
    p = name("frozen_output.h5")
    write_valid(p, 13)
    with h5py.File(p, "a") as f:
        x = f["rate"][...]
        x[700:900] = x[699]
        f["rate"][...] = x
    suspect[p] = "samples 699..899 (t = 6.99..9 s)"
    return suspect

