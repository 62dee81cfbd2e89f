"""docs/python.md's walk-through runs as written: every ```python cell, in order, in one
namespace (a cell guarded by `if __name__ == "__main__":` defines its functions only; the
sweep it shows runs in test_sweep.py)."""

import re
from pathlib import Path

from conftest import REPO


def cells() -> list:
    text = (REPO / "docs" / "python.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def test_the_walk_through_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "docs_python"}
    found = cells()
    assert len(found) >= 8
    for k, code in enumerate(found):
        try:
            exec(compile(code, f"docs/python.md cell {k + 1}", "exec"), namespace)
        except Exception as e:  # pragma: no cover - the message says which cell
            raise AssertionError(f"docs/python.md cell {k + 1} failed: {e!r}\n{code}") from e
