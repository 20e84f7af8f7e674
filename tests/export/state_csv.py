# `clothsim run --state`'s CSV as (positions, velocities), lists of [x, y, z] per particle;
# plain Python, so that Blender's and ParaView's own interpreters read it too.
import csv
import struct


def read_state(path):
    x, v = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            x.append([float(row[k]) for k in ("x", "y", "z")])
            v.append([float(row[k]) for k in ("vx", "vy", "vz")])
    return x, v


def worst_float32_gap(got, want):
    """Largest |got - want| after rounding both to float32, in units of float32's spacing at want:
    0 means what was read is the float32 of the state's double (a text format's 9 digits read
    back as a double round to that float)."""
    worst = 0.0
    for g, w in zip(got, want):
        for a, b in zip(g, w):
            a32, b32 = float32(a), float32(b)
            ulp = max(abs(b32), 1e-30) * 2.0 ** -23
            worst = max(worst, abs(a32 - b32) / ulp)
    return worst


def float32(value):
    return struct.unpack("<f", struct.pack("<f", value))[0]
