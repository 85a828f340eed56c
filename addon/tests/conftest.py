"""The add-on's core, tested in plain Python (no Blender):

    python3 -m pytest addon/tests

The package ``road_grammar`` is set up without running its ``__init__`` (which registers
with Blender), so that ``road_grammar.core`` imports as it does inside Blender; core never
imports bpy, so nothing else is needed."""

import importlib.machinery
import importlib.util
import os
import sys
from pathlib import Path

import pytest

ADDON = Path(__file__).resolve().parent.parent / "road_grammar"
REPO = ADDON.parent.parent

if "road_grammar" not in sys.modules:
    _package = importlib.util.module_from_spec(importlib.machinery.ModuleSpec("road_grammar", None, is_package=True))
    _package.__path__ = [str(ADDON)]
    sys.modules["road_grammar"] = _package


@pytest.fixture(scope="session")
def ggg():
    """The native module (from $GGG_MODULE_DIR, default build/python), for the core
    functions that take it; the tests that need it are skipped where it is not built for
    this Python."""
    os.environ.setdefault("GGG_MODULE_DIR", str(REPO / "build" / "python"))
    from road_grammar.core import native

    try:
        return native.load()
    except native.NativeModuleError as ex:
        pytest.skip(str(ex))
