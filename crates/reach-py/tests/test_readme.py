"""The README's Python tour runs (every ```python block of its Python section)."""

import re

from conftest import ROOT


def test_readme_python_snippets_run():
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "the README has a Python section with ```python blocks"
    for block in blocks:
        if "ray.init" in block or "pip install" in block:
            continue
        exec(compile(block, "README.md", "exec"), {})
