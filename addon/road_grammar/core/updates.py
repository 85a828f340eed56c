"""Property updates the add-on itself triggers: while it sets a list's active index or the
level shown, the update callbacks (highlighting, rebuilding a display) do not run."""

import contextlib

_suspended = [0]


@contextlib.contextmanager
def suspended_updates():
    """While the add-on sets the list's active index, its update (highlight) does not run."""
    _suspended[0] += 1
    try:
        yield
    finally:
        _suspended[0] -= 1


def updates_suspended():
    return _suspended[0] > 0
