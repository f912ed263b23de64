#!/usr/bin/env python3
"""Fail when the product narrates how the work went instead of saying what is true now.

README, docs, comments, tests and help texts describe the product and how to reproduce each
figure; history belongs to git and CHANGELOG.md (by release). This scans every file git tracks
(and untracked ones it does not ignore) for labels of numbered work periods and similar
narration, and prints each with its file and line.

Usage: python3 tools/ci/no_narration.py      (exit 0 when none is found, 1 otherwise)
"""
import re
import subprocess
import sys
from pathlib import Path

PATTERNS = [
    r"\bsessions?[ -]\d+",                 # "session 27", "sessions 31-32", "session-3"
    r"\b(?:this|last|previous|earlier|next) session\b",
    r"\bissues?\s+#?\d+\b",               # the project's own issue numbers
    r"\bsprints?\s+\d+",
    r"\bwork(?:ing)?[ -]periods?\b",
    r"\bround\s+\d+\s+of\s+(?:work|the project)",
]
NARRATION = re.compile("|".join(PATTERNS), re.IGNORECASE)
# Binary and generated files, and this checker (which must name what it looks for).
SKIP_SUFFIXES = {".png", ".jpg", ".glb", ".bin", ".stl", ".ply", ".wasm", ".parquet", ".lock"}
SKIP_FILES = {"tools/ci/no_narration.py", "package-lock.json"}


def files(root: Path) -> list[Path]:
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard"],
        cwd=root, capture_output=True, text=True, check=True).stdout.split("\n")
    return [root / f for f in listed
            if f and Path(f).suffix.lower() not in SKIP_SUFFIXES
            and f not in SKIP_FILES and Path(f).name not in SKIP_FILES]


def main() -> int:
    root = Path(__file__).resolve().parents[2]
    found = 0
    for path in files(root):
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError, IsADirectoryError):
            continue
        for number, line in enumerate(text.split("\n"), 1):
            match = NARRATION.search(line)
            if match:
                found += 1
                print(f"{path.relative_to(root)}:{number}: '{match.group(0)}': {line.strip()[:120]}")
    if found:
        print(f"{found} line(s) narrate the work: say what is true now and how to reproduce it; "
              "history goes to git and CHANGELOG.md")
        return 1
    print("no narration of the work in the product")
    return 0


if __name__ == "__main__":
    sys.exit(main())
