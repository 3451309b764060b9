"""The project's rule for bad input, as a test helper: one line ``sealeak: error: ...`` naming the field, no traceback."""

from __future__ import annotations

from typing import Any

__all__ = ["one_line_error"]


def one_line_error(source: Any, *names: object) -> str:
    """Check that stderr is one line ``sealeak: error: ...`` naming each of ``names``, without a traceback or warning.

    ``source`` is the stderr text, or pytest's ``capsys`` (its stderr is read). Returns the line.
    """
    err = source if isinstance(source, str) else source.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("sealeak: error: "), err
    assert "Traceback" not in err and "Warning" not in err, err
    for name in names:
        assert str(name) in lines[0], (name, lines[0])
    return err
