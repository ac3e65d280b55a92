# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's folders (docs/ARCHITECTURE.md, Layout): every module sits in one folder per concern,
a folder imports only the folders before it in LAYERS, and no import, at the top of a module or
inside a function, closes a circle (a script's __main__ block, run as Blender's script and not as
a module of the add-on, aside). Read from the sources with ast: nothing imports bpy."""

import ast
from pathlib import Path

ADDON = Path(__file__).resolve().parents[2] / "addon" / "hapticfluid_blender"
TOP = ADDON.name
LAYERS = ("render", "properties", "bake", "operators", "ui", "live")


def _modules():
    """Dotted module name -> file, for every .py of the add-on."""
    found = {}
    for path in sorted(ADDON.rglob("*.py")):
        parts = list(path.relative_to(ADDON.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


def _is_main_block(node):
    """``if __name__ == "__main__":``: code that runs only when the file is Blender's script, where
    the module is __main__ and not a module of the add-on."""
    test = getattr(node, "test", None)
    return (isinstance(node, ast.If) and isinstance(test, ast.Compare) and isinstance(test.left, ast.Name)
            and test.left.id == "__name__" and any(getattr(c, "value", None) == "__main__" for c in test.comparators))


def _module_body(path):
    """The module's top-level statements, its __main__ block left out."""
    return [n for n in ast.parse(path.read_text(encoding="utf-8")).body if not _is_main_block(n)]


def _imports(modules):
    """Module -> the add-on modules it imports (a package's __init__ when no module matches)."""
    edges = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = set()
        for node in (n for top in _module_body(path) for n in ast.walk(top)):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    above = package.split(".")[:len(package.split(".")) - node.level + 1]
                    base = ".".join(above + ([node.module] if node.module else []))
                if base.split(".")[0] == TOP:
                    targets |= {f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names}
            elif isinstance(node, ast.Import):
                targets |= {a.name for a in node.names if a.name.split(".")[0] == TOP}
        missing = targets - modules.keys()
        assert not missing, f"{name} imports {sorted(missing)}, which the add-on does not have"
        edges[name] = targets
    return edges


def _group(name):
    parts = name.split(".")
    return parts[1] if len(parts) > 1 else None


def test_every_module_sits_in_a_folder_of_the_layout():
    loose = [p.name for p in ADDON.glob("*.py") if p.name != "__init__.py"]
    assert not loose, f"modules at the add-on's top: {loose} (put each in the folder of its concern)"
    folders = {p.name for p in ADDON.iterdir() if p.is_dir() and p.name != "__pycache__"}
    assert folders == set(LAYERS), f"folders {sorted(folders)}, the layout names {sorted(LAYERS)}"
    assert all((ADDON / folder / "__init__.py").is_file() for folder in LAYERS)


def test_a_folder_imports_only_the_folders_before_it():
    bad = []
    for name, targets in _imports(_modules()).items():
        group = _group(name)
        if group is None:  # the add-on's __init__ registers every folder's classes
            continue
        for target in targets:
            other = _group(target)
            if other != group and (other is None or LAYERS.index(other) > LAYERS.index(group)):
                bad.append(f"{name} -> {target}")
    assert not bad, f"imports against the layers {' <- '.join(LAYERS)}: {bad}"


def test_no_import_closes_a_circle():
    edges = _imports(_modules())
    circles, index, low, stack, on_stack = [], {}, {}, [], set()

    def visit(v):  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while not component or component[-1] != v:
                component.append(stack.pop())
                on_stack.discard(component[-1])
            if len(component) > 1 or v in edges[v]:
                circles.append(sorted(component))

    for name in edges:
        if name not in index:
            visit(name)
    assert circles == [], f"import circles in the add-on: {circles}"


def test_the_package_names_only_the_add_ons_entry_points():
    """The pip package (farm jobs) runs the add-on only through functions of its top package
    (hapticfluid.farm.BLENDER_*_EXPR), so the add-on's files can move without it: no source or
    job file of the package names an add-on module, and each function it calls is defined there."""
    import re

    package = ADDON.parents[1] / "python" / "hapticfluid"
    named = [f"{p.relative_to(package)}: {m.group(0)}" for p in sorted(package.rglob("*"))
             if p.suffix in (".py", ".yaml", ".js") for m in re.finditer(r"hapticfluid_blender\.\w+", p.read_text())]
    assert not named, f"the package names the add-on's modules: {named}"
    called = set(re.findall(r"import hapticfluid_blender as a; a\.(\w+)\(\)",
                            (package / "farm" / "__init__.py").read_text()))
    defined = {n.name for n in ast.parse((ADDON / "__init__.py").read_text()).body if isinstance(n, ast.FunctionDef)}
    assert called and called <= defined, f"entry points {sorted(called)}, the add-on defines {sorted(defined)}"
