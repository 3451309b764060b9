"""The package's shape: no imports inside functions, no import cycles, no backend taken on import.

The layer contracts themselves are import-linter's (``lint-imports`` in ``make test``,
contracts in ``pyproject.toml``); these tests check what import-linter cannot see.
"""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGE = SRC / "sealeak"
DOCS = Path(__file__).resolve().parents[2] / "docs"

#: Function-level imports allowed outside the command line: an optional extra, imported when used.
ALLOWED_LAZY = {("sealeak/topography/_external.py", "SurfaceTopography"),
                # CoolProp takes ~3 s to import; a case whose viscosity is given needs no property lookup
                ("sealeak/physics/properties.py", "CoolProp"),
                # zarr takes ~0.7 s to import; only a store that keeps fields needs it
                ("sealeak/io/fieldstore.py", "zarr")}


def _modules() -> dict[str, Path]:
    out = {}
    for p in sorted(PACKAGE.rglob("*.py")):
        parts = list(p.relative_to(SRC).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


MODULES = _modules()


def _is_package(name: str) -> bool:
    return MODULES[name].name == "__init__.py"


def _resolve(module: str, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = module.split(".") if _is_package(module) else module.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _function_level_imports(tree: ast.AST):
    def walk(node, inside):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.Import, ast.ImportFrom)) and inside:
                yield child
            yield from walk(child, inside or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)))

    yield from walk(tree, False)


def test_the_module_list_is_the_package():
    assert "sealeak.physics.contact" in MODULES and "sealeak.cli" in MODULES and len(MODULES) > 40


def test_no_import_inside_a_function_except_the_cli():
    offenders = []
    for name, path in MODULES.items():
        if name == "sealeak.cli" or name.startswith("sealeak.cli."):
            continue  # deliberate lazy imports: `sealeak --help` stays fast
        rel = str(path.relative_to(SRC))
        for node in _function_level_imports(ast.parse(path.read_text(encoding="utf-8"))):
            target = node.module if isinstance(node, ast.ImportFrom) and node.level == 0 else (
                _resolve(name, node) if isinstance(node, ast.ImportFrom) else node.names[0].name)
            if (rel, (target or "").split(".")[0]) not in ALLOWED_LAZY:
                offenders.append(f"{rel}:{node.lineno} imports {target}")
    assert not offenders, "imports inside functions:\n" + "\n".join(offenders)


def _graph() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {name: set() for name in MODULES}
    for name, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:  # module level only (TYPE_CHECKING blocks are not run)
            targets = []
            if isinstance(node, ast.ImportFrom):
                base = _resolve(name, node)
                for alias in node.names:
                    sub = f"{base}.{alias.name}"
                    targets.append(sub if sub in MODULES else base)
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            for t in targets:
                if t in MODULES and t != name:
                    graph[name].add(t)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out = []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
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
                out.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_cycle_finder_finds_a_cycle():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_import_cycles_between_modules():
    graph = _graph()
    # a sub-module importing its own package's __init__ would close a loop through it
    assert not _cycles(graph), _cycles(graph)


def test_import_sealeak_leaves_the_matplotlib_backend_alone():
    code = ("import sys, matplotlib; matplotlib.use('svg'); import sealeak, sealeak.render, sealeak.cases; "
            "assert matplotlib.get_backend() == 'svg', matplotlib.get_backend(); "
            "assert 'matplotlib.pyplot' not in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True)


@pytest.mark.parametrize("folder", [PACKAGE, DOCS])
def test_nothing_users_have_not_got_is_referred_to(folder):
    bad = [str(p) for p in folder.rglob("*") if p.suffix in (".py", ".md", ".toml")
           and ("../shared" in (t := p.read_text(encoding="utf-8")) or "THEORY.md" in t)]
    assert not bad


# ------------------------------------------------------------------ start-up: the facades import lazily (PEP 562)
HEAVY = ("pint", "scipy.integrate", "matplotlib", "dask", "distributed", "zarr")


@pytest.mark.parametrize("code", ["import sealeak",
                                  "from sealeak.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass",
                                  "from sealeak.cli import main\ntry:\n    main(['predict', '--help'])\nexcept SystemExit:\n    pass"],
                         ids=["import", "help", "predict-help"])
def test_start_up_imports_none_of_the_heavy_libraries(code):
    probe = f"import sys\n{code}\nprint(' '.join(m for m in {HEAVY!r} if m in sys.modules), file=sys.stderr)"
    run = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert run.stderr.strip() == "", f"imported at start-up: {run.stderr.strip()}"


def test_the_lazy_facade_gives_every_public_name_and_sub_package():
    import sealeak

    for name in sealeak.__all__:
        assert getattr(sealeak, name) is not None, name
    assert sealeak.run_case is sealeak.cases.run_case and sealeak.PowerSpectrum is sealeak.physics.PowerSpectrum
    assert set(sealeak.__all__) <= set(dir(sealeak))
    with pytest.raises(AttributeError, match="no attribute 'nonesuch'"):
        sealeak.nonesuch  # noqa: B018
