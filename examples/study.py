"""Run a study file on Dask from Python and compare its Z with Hansen-Goos.

    python examples/study.py examples/eos.toml [--serial] [--scheduler tcp://HOST:8786]
"""

import argparse

import numpy as np

import hardspheres as hs
from hardspheres import eos

parser = argparse.ArgumentParser()
parser.add_argument("study")
parser.add_argument("--serial", action="store_true", help="in this process, without Dask")
parser.add_argument("--scheduler", help="an existing Dask scheduler's address")
args = parser.parse_args()

client = None
if args.scheduler:
    from distributed import Client

    client = Client(args.scheduler)
df = hs.sweep(args.study, client=client, serial=args.serial)
for phi, rows in df.groupby("packing"):
    z = rows["Z"].mean()
    err = np.sqrt(np.sum(rows["Z_err"] ** 2)) / len(rows)
    print(f"phi = {phi:.2f}: Z = {z:.4f} +- {err:.4f}, Hansen-Goos {float(eos.hansen_goos(phi)):.4f}")
