"""Run the add-on's tests with pytest inside Blender.

  blender -b --factory-startup --python-exit-code 1 --python blender_tests/run.py -- \
      [--zip dist/road_grammar.zip] [pytest arguments]

By default the add-on is taken from addon/ and the native module from $GGG_MODULE_DIR
(default: build/python). With --zip, the packaged add-on is unpacked into a temporary
folder and tested as shipped, with the module bundled inside it (GGG_MODULE_DIR unset).
Blender exits with pytest's code; "no tests collected" (5) counts as a failure.
"""

import os
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path

import addon_utils
import bpy

REPO = Path(__file__).resolve().parent.parent
TESTS = REPO / "blender_tests"


def _split_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    zip_path = None
    if argv[:1] == ["--zip"]:
        if len(argv) < 2:
            raise SystemExit("run.py: --zip needs the path of the add-on zip")
        zip_path, argv = Path(argv[1]).resolve(), argv[2:]
    return zip_path, argv


def _put_addon_on_path(zip_path):
    """The folder that holds road_grammar/, and a temporary folder to remove afterwards."""
    if zip_path is None:
        os.environ.setdefault("GGG_MODULE_DIR", str(REPO / "build" / "python"))
        return REPO / "addon", None
    if not zip_path.is_file():
        raise SystemExit("run.py: no such zip: {}".format(zip_path))
    temporary = Path(tempfile.mkdtemp(prefix="road_grammar_zip_"))
    with zipfile.ZipFile(zip_path) as archive:
        archive.extractall(temporary)
    os.environ.pop("GGG_MODULE_DIR", None)
    os.environ["ROAD_GRAMMAR_TEST_ZIP"] = str(zip_path)
    return temporary, temporary


def _enable_addon(addon_parent):
    sys.path.insert(0, str(addon_parent))
    sys.path.insert(0, str(TESTS))
    errors = []
    addon_utils.enable("road_grammar", default_set=True, handle_error=errors.append)
    if errors or "road_grammar" not in bpy.context.preferences.addons:
        raise SystemExit("run.py: the add-on road_grammar could not be enabled: {}".format(errors))


def main():
    zip_path, pytest_args = _split_args()
    sys.dont_write_bytecode = True  # no __pycache__ in the source tree
    addon_parent, temporary = _put_addon_on_path(zip_path)
    try:
        _enable_addon(addon_parent)
        import pytest

        # Without paths on the command line, pytest collects testpaths (relative to the repo).
        os.chdir(REPO)
        code = int(pytest.main(["-o", "testpaths=blender_tests", "-p", "no:cacheprovider", "-ra",
                                *pytest_args]))
    finally:
        if temporary is not None:
            shutil.rmtree(temporary, ignore_errors=True)
    if code == 5:
        print("run.py: pytest collected no tests; that is a failure", file=sys.stderr)
    sys.exit(code)


main()
