"""The package's module graph, read from each module's top-level import statements: no cycle (a cycle hidden by an
import inside a function body breaks as soon as someone moves it to the top), and no module reaches for a private
name (_x) of another."""
import ast
import os

import pytest

# The source tree (build/python holds a copy made at build time).
PACKAGE_DIR = os.path.join(os.path.dirname(__file__), "..", "..", "python", "sphrect")


def _modules():
    """{dotted name: path} of the package's Python modules."""
    found = {}
    for folder, _, files in os.walk(PACKAGE_DIR):
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(folder, f), os.path.join(PACKAGE_DIR, ".."))[:-3].split(os.sep)
                if rel[-1] == "__init__":
                    rel = rel[:-1]
                found[".".join(rel)] = os.path.join(folder, f)
    return found


def _imports(name, path, modules):
    """(module imported, names taken from it) for every import statement anywhere in `path`'s module."""
    package = name if path.endswith("__init__.py") else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(open(path).read())):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parts = parts[:len(parts) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                if sub in modules:  # `from . import scene`: the submodule itself
                    yield sub, [], node
                else:
                    yield base, [alias.name], node
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, [], node


def _graph():
    modules = _modules()
    edges = {m: set() for m in modules}
    private = []
    for name, path in modules.items():
        for target, names, _ in _imports(name, path, modules):
            if target in modules and target != name:
                edges[name].add(target)
                private += [f"{name} imports {target}.{n}" for n in names
                            if n.startswith("_") and not n.startswith("__") and n != "_native"]
    return edges, private


def test_the_package_is_found():
    edges, _ = _graph()
    assert {"sphrect", "sphrect.render", "sphrect.scene", "sphrect.sample_ranges", "sphrect.distributed"} <= set(edges)


def test_no_import_cycle():
    edges, _ = _graph()

    # Parent packages import their children by design (sphrect/__init__ re-exports): only sibling edges count.
    def counts(a, b):
        return not b.startswith(a + ".") and not a.startswith(b + ".")
    state = {}

    def visit(m, path):
        state[m] = "open"
        for n in sorted(edges[m]):
            if not counts(m, n):
                continue
            if state.get(n) == "open":
                pytest.fail("import cycle: " + " -> ".join(path[path.index(n):] + [n]))
            if n not in state:
                visit(n, path + [n])
        state[m] = "done"

    for m in sorted(edges):
        if m not in state:
            visit(m, [m])


def test_no_private_name_of_another_module():
    _, private = _graph()
    assert private == []
