"""The Python in the docs runs: every ```python block of docs/PYTHON.md, in a scratch directory
holding the CGAL meshes it names and examples/, with the tests' product cache."""

import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "PYTHON.md"
BLOCKS = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)


def test_the_doc_has_python_blocks():
    assert BLOCKS


@pytest.mark.parametrize("block", range(len(BLOCKS)))
def test_each_python_block_runs(block, cgal_meshes, scene_examples, product_cache, tmp_path,
                                monkeypatch):
    for name in re.findall(r'"(\w[\w-]*\.(?:off|ply))"', BLOCKS[block]):
        (tmp_path / name).symlink_to(cgal_meshes / name)
    (tmp_path / "examples").symlink_to(scene_examples.parent)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("XDG_CACHE_HOME", str(product_cache))
    exec(compile(BLOCKS[block], f"{DOC.name} block {block}", "exec"), {"__name__": "__doc__"})
