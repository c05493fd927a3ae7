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

# ---- the study of README.md's "Studies" (its TOML block; a few minutes)
sed -n '/^## Studies/,/^## Pictures/p' "$root/README.md" \
  | awk '/^```toml/{f=1; next} /^```/{f=0} f' > eos.toml
hardspheres sweep eos.toml
hardspheres plot sweep eos/results.parquet --x packing --y Z -o eos-study.png

mv viewer.png still.png inside.png conservation.png speeds.png eos.png eos-study.png "$root/docs/images/"
ls -l "$root"/docs/images/*.png
