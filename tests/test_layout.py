"""The package's layout: families in layers, imports running one way only.

The import graph of ``src/hardspheres`` is read with :mod:`ast` (every
``import``, at the top, inside functions and under ``TYPE_CHECKING``), and
must have no circle and no import from a lower family to a higher one.
docs/architecture.md draws the same layers.
"""

import ast
import pathlib

import pytest

SRC = pathlib.Path(__file__).resolve().parents[1] / "src" / "hardspheres"

#: The families, lowest first.  A module may import its own family's modules
#: and any lower family's, never a higher one's.
LAYERS = (
    # the terms: what the core and everything above speak in (numpy-free where the
    # assignment's program needs them)
    (
        "_jitcache",
        "errors",
        "extras",
        "version",
        "messages",
        "fileio",
        "progress",
        "physics",
        "events",
        "eos",
        "blocking",
        "containers",
        "scenario",
        "state",
        "frames",
        "maxwell",
        "builders",
    ),
    ("core",),  # the exact dynamics: nothing of Simulation, files or commands
    ("writers", "observables", "dense", "barostat", "simulation"),  # the run loop a physicist scripts
    ("mc",),  # Monte Carlo: event chains on the same states, containers and writers
    ("io",),
    ("analysis",),
    ("studies",),
    ("viz",),
    ("cli",),  # the two programs: nothing imports them
    ("", "__main__"),  # the package root (lazy re-exports) and ``python -m hardspheres``
)


def _family(module):
    """The family of ``hardspheres.X...``: its subpackage, or its root module's name."""
    parts = module.split(".")[1:]
    return parts[0] if parts else ""


def _rank(module):
    fam = _family(module)
    for rank, layer in enumerate(LAYERS):
        if fam in layer:
            return rank
    raise AssertionError(f"{module}: not in any layer of tests/test_layout.py; add it to one")


def modules():
    """``{dotted name: path}`` of every module of the package."""
    out = {}
    for path in SRC.rglob("*.py"):
        parts = ["hardspheres", *path.relative_to(SRC).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def import_graph():
    """``{module: {modules it imports}}``, counting every import statement.

    The rule of ``../shared/tools/import_circles.py``: ``from P import a``
    runs ``P`` (its ``__init__``) and, if ``P.a`` is a module, ``P.a``, so
    it is an edge to each; ``import P.a`` is an edge to ``P.a``.  Only the
    package root is left out (every module's import of it runs it anyway,
    for the lazy names).
    """
    mods = modules()
    graph = {}
    for name, path in mods.items():
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        deps = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package[: len(package) - node.level + 1]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                names = [target] + [f"{target}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            for n in names:
                while n and n not in mods:
                    n = n.rpartition(".")[0]
                if n:
                    deps.add(n)
        deps.discard(name)
        deps.discard("hardspheres")
        graph[name] = deps
    return graph


def circles(graph):
    """The strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_the_graph_sees_imports_inside_functions(tmp_path):
    # the reader itself: an import inside a function counts
    graph = import_graph()
    assert "hardspheres.core.engine" in graph["hardspheres.cli.assignment"]  # imported inside a function
    assert "hardspheres.core._core" in graph["hardspheres.core.engine"]  # ``from . import _core``
    # ... and ``from . import _core`` runs ``core/__init__`` too: an edge to the
    # package as well (the rule of ../shared/tools/import_circles.py; the old
    # rule here missed the circle studies -> dispatch -> task -> studies that
    # task's ``from . import measures`` closed, mended in d5e1721)
    assert "hardspheres.core" in graph["hardspheres.core.engine"]
    assert "hardspheres" not in graph["hardspheres.core.engine"]  # the root: lazy names only


def test_the_rule_finds_the_circle_through_a_package(monkeypatch, tmp_path):
    # the circle of d5e1721, rebuilt: a package whose __init__ imports a
    # module that imports a sibling by ``from . import``
    pkg = tmp_path / "hardspheres"
    (pkg / "studies").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "studies" / "__init__.py").write_text("from .task import run\n")
    (pkg / "studies" / "task.py").write_text("from . import measures\n")
    (pkg / "studies" / "measures.py").write_text("")
    monkeypatch.setitem(globals(), "SRC", pkg)
    assert circles(import_graph()) == [["hardspheres.studies", "hardspheres.studies.task"]]


def test_no_import_circles():
    assert circles(import_graph()) == []


def test_circle_detection_can_fail():
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == [["a", "b", "c"]]


def test_nothing_imports_upward():
    upward = [
        f"{a} -> {b}"
        for a, deps in sorted(import_graph().items())
        for b in sorted(deps)
        if _rank(b) > _rank(a)
    ]
    assert upward == []


@pytest.mark.parametrize("family", ["cli"])
def test_nothing_imports_the_commands(family):
    users = [
        a
        for a, deps in import_graph().items()
        if _family(a) not in (family, "__main__") and any(_family(b) == family for b in deps)
    ]
    assert users == []


def test_every_family_states_its_contract():
    for sub in sorted(p for p in SRC.iterdir() if (p / "__init__.py").exists()):
        doc = ast.get_docstring(ast.parse((sub / "__init__.py").read_text()))
        assert doc and len(doc.split()) >= 20, (
            f"{sub.name}/__init__.py: its docstring states the family's contract"
        )


def test_the_programs_live_in_cli():
    # argparse, sys.exit and print to stdout only in cli/ (and the assignment's report writer)
    allowed = {"cli", "io.report"}
    bad = []
    for name, path in modules().items():
        rel = name.split(".", 1)[1] if "." in name else ""
        if rel.split(".")[0] in allowed or rel in allowed:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] + [getattr(node, "module", None) or ""]
                if "argparse" in names:
                    bad.append(f"{name}: imports argparse")
            elif isinstance(node, ast.Call):
                f = node.func
                if isinstance(f, ast.Attribute) and f.attr == "exit" and getattr(f.value, "id", "") == "sys":
                    bad.append(f"{name}:{node.lineno}: sys.exit")
                if isinstance(f, ast.Name) and f.id == "print":
                    to = [k for k in node.keywords if k.arg == "file"]
                    if not to or ast.unparse(to[0].value) in ("sys.stdout", "stdout"):
                        bad.append(f"{name}:{node.lineno}: print to stdout")
    assert bad == []


def _private_reach_ins():
    """``obj._name`` where ``_name`` is not defined by a class of the same module."""
    hits = []
    for name, path in modules().items():
        tree = ast.parse(path.read_text())
        own = set()
        for cls in (n for n in ast.walk(tree) if isinstance(n, ast.ClassDef)):
            for sub in ast.walk(cls):
                if isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    own.add(sub.name)
                elif isinstance(sub, ast.Attribute) and getattr(sub.value, "id", None) in ("self", "cls"):
                    own.add(sub.attr)
                elif isinstance(sub, ast.AnnAssign) and isinstance(sub.target, ast.Name):
                    own.add(sub.target.id)
                elif isinstance(sub, ast.Assign):
                    own.update(t.id for t in sub.targets if isinstance(t, ast.Name))
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and node.attr.startswith("_")
                and not node.attr.startswith("__")
                and getattr(node.value, "id", None) not in ("self", "cls")
                and node.attr not in own
                and node.attr != "_replace"  # namedtuple's public API
            ):
                hits.append(f"{name}:{node.lineno}: {ast.unparse(node)}")
    return hits


def test_no_private_reach_ins_across_modules():
    # the engine may use its own numba core's helpers (one family, one concept)
    # and the cores' cache reaches into numba: it has no public way to key its on-disk cache
    # to the sources' content (hardspheres._jitcache; .ci/run checks it on the oldest numba too)
    allowed = {
        "hardspheres.core.checkpoint": {"core._key"},
        "hardspheres._jitcache": {"caching._CacheLocator", "dispatcher._cache"},
    }
    bad = [h for h in _private_reach_ins() if h.split(": ", 1)[1] not in allowed.get(h.split(":")[0], ())]
    assert bad == []


def test_lazy_names_are_visible_to_type_checkers_dir_and_help():
    import pydoc
    import subprocess
    import sys

    tree = ast.parse((SRC / "__init__.py").read_text())
    lazy = next(
        n.value for n in tree.body if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", "") == "_LAZY"
    )
    lazy_names = {k.value for k in lazy.keys}
    checked = {
        a.asname or a.name
        for n in tree.body
        if isinstance(n, ast.If) and ast.unparse(n.test) == "TYPE_CHECKING"
        for imp in n.body
        for a in imp.names
    }
    assert lazy_names == checked
    import hardspheres as hs

    assert set(hs.__all__) <= set(dir(hs))
    text = pydoc.render_doc(hs, renderer=pydoc.plaintext)
    for name in ("Simulation", "MSD", "GSDWriter", "random_spheres"):
        assert name in text
    # and importing the package still loads no numpy (the assignment's program starts fast)
    out = subprocess.run(
        [sys.executable, "-c", "import sys, hardspheres; print('numpy' in sys.modules)"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert out.strip() == "False"


def test_a_picture_command_parses_its_scenario_once(tmp_path, monkeypatch):
    """view/render/plot start from cli.source.starting_simulation: one parse, checked before compiling."""
    from hardspheres import scenario
    from hardspheres.cli.commands import main

    calls = []
    real = scenario.parse_scenario

    def counting(data):
        calls.append(1)
        return real(data)

    monkeypatch.setattr(scenario, "parse_scenario", counting)
    scn = tmp_path / "s.txt"
    scn.write_text("1 0.5 0 0 0 1 0 0 a\n1 0.5 3 0 0 -1 0 0 b\n")
    out = tmp_path / "v.html"
    assert main(["view", str(scn), "--container", "10", "--until", "1", "-o", str(out)]) == 0
    assert out.exists() and len(calls) == 1


def test_every_subcommand_is_one_module_with_add_parser_and_run():
    from hardspheres.cli import commands

    names = []
    for module in commands.SUBCOMMANDS:
        assert callable(module.add_parser) and callable(module.run)
        names.append(module.__name__.rsplit(".", 1)[1])
    parser = commands.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert sorted(sub.choices) == sorted(names)


def test_every_exception_and_warning_lives_in_errors_py():
    import hardspheres.errors as errors

    defined = {n for n in dir(errors) if isinstance(getattr(errors, n), type)}
    elsewhere = []
    for name, path in modules().items():
        if name == "hardspheres.errors":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef):
                bases = {ast.unparse(b).rsplit(".", 1)[-1] for b in node.bases}
                if any(b.endswith(("Error", "Warning", "Exception")) for b in bases | {node.name}):
                    elsewhere.append(f"{name}.{node.name}")
    assert elsewhere == [] and {"ScenarioError", "CheckpointError", "TruncatedTrajectory"} <= defined


def test_no_function_over_80_lines_unless_its_docstring_says_why():
    long = []
    for name, path in modules().items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1
                if lines > 80 and "Longer than 80 lines" not in (ast.get_docstring(node) or ""):
                    long.append(f"{name}.{node.name}: {lines} lines")
    assert long == []
