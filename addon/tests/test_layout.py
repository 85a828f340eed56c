"""The add-on's layout (read from its source, nothing imported): core is pure Python, the
layers import only downwards, no module imports another's private names or takes part in an
import cycle, and every Blender class is registered through its module's ``classes``."""

import ast
import sys
from pathlib import Path

import pytest

ADDON = Path(__file__).resolve().parent.parent / "road_grammar"
PACKAGE = "road_grammar"
# Each layer may import from itself and the layers before it.
LAYERS = ("core", "data", "display", "properties", "operators", "ui")
LEVEL = {"core": 0, "data": 1, "display": 1, "properties": 2, "operators": 3, "ui": 4}
REGISTERED = ("properties", "operators", "ui")
BLENDER_CLASS_PREFIXES = ("ROADS_OT_", "ROADS_PT_", "ROADS_PG_", "ROADS_UL_", "ROADS_AP_", "ROADS_MT_", "VIEW3D_PT_")


def module_name(path):
    parts = list(path.relative_to(ADDON).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join([PACKAGE] + parts)


MODULES = {module_name(path): path for path in sorted(ADDON.rglob("*.py")) if "__pycache__" not in path.parts}


def is_package(name):
    return MODULES[name].name == "__init__.py"


def tree(name):
    return ast.parse(MODULES[name].read_text(), str(MODULES[name]))


def imports(name):
    """(imported module, names or None, private names) of every import in ``name``'s
    source, with relative imports resolved; a name that is a module of the add-on counts as
    that module."""
    base = name if is_package(name) else name.rpartition(".")[0]
    found = []
    for node in ast.walk(tree(name)):
        if isinstance(node, ast.Import):
            found.extend((alias.name, None) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parent = base
                for _ in range(node.level - 1):
                    parent = parent.rpartition(".")[0]
                source = parent + ("." + node.module if node.module else "")
            else:
                source = node.module
            for alias in node.names:
                submodule = source + "." + alias.name
                if submodule in MODULES:
                    found.append((submodule, None))
                else:
                    found.append((source, alias.name))
    return found


def internal_dependencies(name):
    return {module for module, _name in imports(name) if module in MODULES and module != name}


def layer(name):
    parts = name.split(".")
    return parts[1] if len(parts) > 1 else None


@pytest.mark.parametrize("name", sorted(n for n in MODULES if layer(n) == "core"))
def test_core_is_pure_python(name):
    """core imports only the standard library, numpy and itself: never bpy."""
    for module, _name in imports(name):
        top = module.split(".")[0]
        if module in MODULES:
            assert layer(module) == "core", "{} imports {}".format(name, module)
        else:
            assert top == "numpy" or top in sys.stdlib_module_names, "{} imports {}".format(name, module)


@pytest.mark.parametrize("name", sorted(n for n in MODULES if layer(n) in LAYERS))
def test_layers_import_downwards(name):
    for module in internal_dependencies(name):
        if layer(module) is None:
            pytest.fail("{} imports the add-on's __init__".format(name))
        assert LEVEL[layer(module)] <= LEVEL[layer(name)], "{} ({}) imports {} ({})".format(
            name, layer(name), module, layer(module))


@pytest.mark.parametrize("name", sorted(MODULES))
def test_no_private_imports(name):
    """No module takes another's private names (``from .x import _name``)."""
    for module, imported in imports(name):
        assert not (imported or "").startswith("_"), "{} imports {} from {}".format(name, imported, module)


def test_no_import_cycles():
    """The modules of the add-on import each other without a cycle (counting imports
    inside functions too, so none is hidden in a local import)."""
    graph = {name: internal_dependencies(name) for name in MODULES}
    state = {}
    path = []

    def visit(node):
        state[node] = "open"
        path.append(node)
        for following in sorted(graph[node]):
            if state.get(following) == "open":
                cycle = path[path.index(following):] + [following]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if following not in state:
                visit(following)
        path.pop()
        state[node] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name)


def _module_level_classes(name):
    return [node.name for node in tree(name).body if isinstance(node, ast.ClassDef)]


def _tuple_names(name, variable):
    for node in tree(name).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == variable for t in node.targets):
            assert isinstance(node.value, ast.Tuple), "{}.{} is not a tuple".format(name, variable)
            return [element.id if isinstance(element, ast.Name) else ast.unparse(element)
                    for element in node.value.elts]
    return None


@pytest.mark.parametrize("package", REGISTERED)
def test_registered_packages_list_their_modules(package):
    """properties, operators and ui list every module that defines Blender classes in
    ``modules``, and each lists its classes in ``classes``."""
    listed = _tuple_names(PACKAGE + "." + package, "modules")
    assert listed is not None
    for name in sorted(n for n in MODULES if layer(n) == package and not is_package(n)):
        blender = [c for c in _module_level_classes(name) if c.startswith(BLENDER_CLASS_PREFIXES)]
        classes = _tuple_names(name, "classes")
        if blender or classes:
            assert name.rpartition(".")[2] in listed, "{} is not in {}.modules".format(name, package)
            assert sorted(classes or []) == sorted(blender), "{}.classes".format(name)


def test_blender_classes_only_where_registered():
    for name in MODULES:
        if layer(name) not in REGISTERED:
            blender = [c for c in _module_level_classes(name) if c.startswith(BLENDER_CLASS_PREFIXES)]
            assert not blender, "{} defines {} but is not registered".format(name, blender)


def test_one_plural():
    """Messages count things with core.text.plural, defined once."""
    for name in MODULES:
        defined = [node.name for node in ast.walk(tree(name)) if isinstance(node, ast.FunctionDef)
                   and node.name.strip("_") == "plural"]
        if name != PACKAGE + ".core.text":
            assert not defined, "{} defines {}".format(name, defined)
