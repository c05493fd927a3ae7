#!/bin/sh
# A/B cost of the image counts: `hardspheres bench --box`, base and new code
# interleaved (the machine is shared: compare medians of pairs run side by side).
# usage: benchmarks/ab_images.sh BASE_SRC NEW_SRC [pairs] [N] [packing] [collisions]
BASE=$1; NEW=$2; PAIRS=${3:-10}; N=${4:-10000}; PHI=${5:-0.3}; COLL=${6:-2000000}
for s in "$BASE" "$NEW"; do  # compile both first
  PYTHONPATH=$s python3 -m hardspheres bench --box --n 1000 --packing $PHI --collisions 1000 >/dev/null
done
i=0
while [ $i -lt $PAIRS ]; do
  for s in "$BASE" "$NEW"; do
    tag=base; [ "$s" = "$NEW" ] && tag=new
    r=$(PYTHONPATH=$s python3 -m hardspheres bench --box --n $N --packing $PHI --collisions $COLL | tail -1)
    echo "$tag $r" | python3 -c "import sys, json; t, j = sys.stdin.read().split(' ', 1); print(t, json.loads(j)['collisions_per_s'])"
  done
  i=$((i+1))
done
