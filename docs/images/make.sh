#!/usr/bin/env bash
# Makes the pictures in README.md (docs/images/*.png) with hardspheres' own
# commands: the lines between "picture commands" below are README's, verbatim.
# Run from anywhere in a checkout with the package installed:
#   bash docs/images/make.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
ln -s "$root/docs" docs   # for docs/validation.csv

# ---- picture commands (README.md, "Pictures")
hardspheres generate --n 400 --container 10 --packing 0.25 --seed 1 > scn.txt
hardspheres run scn.txt --container 10 --until 10 --trajectory run.gsd --every 0.05 --events
hardspheres view run.gsd -o viewer.html --title "400 spheres, phi = 0.25" --screenshot viewer.png
hardspheres render run.gsd -o still.png
hardspheres render run.gsd -o inside.png --slice 0
hardspheres plot conservation run.gsd -o conservation.png
hardspheres plot speeds run.gsd -o speeds.png
hardspheres plot eos docs/validation.csv -o eos.png
# ---- end of picture commands

# ---- dense picture commands (README.md, "Dense matter"; a few minutes)
hardspheres generate --n 1000 --box 18 --packing 0.3 --seed 1 > fluid.txt
hardspheres compress fluid.txt --box 18 --packing 0.74 --rate 0.01 --pressure 1e4 -o jammed.txt
hardspheres view jammed.txt --box 18 --until 0.01 --every 0.001 --color q6 -o jammed.html --title "1000 spheres, fast compression: jammed" --screenshot jammed_q6.png --size 960x720
hardspheres generate --n 500 --box 14 --packing 0.3 --seed 1 > fluid500.txt
hardspheres compress fluid500.txt --box 14 --packing 0.56 --rate 1e-3 -o dense.txt
hardspheres run dense.txt --box 14 --until 250 --checkpoint crystal.npz
hardspheres run --resume crystal.npz --until 252 --trajectory crystal.gsd --every 0.1
hardspheres view crystal.gsd --color q6 -o crystal.html --title "500 spheres, slow compression to 0.56 and a run: a crystal" --screenshot crystal_q6.png --size 960x720
# ---- end of dense picture commands

# ---- the study of README.md's "Studies" (its TOML block; a few minutes)
sed -n '/^## Studies/,/^## Pictures/p' "$root/README.md" \
  | awk '/^```toml/{f=1; next} /^```/{f=0} f' > eos.toml
hardspheres sweep eos.toml
hardspheres plot sweep eos/results.parquet --x packing --y Z -o eos-study.png

# ---- README.md's "Hard disks" block (its Python, verbatim; about 10 s of CPU)
sed -n '/^## Hard disks/,/^## Speed/p' "$root/README.md" \
  | awk '/^```python/{f=1; next} /^```/{f=0} f' > disks.py
python3 disks.py

mv disks.png viewer.png still.png inside.png conservation.png speeds.png eos.png eos-study.png \
  jammed_q6.png crystal_q6.png "$root/docs/images/"
ls -l "$root"/docs/images/*.png
