"""The add-on's layout (read from its source, nothing imported): core is pure Python, the
layers import only downwards (display draws what data holds: display may import data, data
never imports display), no module imports or reads another's private names or takes part in
an import cycle, and every Blender class is registered through its module's ``classes``."""

import ast
import sys
from pathlib import Path

import pytest

ADDON = Path(__file__).resolve().parent.parent / "road_grammar"
PACKAGE = "road_grammar"
# Each layer may import from itself and the layers before it.
LAYERS = ("core", "data", "display", "properties", "operators", "ui")
LEVEL = {layer: level for level, layer in enumerate(LAYERS)}
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


def _resolved_imports(name):
    """(imported module, name or None, the name it is bound to) of every import in
    ``name``'s source, with relative imports resolved; a name that is a module of the add-on
    counts as that module."""
    base = name if is_package(name) else name.rpartition(".")[0]
    found = []
    for node in ast.walk(tree(name)):
        if isinstance(node, ast.Import):
            found.extend((alias.name, None, alias.asname or alias.name.partition(".")[0]) for alias in node.names)
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
                    found.append((submodule, None, alias.asname or alias.name))
                else:
                    found.append((source, alias.name, alias.asname or alias.name))
    return found


def imports(name):
    """(imported module, name or None) of every import in ``name``'s source, with relative
    imports resolved; a name that is a module of the add-on counts as that module."""
    return [(module, imported) for module, imported, _bound in _resolved_imports(name)]


def module_aliases(name):
    """The names under which ``name`` binds modules of the add-on (``from ..data import
    roads``, ``from . import mesh as mesh_data``): bound name -> module."""
    return {bound: module for module, imported, bound in _resolved_imports(name)
            if imported is None and module in MODULES}


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


def is_private(attribute):
    return attribute.startswith("_") and not (attribute.startswith("__") and attribute.endswith("__"))


@pytest.mark.parametrize("name", sorted(MODULES))
def test_no_private_imports(name):
    """No module takes another's private names (``from .x import _name``), nor reads them
    through the module (``from . import x`` then ``x._name``)."""
    for module, imported in imports(name):
        assert not is_private(imported or ""), "{} imports {} from {}".format(name, imported, module)
    aliases = module_aliases(name)
    for node in ast.walk(tree(name)):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases:
            assert not is_private(node.attr), "{} uses {} of {} (line {})".format(
                name, node.attr, aliases[node.value.id], node.lineno)


def test_data_does_not_import_display():
    """display draws what data holds, so it imports data; data never imports display (the
    levels above say so; this names the rule)."""
    for name in sorted(n for n in MODULES if layer(n) == "data"):
        assert not [m for m in internal_dependencies(name) if layer(m) == "display"], name


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
