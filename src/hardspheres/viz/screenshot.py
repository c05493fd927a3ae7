"""Pictures of viewer pages: headless Chromium saves a PNG of a page.

:func:`screenshot` opens a page written by
:func:`hardspheres.viz.viewer.write_viewer` in headless Chromium (Debian's
``chromium`` driven by the Python ``playwright`` package) and saves a PNG::

    from hardspheres.viz.screenshot import screenshot
    screenshot("run.html", "run.png")
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import PictureError

# Headless Chromium as Debian ships it (software WebGL through SwiftShader);
# playwright drives it, its own browser downloads are never used.
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--use-gl=angle",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
]


def find_chromium() -> str | None:
    """Path of a Chromium executable (``/usr/bin/chromium`` or on PATH), or ``None``."""
    import os
    import shutil

    if os.access("/usr/bin/chromium", os.X_OK):
        return "/usr/bin/chromium"
    return shutil.which("chromium") or shutil.which("chromium-browser")


def screenshot(
    html_path: str | os.PathLike[str],
    png_path: str | os.PathLike[str],
    size: tuple[int, int] = (960, 640),
    play_seconds: float = 1.0,
    timeout: float = 60.0,
) -> Path:
    """Open a viewer page in headless Chromium, play it a while, save a PNG of the page.

    Args:
        html_path: a page written by :func:`write_viewer`.
        png_path: the ``.png`` to write, ``size`` pixels.
        size: ``(width, height)`` of the browser window [pixels].
        play_seconds: how long the animation plays before the picture
            (0: the first frame).
        timeout: give up when the page has not drawn after this many seconds.

    Returns:
        ``png_path`` as a :class:`pathlib.Path`.

    Raises:
        ValueError: Chromium or the Python ``playwright`` package is
            missing, or the page did not start (the message says which).

    Longer than 80 lines: one browser session, start to close, in one
    ``try``, and an annotated signature of a line per parameter.
    """
    html_path, png_path = Path(html_path).resolve(), Path(png_path)
    width, height = (int(x) for x in size)
    if width <= 0 or height <= 0:
        raise PictureError(f"screenshot: bad size {size}; give (width, height) in pixels, both > 0")
    chromium = find_chromium()
    if chromium is None:
        raise PictureError(
            "screenshot: needs Chromium, which was not found (/usr/bin/chromium "
            "or chromium on PATH; e.g. apt-get install chromium)"
        )
    from ..extras import need

    sync_api = need("playwright.sync_api", "a screenshot (its browser download is not needed)")
    PlaywrightError, sync_playwright = sync_api.Error, sync_api.sync_playwright
    errors = []
    try:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS, headless=True)
            try:
                page = browser.new_page(viewport={"width": width, "height": height})
                page.on("pageerror", lambda exc: errors.append(str(exc)))
                page.set_default_timeout(timeout * 1000)
                page.goto(html_path.as_uri())
                page.wait_for_function(
                    "window.viewerReady === true || "
                    "getComputedStyle(document.getElementById('message'))"
                    ".display !== 'none'",
                    timeout=timeout * 1000,
                )
                if page.locator("#message").is_visible():
                    raise PictureError(f"screenshot: {page.locator('#message').inner_text()}")
                # through the page's own controls, not clicks: a click waits
                # for the page to settle, which a page of 20000 spheres drawn
                # by software WebGL may not do within playwright's timeout
                # (the first frames of a software renderer are slow: wait for a
                # few before playing, and for a few more before pausing)
                page.wait_for_function("(window.viewerTicks || 0) >= 3")
                if play_seconds > 0 and page.evaluate("window.viewerState.playing") is False:
                    page.evaluate("window.viewerControl.setPlaying(true)")
                    ticks = page.evaluate("window.viewerTicks")
                    page.wait_for_timeout(play_seconds * 1000)
                    page.wait_for_function(f"window.viewerTicks >= {ticks + 3}")
                    # pause: the picture shows the Play button
                    page.evaluate("window.viewerControl.setPlaying(false)")
                page.wait_for_timeout(100)
                from ..fileio import atomic_path

                with atomic_path(png_path) as tmp:
                    page.screenshot(path=tmp, type="png", timeout=timeout * 1000)
            finally:
                browser.close()
    except PlaywrightError as e:
        first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        more = f" (page errors: {'; '.join(errors)})" if errors else ""
        raise PictureError(f"screenshot: Chromium failed: {first}{more}") from None
    return png_path
