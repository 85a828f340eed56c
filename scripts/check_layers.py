#!/usr/bin/env python3
"""Checks the library's layers (docs/architecture.md): a header or source includes only its
own folder and the folders before it in the pipeline, and only io/ knows JSON.

    python3 scripts/check_layers.py [native]

Exits 1 and names each file that breaks the order."""
import re
import sys
from pathlib import Path

# error.hpp, progress.hpp, files.hpp and random.hpp sit at the root: every layer may use them.
ORDER = ["", "graph", "osm", "grammar", "analysis", "encoding", "measures", "synthesis", "io"]


def layer(relative):
    parts = Path(relative).parts
    return "" if len(parts) == 1 else parts[0]


def main():
    native = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent / "native")
    problems = []
    for base in (native / "include" / "ggg", native / "src"):
        for path in sorted(base.rglob("*.[ch]pp")):
            relative = path.relative_to(base)
            own = layer(relative)
            if own not in ORDER:
                problems.append("{}: folder '{}' is not a layer of the pipeline".format(path, own))
                continue
            text = path.read_text()
            for match in re.finditer(r'#include "ggg/([^"]+)"', text):
                other = layer(match.group(1))
                if other in ORDER and ORDER.index(other) > ORDER.index(own):
                    problems.append("{}: a {} file includes {} (a later layer)".format(path, own or "root", match.group(1)))
            if own != "io" and re.search(r"#include <nlohmann/", text):
                problems.append("{}: includes nlohmann/json outside io/".format(path))
            if re.search(r'#include "\.\./', text):
                problems.append("{}: includes a private header of another folder".format(path))
    for p in problems:
        print(p)
    if not problems:
        print("layers: every include keeps to the pipeline's order")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
