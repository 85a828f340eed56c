"""Locating and importing the native module ``ggg``.

The module is a compiled CPython extension, so it only loads into the Python it was
built for. It is looked for, in this order:

1. bundled inside the add-on, in ``road_grammar/native/`` (the packaged zip);
2. the folder(s) named by the environment variable ``GGG_MODULE_DIR`` (a build tree);
3. anywhere on ``sys.path`` (a module installed next to Blender's Python).

Nothing here runs at register time: the add-on registers without the module, and the
import operator and the sidebar panel tell the user what is wrong when it cannot load.
"""

import importlib.machinery
import importlib.util
import os
import re
import sys
from pathlib import Path

MODULE_NAME = "ggg"
ENV_VAR = "GGG_MODULE_DIR"
# road_grammar/native/, next to this package (core/).
BUNDLED_DIR = Path(__file__).resolve().parent.parent / "native"

# What the add-on calls; a module lacking any of these is from an older build.
REQUIRED_NAMES = ("read_graph", "Graph", "Error", "InputError", "highway_classes", "default_widths",
                  "highway_ranks", "Grammar", "GrammarError", "read_grammar", "parse_grammar", "derive")

_CPYTHON_TAG = re.compile(r"\.cpython-(\d)(\d+)")


class NativeModuleError(Exception):
    """The native module cannot be used; the message says what to do about it."""


_module = None
_failure = None  # (search signature, message) of the last failed attempt


def search_dirs():
    """The folders searched for the module, in order of preference."""
    dirs = [BUNDLED_DIR]
    for entry in os.environ.get(ENV_VAR, "").split(os.pathsep):
        if entry:
            dirs.append(Path(entry).expanduser())
    return dirs


def _candidates(dirs):
    """Files in ``dirs`` that look like a build of the module (any Python version)."""
    found = []
    for directory in dirs:
        if not directory.is_dir():
            continue
        for path in sorted(directory.iterdir()):
            name = path.name
            if name.startswith(MODULE_NAME + ".") and name.endswith((".so", ".pyd")) and path.is_file():
                found.append(path)
    return found


def _is_compatible(path):
    return any(path.name == MODULE_NAME + suffix for suffix in importlib.machinery.EXTENSION_SUFFIXES)


def _python_of(path):
    """'3.12' for ggg.cpython-312-x86_64-linux-gnu.so, None when the name does not say."""
    match = _CPYTHON_TAG.search(path.name)
    return "{}.{}".format(match.group(1), match.group(2)) if match else None


def _mismatch_message(paths):
    running = "{}.{}".format(*sys.version_info[:2])
    built = ", ".join(
        "{} ({})".format(p, "Python " + _python_of(p) if _python_of(p) else "another platform")
        for p in paths
    )
    return (
        "The native module 'ggg' was built for another Python: {}. Blender runs Python {} "
        "(expects a file named ggg{}). Rebuild the module with Python {}, e.g. "
        "`cmake -S . -B build -DPython_EXECUTABLE=$(command -v python{}) && cmake --build build`, "
        "then package the add-on again or point {} at build/python."
    ).format(built, running, importlib.machinery.EXTENSION_SUFFIXES[0], running, running, ENV_VAR)


def _not_found_message(dirs):
    where = ", ".join(str(d) for d in dirs)
    return (
        "The native module 'ggg' was not found (looked in {} and on sys.path). Install the "
        "packaged add-on zip (it bundles the module), or build it (`cmake --build build`) and "
        "start Blender with {}=<repository>/build/python."
    ).format(where, ENV_VAR)


def _load_file(path):
    loader = importlib.machinery.ExtensionFileLoader(MODULE_NAME, str(path))
    spec = importlib.util.spec_from_file_location(MODULE_NAME, str(path), loader=loader)
    try:
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    except ImportError as ex:
        raise NativeModuleError("Cannot load the native module {}: {}".format(path, ex)) from ex
    return module


def _check_api(module):
    missing = [name for name in REQUIRED_NAMES if not hasattr(module, name)]
    if missing:
        raise NativeModuleError(
            "The native module {} is too old for this add-on (it lacks {}); rebuild it.".format(
                getattr(module, "__file__", MODULE_NAME), ", ".join(missing)
            )
        )
    return module


def _find_and_load():
    existing = sys.modules.get(MODULE_NAME)
    if existing is not None:
        return _check_api(existing)
    dirs = search_dirs()
    candidates = _candidates(dirs)
    compatible = [p for p in candidates if _is_compatible(p)]
    if compatible:
        module = _load_file(compatible[0])
        sys.modules[MODULE_NAME] = module
        return _check_api(module)
    spec = importlib.util.find_spec(MODULE_NAME)
    if spec is not None:
        try:
            module = importlib.import_module(MODULE_NAME)
        except ImportError as ex:
            raise NativeModuleError("Cannot load the native module {}: {}".format(spec.origin, ex)) from ex
        return _check_api(module)
    if candidates:
        raise NativeModuleError(_mismatch_message(candidates))
    raise NativeModuleError(_not_found_message(dirs))


def _signature():
    """What a new attempt would see; a failure is only retried when this changes."""
    dirs = search_dirs()
    return tuple((str(p), p.stat().st_mtime_ns) for p in _candidates(dirs)) + tuple(str(d) for d in dirs)


def load():
    """The module ``ggg``; raises NativeModuleError with advice when it cannot be used."""
    global _module, _failure
    if _module is not None:
        return _module
    signature = _signature()
    if _failure is not None and _failure[0] == signature:
        raise NativeModuleError(_failure[1])
    try:
        _module = _find_and_load()
    except NativeModuleError as ex:
        _failure = (signature, str(ex))
        raise
    _failure = None
    return _module


def status():
    """(module or None, message): for the panel, which must never raise."""
    try:
        module = load()
    except NativeModuleError as ex:
        return None, str(ex)
    version = getattr(module, "__version__", "unknown version")
    return module, "ggg {} ({})".format(version, getattr(module, "__file__", "built in"))


def load_or_report(operator):
    """The module ``ggg``, or None after reporting to ``operator`` (an ERROR) why it cannot
    be used."""
    try:
        return load()
    except NativeModuleError as ex:
        operator.report({'ERROR'}, str(ex))
        return None
