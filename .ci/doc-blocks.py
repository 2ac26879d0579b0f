#!/usr/bin/env python3
"""Run the shell blocks of README.md, docs/*.md and crates/*/README.md that a user would paste
(issue 42).

Convention (docs/README of the blocks, stated here and in .ci/run):
* Every fenced block says its language: `sh` (commands to paste), `python` (run by
  crates/vpmap-py/tests/test_docs.py), `rust` (doc tests), `json`, `yaml`, `text` (synopses,
  outputs, formulas, HTTP requests). A bare ``` fence fails this check.
* A block preceded by `<!-- not run in CI: REASON -->` is not run; the reason is printed.
* The other `sh` blocks of a file run in order, in one temporary folder holding copies of
  `examples/` and `docs/` (so a block may use what an earlier one wrote, and the repository is
  never modified), with `bash -euo pipefail`, `vpmap` on the PATH as the binary given, and
  `cargo run --release --` read as that `vpmap` (the same code, built once by `cargo test`
  instead of once more in release).
* After a file's blocks ran, every file of `examples/` they rewrote must equal the committed
  one byte for byte (the README's commands that regenerate the bundled room).

Usage: doc-blocks.py VPMAP_BINARY [--list]
"""
import filecmp
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

REPO = pathlib.Path(__file__).resolve().parents[1]
SKIP = re.compile(r"^<!-- not run in CI: (.+) -->$")
FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
TIMEOUT_S = 300


def blocks(path):
    """(line, language, text, skip reason or None) of every fenced block of a Markdown file."""
    lines = path.read_text().split("\n")
    out, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        start, lang, indent = i + 1, m.group(2), m.group(1)
        j = i + 1
        while j < len(lines) and lines[j].strip() != "```":
            j += 1
        text = "\n".join(l[len(indent):] if l.startswith(indent) else l for l in lines[i + 1 : j])
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        skip = SKIP.match(lines[k].strip()) if k >= 0 else None
        out.append((start, lang, text, skip.group(1) if skip else None))
        i = j + 1
    return out


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    vpmap = pathlib.Path(sys.argv[1]).resolve()
    listing = "--list" in sys.argv[2:]
    files = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md")),
             *sorted((REPO / "crates").glob("*/README.md"))]
    failures, ran, skipped = [], 0, 0
    for md in files:
        rel = md.relative_to(REPO)
        todo = []
        for line, lang, text, skip in blocks(md):
            if not lang:
                failures.append(f"{rel}:{line}: a fenced block without a language")
            elif lang == "sh" and skip:
                skipped += 1
                print(f"not run: {rel}:{line}: {skip}")
            elif lang == "sh":
                todo.append((line, text))
        if not todo or listing:
            for line, _ in todo:
                print(f"would run: {rel}:{line}")
            continue
        with tempfile.TemporaryDirectory(prefix="vpmap-doc-") as tmp:
            work = pathlib.Path(tmp)
            shutil.copytree(REPO / "examples", work / "examples")
            shutil.copytree(REPO / "docs", work / "docs")
            (work / "bin").mkdir()
            (work / "bin" / "vpmap").symlink_to(vpmap)
            env = dict(os.environ, PATH=f"{work / 'bin'}:{os.environ['PATH']}")
            for line, text in todo:
                script = text.replace("cargo run --release -- ", "vpmap ")
                print(f"run: {rel}:{line}", flush=True)
                ran += 1
                try:
                    r = subprocess.run(["bash", "-euo", "pipefail", "-c", script], cwd=work,
                                       env=env, capture_output=True, text=True,
                                       timeout=TIMEOUT_S)
                except subprocess.TimeoutExpired:
                    failures.append(f"{rel}:{line}: still running after {TIMEOUT_S} s")
                    continue
                if r.returncode != 0:
                    failures.append(f"{rel}:{line}: exit {r.returncode}\n{r.stdout}{r.stderr}")
            for f in (work / "examples").iterdir():
                if not filecmp.cmp(f, REPO / "examples" / f.name, shallow=False):
                    failures.append(f"{rel}: its commands rewrote examples/{f.name} differently")
    for f in failures:
        print(f"FAILED: {f}", file=sys.stderr)
    print(f"{ran} shell blocks run, {skipped} not run (reasons above), {len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
