"""core.native: where the native module is looked for, and what is said when it cannot load."""

from road_grammar.core import native


def test_search_dirs(monkeypatch, tmp_path):
    monkeypatch.setenv(native.ENV_VAR, "{}:{}".format(tmp_path / "a", tmp_path / "b"))
    dirs = native.search_dirs()
    assert dirs[0] == native.BUNDLED_DIR and dirs[1:] == [tmp_path / "a", tmp_path / "b"]
    assert native.BUNDLED_DIR.parent.name == "road_grammar"


def test_builds_for_other_pythons_are_named(tmp_path):
    other = tmp_path / "ggg.cpython-39-x86_64-linux-gnu.so"
    other.write_bytes(b"")
    (tmp_path / "other.so").write_bytes(b"")
    assert native._candidates([tmp_path]) == [other]
    assert not native._is_compatible(other)
    assert native._python_of(other) == "3.9"
    message = native._mismatch_message([other])
    assert "built for another Python" in message and "Python 3.9" in message and native.ENV_VAR in message


def test_not_found_message(tmp_path):
    message = native._not_found_message([tmp_path])
    assert str(tmp_path) in message and native.ENV_VAR in message


class FakeOperator:
    def __init__(self):
        self.reports = []

    def report(self, kind, message):
        self.reports.append((kind, message))


def test_load_or_report(ggg):
    operator = FakeOperator()
    assert native.load_or_report(operator) is ggg and not operator.reports
    module, message = native.status()
    assert module is ggg and message.startswith("ggg ")
