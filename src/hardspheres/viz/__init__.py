"""Pictures: plots, stills and movies, the interactive viewer and its screenshots.

Contract: a picture reads frames, results or tables and writes a file (or
returns matplotlib Axes); it never changes a simulation.  matplotlib, ffmpeg
and the browser are imported or started only when a picture is made.  This
family may import analyses and studies (to plot them) and everything below,
never the commands.

Modules:
    plots: the ``plot`` command's figures (g(r), MSD, equation of state, ...).
    render: stills and movies of frames (matplotlib, ffmpeg).
    viewer: the self-contained three.js page (``_static/`` holds its files).
    screenshot: a viewer page rendered to PNG in headless Chromium.
"""
