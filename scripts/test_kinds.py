#!/usr/bin/env python3
"""Sorts the C++ test cases by what they need, for ctest's labels (native/tests/CMakeLists.txt):
`corpus` reads ../shared/osm, `cli` runs the ggg command, `unit` needs neither and runs in
seconds. Reads the test sources and prints CMake lists of test names (Suite.Name).

    python3 scripts/test_kinds.py native/tests > test_kinds.cmake"""
import re
import sys
from pathlib import Path

START = re.compile(r"^(TEST|TEST_F|TEST_P)\((\w+),\s*(\w+)\)", re.M)
CORPUS = re.compile(r"GGG_REQUIRE_CORPUS|shared_osm_dir|corpus_files|GetParam\(\)")
CLI = re.compile(r"run_cli\(")


def main():
    tests = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent / "native" / "tests")
    corpus, cli = [], []
    for source in sorted(tests.glob("*_test.cpp")):
        text = source.read_text()
        starts = list(START.finditer(text))
        for i, match in enumerate(starts):
            body = text[match.end(): starts[i + 1].start() if i + 1 < len(starts) else len(text)]
            name = "{}.{}".format(match.group(2), match.group(3))
            if CORPUS.search(body):
                corpus.append(name)
            if CLI.search(body):
                cli.append(name)
    print("# Made by scripts/test_kinds.py from native/tests/*_test.cpp.")
    print("set(ggg_corpus_tests\n  {})".format("\n  ".join(corpus)))
    print("set(ggg_cli_tests\n  {})".format("\n  ".join(cli)))


if __name__ == "__main__":
    main()
