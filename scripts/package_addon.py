#!/usr/bin/env python3
"""Build the installable add-on zip: addon/road_grammar/ with all its subpackages (core,
data, display, properties, operators, ui) plus the compiled module ggg under
road_grammar/native/, ready for Edit > Preferences > Add-ons > Install.

usage: python3 scripts/package_addon.py [--module-dir build/python] [--out dist/road_grammar.zip]

The zip is reproducible: entries are sorted and carry a fixed timestamp.
"""

import argparse
import re
import sys
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
ADDON = REPO / "addon" / "road_grammar"
FIXED_TIME = (2024, 1, 1, 0, 0, 0)
MODULE_PATTERN = re.compile(r"^ggg\.[^/]*\.(so|pyd)$")


def addon_files():
    for path in sorted(ADDON.rglob("*")):
        relative = path.relative_to(ADDON)
        if not path.is_file() or "__pycache__" in relative.parts or path.suffix in (".pyc", ".pyo"):
            continue
        if relative.parts[0] == "native":  # a module dropped there by hand is not packaged
            continue
        yield path, Path("road_grammar") / relative


def module_files(module_dir):
    found = sorted(p for p in module_dir.iterdir() if p.is_file() and MODULE_PATTERN.match(p.name))
    return [(p, Path("road_grammar") / "native" / p.name) for p in found]


def write_zip(out, entries):
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name + ".tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for source, name in entries:
            info = zipfile.ZipInfo(name.as_posix(), date_time=FIXED_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = (0o755 if source.suffix in (".so", ".pyd") else 0o644) << 16
            archive.writestr(info, source.read_bytes())
    tmp.replace(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--module-dir", type=Path, default=REPO / "build" / "python",
                        help="folder holding the built module ggg.cpython-*.so (default: build/python)")
    parser.add_argument("--out", type=Path, default=REPO / "dist" / "road_grammar.zip",
                        help="zip to write (default: dist/road_grammar.zip)")
    args = parser.parse_args(argv)

    if not args.module_dir.is_dir():
        print("error: module folder {} does not exist; build first (cmake --build build)".format(args.module_dir),
              file=sys.stderr)
        return 1
    modules = module_files(args.module_dir)
    if not modules:
        print("error: no ggg.*.so in {}; build first (cmake --build build)".format(args.module_dir),
              file=sys.stderr)
        return 1
    entries = list(addon_files()) + modules
    if Path("road_grammar") / "__init__.py" not in {name for _, name in entries}:
        print("error: {} holds no add-on".format(ADDON), file=sys.stderr)
        return 1
    write_zip(args.out, entries)
    print("wrote {} ({} files, module {})".format(args.out, len(entries), ", ".join(p.name for p, _ in modules)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
