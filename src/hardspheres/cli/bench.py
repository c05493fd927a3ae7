"""``hardspheres bench``: the collisions per second of one system, printed."""

import json

from ..core.bench import bench


def main(n, packing, collisions, **kw):
    """Print the figures, the JSON object last."""
    res = bench(n, packing, collisions, **kw)
    ens = res["enskog_collision_rate"]
    print(
        f"N={n} packing={packing}: setup {res['setup_s']:.1f} s (generation "
        f"{res['generate_s']:.1f} s; CPU {res['setup_cpu_s']:.1f} s), peak "
        f"{res['setup_peak_rss_mb']:.0f} MB after setup"
    )
    enskog = f" (Enskog-CS {ens:.4g})" if ens else ""
    if res["warmup_blocks"]:
        print(
            f"warm-up: {res['warmup_per_sphere']:g} collisions per sphere in "
            f"{res['warmup_s']:.1f} s, {'settled' if res['settled'] else 'NOT settled'}; "
            f"per sphere per unit time over its last block: collisions "
            f"{res['warmup_collision_rate']:.4g}{enskog}, cell crossings "
            f"{res['warmup_crossing_rate']:.4g}"
        )
    else:
        print("warm-up: none (the lattice as built is timed, not a fluid)")
    print(
        f"timed: per sphere per unit time, collisions {res['collision_rate']:.4g}{enskog}, "
        f"cell crossings {res['crossing_rate']:.4g}"
    )
    print(
        f"timed: {res['collisions_per_s'] / 1e6:.3f} M collisions/s, "
        f"{res['events_per_s'] / 1e6:.3f} M events/s, peak {res['peak_rss_mb']:.0f} MB"
    )
    print(json.dumps(res))
    return res
