"""Every Python block of README.md, docs/*.md and crates/*/README.md runs (issue 42).

A fenced `python` block is run as a script in a fresh folder holding a copy of `examples/` and a
`scenes/` folder with the bundled office, the way a user pastes it from the repository's root;
a block preceded by `<!-- not run in CI: REASON -->` is skipped with its reason (the convention
of .ci/doc-blocks.py, which runs the shell blocks).
"""

import pathlib
import re
import shutil
import subprocess
import sys

import pytest

from conftest import REPO

FENCE = re.compile(r"^```(\S*)\s*$")
SKIP = re.compile(r"^<!-- not run in CI: (.+) -->$")


def python_blocks():
    """(file:line, text, skip reason or None) of every fenced python block."""
    found = []
    for md in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md")),
               *sorted((REPO / "crates").glob("*/README.md"))]:
        lines = md.read_text().split("\n")
        i = 0
        while i < len(lines):
            m = FENCE.match(lines[i])
            if not m:
                i += 1
                continue
            j = i + 1
            while j < len(lines) and lines[j].strip() != "```":
                j += 1
            if m.group(1) == "python":
                k = i - 1
                while k >= 0 and not lines[k].strip():
                    k -= 1
                skip = SKIP.match(lines[k].strip()) if k >= 0 else None
                found.append((f"{md.relative_to(REPO)}:{i + 1}", "\n".join(lines[i + 1 : j]),
                              skip.group(1) if skip else None))
            i = j + 1
    return found


BLOCKS = python_blocks()


def test_the_docs_have_python_blocks_to_run():
    assert [b for b in BLOCKS if b[2] is None], "no runnable python block found in the docs"


@pytest.mark.parametrize("where,text,skip", BLOCKS, ids=[b[0] for b in BLOCKS])
def test_python_block_runs(where, text, skip, tmp_path):
    if skip:
        pytest.skip(f"{where}: {skip}")
    shutil.copytree(REPO / "examples", tmp_path / "examples")
    (tmp_path / "scenes").mkdir()
    shutil.copy(REPO / "examples" / "office.json", tmp_path / "scenes" / "office.json")
    script = tmp_path / "block.py"
    script.write_text(text)
    r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, f"{where} failed:\n{r.stdout}\n{r.stderr}"
    assert r.stdout.strip(), f"{where} printed nothing"
