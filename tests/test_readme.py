"""The README's usage example runs as printed (it is the public API's front page)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_example_runs(capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "README has no python example"
    ns: dict = {}
    exec(compile(blocks[0], str(README), "exec"), ns)
    h, d, cert = ns["h"], ns["d"], ns["cert"]
    assert abs(h.radius - 66.60) < 0.01 and h.stable
    assert d.helix.stable and abs(d.helix.radius - 50.0) < 1e-3 * 50
    assert cert.certified == (cert.mu < cert.mu_d)
    assert np.all(ns["sw"].exists)
    assert capsys.readouterr().out  # the example prints its results
