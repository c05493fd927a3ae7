"""A trajectory (GSD) and its pictures: the viewer page, a still, a cut-away, a movie, plots.

    python examples/trajectory_pictures.py [--quick]
    # writes run.gsd, viewer.html, still.png, inside.png, movie.gif, conservation.png, speeds.png
"""

import sys

import hardspheres as hs
from hardspheres.viz.plots import plot_conservation, plot_speeds
from hardspheres.viz.render import render_movie, render_still
from hardspheres.viz.viewer import write_viewer

quick = "--quick" in sys.argv
n, until = (100, 1.0) if quick else (400, 10.0)
ball = hs.SphericalContainer.for_packing(n, 0.25)
sim = hs.Simulation(hs.random_spheres(n, 0.25, ball, seed=1), ball)
with hs.GSDWriter("run.gsd", every=0.05, events=True) as gsd:  # every event between frames, too
    sim.writers.append(gsd)
    sim.run(until=until)
frames = hs.read_trajectory("run.gsd")
print(frames)
write_viewer(frames, "viewer.html", title=f"{n} spheres in a sphere")  # opens offline
render_still(frames, "still.png")
render_still(frames, "inside.png", cut=0.0)  # only the spheres with z <= 0
render_movie(frames, "movie.gif", fps=10, size=(480, 270), max_frames=20 if quick else 200)
plot_conservation(frames, "conservation.png")
plot_speeds(frames, "speeds.png")
print("wrote viewer.html, still.png, inside.png, movie.gif, conservation.png, speeds.png")
