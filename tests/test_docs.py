"""The documentation site: every public name has an API page; a small site builds and renders.

``.ci/run`` builds the whole site with warnings as errors
(``python -m sphinx -W -b html docs docs/_build/html``).  These tests build
a smaller copy (the API reference, the user guide and the first tutorial,
executed) in a temporary folder, check that every public name has its page,
and open the index and the executed tutorial in headless Debian Chromium.
"""

import ast
import importlib
import inspect
import os
import pkgutil
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hardspheres as hs

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
CHROMIUM = "/usr/bin/chromium"
TUTORIAL = "01-first-simulation"

pytest.importorskip("sphinx", reason="the docs extra is missing (pip install -e '.[docs]')")
pytest.importorskip("myst_nb", reason="the docs extra is missing (pip install -e '.[docs]')")


def internal_modules():
    """docs/conf.py's ``INTERNAL_MODULES``: the modules without an API page (the commands, the engine's insides)."""
    tree = ast.parse((DOCS / "conf.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            getattr(t, "id", "") == "INTERNAL_MODULES" for t in node.targets
        ):
            return ast.literal_eval(node.value)
    raise AssertionError("docs/conf.py has no INTERNAL_MODULES")


def _internal(name, internal):
    return any(name == m or name.startswith(m + ".") for m in internal)


def public_subpackages():
    """Every module of the package with an API page: no part of its name starts with ``_``, not internal."""
    internal = internal_modules()
    out = []
    for m in pkgutil.walk_packages(hs.__path__, "hardspheres."):
        if not any(part.startswith("_") for part in m.name.split(".")) and not _internal(m.name, internal):
            out.append(m.name)
    return out


def test_property_summaries_are_not_read_as_types():
    """Napoleon reads a property's (or a ``#:`` constant's) first line ``A: b`` as ``type: description``.

    The page would then show "Type: A" (docs/check_html.py fails the built site on it).
    """
    from sphinx.ext.napoleon import Config
    from sphinx.ext.napoleon.docstring import GoogleDocstring
    from sphinx.pycode import ModuleAnalyzer

    split = GoogleDocstring([""], Config())._partition_field_on_colon
    bad = []
    for modname in public_subpackages():
        mod = importlib.import_module(modname)
        for cls in vars(mod).values():
            if not inspect.isclass(cls) or cls.__module__ != modname:
                continue
            for name, attr in vars(cls).items():
                if isinstance(attr, property) and attr.__doc__:
                    first = inspect.cleandoc(attr.__doc__).splitlines()[0]
                    _type, colon, desc = split(first)
                    if colon and desc:
                        bad.append(f"{modname}.{cls.__name__}.{name}: {first!r}")
        # constants and class attributes documented by ``#:`` comments: read the same way
        analyzer = ModuleAnalyzer.for_module(modname)
        for (owner, name), lines in analyzer.find_attr_docs().items():
            first = next((line for line in lines if line.strip()), "")
            _type, colon, desc = split(first)
            if colon and desc and not name.startswith("_"):
                bad.append(f"{modname}.{owner}{'.' if owner else ''}{name}: {first!r}")
    assert bad == [], "first lines with a colon (rephrase without one):\n" + "\n".join(bad)


#: a reference to a tutorial the test site leaves out (every one but TUTORIAL; 01-99)
OTHER_TUTORIAL = re.compile(r"tutorials/\d\d-")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """A copy of docs/ with one tutorial, built to HTML (its notebook executed)."""
    tmp = tmp_path_factory.mktemp("site")
    src = tmp / "docs"
    shutil.copytree(DOCS, src, ignore=shutil.ignore_patterns("_build", "generated"))
    for f in ("CHANGELOG.md", "CONTRIBUTING.md", "README.md"):
        shutil.copy(ROOT / f, tmp / f)
    (src / "api" / "index.rst").unlink(missing_ok=True)  # conf.py writes it from __all__
    for nb in (src / "tutorials").glob("[0-9]*.md"):
        if nb.stem != TUTORIAL:
            nb.unlink()
    env = dict(os.environ)
    # the package as the tests import it (the checkout or the installed wheel)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(Path(hs.__file__).parents[1])] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    )
    out = tmp / "html"
    res = subprocess.run(
        [sys.executable, "-m", "sphinx", "-q", "-b", "html", str(src), str(out)],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp,
    )
    assert res.returncode == 0, res.stderr[-4000:]
    # the other tutorials were removed: references to them are the only warnings allowed
    warnings = [
        line for line in res.stderr.splitlines() if "WARNING" in line and not OTHER_TUTORIAL.search(line)
    ]
    assert warnings == [], warnings
    # a quiet build: no kernel's TCP warning, no notebook client's INFO lines (docs/conf.py)
    noise = [line for line in res.stderr.splitlines() if "running over TCP" in line or " INFO " in line]
    assert noise == [], noise
    return out


def _ids(html_dir):
    ids = set()
    for page in (html_dir / "api" / "generated").glob("*.html"):
        ids.update(re.findall(r'<dt class="sig[^"]*" id="([^"]+)"', page.read_text()))
    return ids


def test_every_public_name_has_a_page(site):
    """Each root name has a page of its own; each subpackage's ``__all__`` names are described."""
    ids = _ids(site)
    for name in hs.__all__:
        assert (site / "api" / "generated" / f"hardspheres.{name}.html").exists(), name
        assert f"hardspheres.{name}" in ids, name
    for modname in public_subpackages():
        mod = importlib.import_module(modname)
        assert (site / "api" / "generated" / f"{modname}.html").exists(), f"no page for {modname}"
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            at_root = name in hs.__all__ and getattr(hs, name) is obj
            # a re-export is described once, on its home module's page
            home = f"{getattr(obj, '__module__', modname)}.{getattr(obj, '__qualname__', name)}"
            assert at_root or f"{modname}.{name}" in ids or home in ids, f"{modname}.{name} has no entry"


def test_internal_modules_have_no_page(site):
    """The sidebar lists what scripts use: no command module, no engine insides."""
    generated = {p.stem for p in (site / "api" / "generated").glob("*.html")}
    internal = internal_modules()
    assert not [g for g in generated if _internal(g, internal)]
    index = (site / "api" / "index.html").read_text()
    for name in ("hardspheres.cli.options", "hardspheres.core.reference", "hardspheres.core.engine"):
        assert name not in index, name


def test_built_html_passes_the_site_checks(site):
    """docs/check_html.py (run by .ci/run on the full site): no summary read as a type, no ArrayLike in full."""
    sys.path.insert(0, str(DOCS))
    try:
        import check_html
    finally:
        sys.path.remove(str(DOCS))
    assert check_html.faults(site) == []


def test_tutorial_executed_with_figures(site):
    page = (site / "tutorials" / f"{TUTORIAL}.html").read_text()
    assert "Hansen-Goos" in page and "standard errors" in page  # the cell's printed comparison
    assert page.count("<img") >= 2  # its plots
    assert "Traceback" not in page
    assert 'class="hardspheres-viewer"' in page  # the Simulation ending a cell, as the viewer


def _nonblank(png):
    from PIL import Image

    img = np.asarray(Image.open(png).convert("RGB")).astype(float)
    return len(np.unique(img.reshape(-1, 3), axis=0)), img.std()


def test_index_and_tutorial_render_in_chromium(site, tmp_path):
    if not os.path.exists(CHROMIUM):
        pytest.skip(f"{CHROMIUM} is missing (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="Python playwright is missing")
    from hardspheres.viz.screenshot import CHROMIUM_ARGS

    errors = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_page(viewport={"width": 1100, "height": 800})
            page.on("pageerror", lambda exc: errors.append(f"page error: {exc}"))
            page.goto((site / "index.html").as_uri())
            page.wait_for_load_state("load")
            assert "hardspheres" in page.title()
            shot = tmp_path / "index.png"
            page.screenshot(path=str(shot))
            colours, spread = _nonblank(shot)
            assert colours > 20 and spread > 5, "the index looks blank"

            page.goto((site / "tutorials" / f"{TUTORIAL}.html").as_uri())
            page.wait_for_load_state("load")
            figures = page.locator("img").evaluate_all(
                "els => els.filter(e => e.complete && e.naturalWidth > 100).length"
            )
            assert figures >= 2, "the tutorial's figures did not load"
            fig = page.locator("div.cell_output img").first
            fig.scroll_into_view_if_needed()
            shot = tmp_path / "tutorial.png"
            fig.screenshot(path=str(shot))
            colours, spread = _nonblank(shot)
            assert colours > 50 and spread > 5, "the tutorial's first figure looks blank"

            # the Simulation ending a cell: the viewer inline, drawn offline in its iframe
            viewer = page.locator("div.hardspheres-viewer iframe").first
            viewer.scroll_into_view_if_needed()
            inner = page.frame_locator("div.hardspheres-viewer iframe").first
            inner.locator("canvas").first.wait_for(timeout=30_000)
            page.wait_for_timeout(1500)
            shot = tmp_path / "viewer.png"
            viewer.screenshot(path=str(shot))
            colours, spread = _nonblank(shot)
            assert colours > 100 and spread > 5, "the inline viewer looks blank"
        finally:
            browser.close()
    assert not errors, errors


def test_math_and_wide_tables_render_offline_in_chromium(site):
    """With the network off, the tutorial's math is typeset by the local MathJax (no raw ``\\(``
    left), and the validation pages' wide tables scroll inside the page instead of being cut off."""
    if not os.path.exists(CHROMIUM):
        pytest.skip(f"{CHROMIUM} is missing (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="Python playwright is missing")
    from hardspheres.viz.screenshot import CHROMIUM_ARGS

    requested = []

    def local_only(route):
        if route.request.url.startswith("file:"):
            route.continue_()
        else:
            requested.append(route.request.url)
            route.abort()

    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            context = browser.new_context(offline=True, viewport={"width": 1100, "height": 800})
            context.route("**/*", local_only)
            page = context.new_page()
            page.goto((site / "tutorials" / f"{TUTORIAL}.html").as_uri())
            page.wait_for_load_state("load")
            maths = page.locator("article .math").count()
            assert maths >= 1, "the tutorial has no math to check"
            page.locator("mjx-container").nth(maths - 1).wait_for(timeout=30_000)
            text = page.locator("article").inner_text()
            assert "\\(" not in text and "\\[" not in text and "$$" not in text, "raw LaTeX on the page"

            page.goto((site / "validation" / "disks.html").as_uri())
            page.wait_for_load_state("load")
            clipped = page.evaluate(
                """() => [...document.querySelectorAll('article table')].filter(t => {
                    const box = t.parentElement;
                    const scrolls = getComputedStyle(box).overflowX;
                    return box.scrollWidth > box.clientWidth + 1 && !['auto', 'scroll'].includes(scrolls);
                }).length"""
            )
            assert clipped == 0, f"{clipped} wide tables cut off"
        finally:
            browser.close()
    assert requested == [], f"the pages asked the network for {requested}"
