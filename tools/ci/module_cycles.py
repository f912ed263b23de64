#!/usr/bin/env python3
"""Fail when a crate's modules import each other in a cycle.

Within a crate, modules are layers: a module may use the ones below it and never the ones above.
For every folder of modules (the crate root, then each folder module) this builds the graph
"sibling A names something of sibling B" from `use crate::…`, `use super::…`, inline `crate::…`
paths and the re-exports that resolve a name to the module defining it, and reports every cycle.
Unit-test modules (`#[cfg(test)] mod … { … }`) are left out: tests may use anything.

Usage: python3 tools/ci/module_cycles.py [CRATE_DIR ...]   (default: every crates/*)
Exit 0 when no crate has a cycle, 1 otherwise (the cycles printed, each as a path of modules
with the line that makes each edge).
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

USE_RE = re.compile(r"\b(?:pub(?:\([^)]*\))?\s+)?use\s+([^;]+);", re.S)
PATH_RE = re.compile(r"(?<![\w:])((?:crate|super|self)(?:::[A-Za-z_][A-Za-z0-9_]*)+)")
MOD_RE = re.compile(r"^\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+([A-Za-z_][A-Za-z0-9_]*)\s*;", re.M)


def strip_comments_and_strings(text: str) -> str:
    """Blank out comments, string and char literals, keeping line numbers."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            i = j
            continue
        if text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append("\n" * text.count("\n", i, j))
            i = j
            continue
        m = re.match(r'r(#*)"', text[i:i + 10]) if c == "r" and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")) else None
        if m:
            end = '"' + m.group(1)
            j = text.find(end, i + len(m.group(0)))
            j = n if j < 0 else j + len(end)
            out.append("\n" * text.count("\n", i, j))
            i = j
            continue
        if c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append("\n" * text.count("\n", i, j + 1))
            i = j + 1
            continue
        if c == "'" and re.match(r"'(\\.|[^\\'])'", text[i:i + 4]) or text.startswith("'\\u{", i):
            j = text.find("'", i + 1 if text[i + 1] != "\\" else i + 3)
            i = j + 1
            out.append(" ")
            continue
        out.append(c)
        i += 1
    return "".join(out)


def strip_test_modules(text: str) -> str:
    """Blank out `#[cfg(test)] mod name { ... }` blocks, keeping line numbers."""
    while True:
        m = re.search(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*\{", text)
        if not m:
            return text
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        text = text[: m.start()] + "\n" * text.count("\n", m.start(), j) + text[j:]


def expand_use_tree(tree: str) -> list[str]:
    """`a::{b, c::{d, e}}` -> ['a::b', 'a::c::d', 'a::c::e'] (aliases and globs kept as paths)."""
    tree = re.sub(r"\s+as\s+\w+", "", tree)
    tree = re.sub(r"\s+", "", tree)

    def split_top(s: str) -> list[str]:
        parts, depth, cur = [], 0, ""
        for ch in s:
            if ch == "," and depth == 0:
                parts.append(cur)
                cur = ""
                continue
            depth += {"{": 1, "}": -1}.get(ch, 0)
            cur += ch
        if cur:
            parts.append(cur)
        return parts

    def go(prefix: str, s: str) -> list[str]:
        brace = s.find("{")
        if brace < 0:
            return [prefix + s]
        head, body = s[:brace], s[brace + 1: s.rfind("}")]
        out = []
        for part in split_top(body):
            out += go(prefix + head, part)
        return out

    return go("", tree)


class Crate:
    """The module tree of one crate, from its src/lib.rs (or main.rs)."""

    def __init__(self, root: Path):
        self.root = root
        src = root / "src"
        entry = src / "lib.rs" if (src / "lib.rs").exists() else src / "main.rs"
        self.files: dict[tuple[str, ...], Path] = {}
        self._walk((), entry)
        self.texts = {
            m: strip_test_modules(strip_comments_and_strings(p.read_text(encoding="utf-8")))
            for m, p in self.files.items()
        }
        self.reexports = {m: self._reexports(m) for m in self.files}

    def _walk(self, module: tuple[str, ...], path: Path) -> None:
        self.files[module] = path
        text = strip_test_modules(strip_comments_and_strings(path.read_text(encoding="utf-8")))
        folder = path.parent if path.name in ("lib.rs", "main.rs", "mod.rs") else path.with_suffix("")
        for name in MOD_RE.findall(text):
            for cand in (folder / f"{name}.rs", folder / name / "mod.rs"):
                if cand.exists():
                    self._walk(module + (name,), cand)
                    break

    def _reexports(self, module: tuple[str, ...]) -> dict[str, tuple[str, ...]]:
        """Names a module re-exports with `pub use`, mapped to the module path they come from."""
        out = {}
        for m in re.finditer(r"\bpub(?:\([^)]*\))?\s+use\s+([^;]+);", self.texts[module]):
            for path in expand_use_tree(m.group(1)):
                parts = [p for p in path.split("::") if p]
                if not parts or parts[-1] == "*":
                    continue
                name = parts[-1]
                whole = self.resolve(module, parts)
                if whole is not None and whole[-1:] == (name,):
                    out[name] = whole  # a module re-exported under its own name
                    continue
                target = self.resolve(module, parts[:-1])
                if target is not None:
                    out[name] = target
        return out

    def resolve(self, module: tuple[str, ...], parts: list[str]) -> tuple[str, ...] | None:
        """The deepest known module a path (without its last item) starts in, from `module`."""
        if not parts:
            return None
        if parts[0] == "crate":
            base, rest = (), parts[1:]
        elif parts[0] in ("super", "self"):
            base = module
            rest = list(parts)
            while rest and rest[0] in ("super", "self"):
                if rest[0] == "super":
                    base = base[:-1]
                rest = rest[1:]
        elif module + (parts[0],) in self.files:
            base, rest = module, parts
        else:
            return None
        cur = base
        for p in rest:
            if cur + (p,) in self.files:
                cur = cur + (p,)
            elif p in getattr(self, "reexports", {}).get(cur, {}):
                # A re-exported module (`pub use request::defaults;`) names its own file.
                cur = self.reexports[cur][p]
            else:
                break
        return cur

    def references(self, module: tuple[str, ...]):
        """(target module, line) for every path in `module` that names another module's item."""
        text = self.texts[module]
        for m in USE_RE.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            for path in expand_use_tree(m.group(1)):
                yield from self._target(module, [p for p in path.split("::") if p], line)
        for m in PATH_RE.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            yield from self._target(module, m.group(1).split("::"), line)

    def _target(self, module, parts, line):
        if parts and parts[0] not in ("crate", "super", "self"):
            if module + (parts[0],) not in self.files:
                return
        target = self.resolve(module, parts[:-1] if len(parts) > 1 else parts)
        if target is None:
            return
        # Follow a re-export of the named item to the module that defines it.
        seen = set()
        item = parts[-1] if len(parts) > 1 else None
        while item and item in self.reexports.get(target, {}) and (target, item) not in seen:
            seen.add((target, item))
            target = self.reexports[target][item]
        yield target, line


def sibling_edges(crate: Crate):
    """edges[folder][(a, b)] = (file, line): in folder, sibling a uses sibling b."""
    edges: dict[tuple[str, ...], dict[tuple[str, str], tuple[Path, int]]] = {}
    for module in crate.files:
        for target, line in crate.references(module):
            # The common folder of the two modules, and the siblings below it they lie in.
            k = 0
            while k < min(len(module), len(target)) and module[k] == target[k]:
                k += 1
            if k == len(module) or k == len(target):
                continue  # a module using its own child or parent: folder structure, not a layer edge
            folder = module[:k]
            a, b = module[k], target[k]
            edges.setdefault(folder, {}).setdefault((a, b), (crate.files[module], line))
    return edges


def find_cycles(edge_map: dict[tuple[str, str], tuple[Path, int]]):
    """Strongly connected components with more than one node (Tarjan)."""
    graph: dict[str, list[str]] = {}
    for a, b in edge_map:
        graph.setdefault(a, []).append(b)
        graph.setdefault(b, [])
    index, low, stack, on, comps = {}, {}, [], set(), []
    counter = [0]

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in graph:
        if v not in index:
            strong(v)
    return comps


def main(argv: list[str]) -> int:
    repo = Path(__file__).resolve().parents[2]
    crates = [Path(a).resolve() for a in argv] or sorted(p.parent for p in (repo / "crates").glob("*/Cargo.toml"))
    failed = 0
    for root in crates:
        if not (root / "src").exists():
            continue
        crate = Crate(root)
        for folder, edge_map in sorted(sibling_edges(crate).items()):
            for comp in find_cycles(edge_map):
                failed += 1
                where = "::".join(("crate",) + folder)
                print(f"{root.name}: modules of {where} in a cycle: {', '.join(comp)}")
                members = set(comp)
                for (a, b), (path, line) in sorted(edge_map.items()):
                    if a in members and b in members:
                        print(f"    {a} -> {b}   ({path.relative_to(repo)}:{line})")
    if failed:
        print(f"{failed} cycle(s): move the shared item down to a module both can use.")
        return 1
    print(f"no module cycles in {len(crates)} crates")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
