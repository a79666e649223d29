#!/usr/bin/env python3
"""Checks every project #include against the layer table of docs/architecture.md.

The table (the section "Layers") names each library's folder, the prefixes its headers are
included by, and the libraries it depends on. A file in a folder may include its own folder's
headers and those of every library it depends on, directly or through others; anything else is
an upward or sideways include, and this test fails naming the file, line and rule.
Run by ctest (include_layers); `python3 tests/layers/check_layers.py SOURCE_DIR`.
"""
import pathlib
import re
import sys

TABLE_ROW = re.compile(r"^\|\s*`([^`]+)`\s*\|\s*`([^`]+)`\s*\|([^|]*)\|([^|]*)\|")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
SOURCES = {".h", ".cpp", ".hpp", ".cc"}


def parse_table(doc):
    """library -> (folder, [include prefixes], [dependencies])"""
    layers = {}
    in_section = False
    for line in doc.splitlines():
        if line.startswith("## "):
            in_section = line.strip() == "## Layers (libraries, lowest first)"
            continue
        match = TABLE_ROW.match(line) if in_section else None
        if not match:
            continue
        library, folder, prefixes, depends = match.groups()
        prefixes = re.findall(r"`([^`]+)`", prefixes)
        depends = [d.strip().strip("`") for d in depends.split(",")]
        depends = [d for d in depends if d and d not in ("—", "-")]
        layers[library] = (folder.rstrip("/"), prefixes, depends)
    return layers


def closure(layers, library, seen=None):
    seen = set() if seen is None else seen
    for dep in layers[library][2]:
        if dep not in layers:
            raise SystemExit(f"layer table: {library} depends on unknown library {dep}")
        if dep not in seen:
            seen.add(dep)
            closure(layers, dep, seen)
    return seen


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    layers = parse_table((root / "docs" / "architecture.md").read_text())
    if len(layers) < 5:
        raise SystemExit(f"layer table not found or too small in docs/architecture.md: {layers}")
    owner_of_prefix = {}
    for library, (_, prefixes, _) in layers.items():
        for prefix in prefixes:
            owner_of_prefix[prefix] = library
    problems = []
    checked = 0
    # Every library folder under server/ must have its row, so a new one cannot go unchecked.
    folders = {folder for folder, _, _ in layers.values()}
    for path in sorted((root / "server").iterdir()):
        if path.is_dir() and str(path.relative_to(root)) not in folders:
            problems.append(f"layer table: folder {path.relative_to(root)} has no row")
    for library, (folder, _, _) in layers.items():
        allowed = closure(layers, library) | {library}
        base = root / folder
        if not base.is_dir():
            problems.append(f"layer table: folder {folder} of {library} does not exist")
            continue
        # A nested folder with its own row (proto/rpc/ inside proto/) is that row's.
        nested = [root / f for f in folders if f != folder and f.startswith(folder + "/")]
        for path in sorted(base.rglob("*")):
            if path.suffix not in SOURCES or any(n in path.parents for n in nested):
                continue
            for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                match = INCLUDE.match(line)
                if not match:
                    continue
                target = match.group(1)
                owner = next((owner_of_prefix[p] for p in owner_of_prefix if target.startswith(p)),
                             None)
                checked += 1
                if owner is not None and owner not in allowed:
                    problems.append(f"{path.relative_to(root)}:{number}: {library} includes "
                                    f'"{target}" of {owner}, which it does not depend on')
    for problem in problems:
        print(problem)
    print(f"{checked} includes in {len(layers)} layers checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
