#!/usr/bin/env python3
"""Every #include of a project header stays on its own floor or below (README, "Layout"):
text -> core and solvers -> io -> analysis -> validation -> tools; and inside core
(elements -> model -> kinematics -> dynamics -> linearization, core/README) and io (formats ->
pictures -> templates, io/README). Tests may include anything of their floor. Prints each include
that runs back up or sideways (file:line) and exits 1 when there is one. Run by ctest
(include_floors)."""
import pathlib
import re
import sys

ALLOWED = {
    "text": {"text"},
    "core": {"text", "core"},
    "solvers": {"text", "solvers"},
    "io": {"text", "core", "io"},
    "analysis": {"text", "core", "solvers", "io", "analysis"},
    "validation": {"text", "core", "solvers", "io", "analysis", "validation"},
    "tools": {"text", "core", "solvers", "io", "analysis", "validation", "tools"},
}
# Inside a floor: folder -> the folders of that floor it may include (tests/ may include all).
INNER = {
    "core": ["elements", "model", "kinematics", "dynamics", "linearization"],
    "io": ["formats", "pictures", "templates"],
}
root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
bad = 0
for floor, allowed in ALLOWED.items():
    for path in sorted((root / floor).rglob("*")):
        if path.suffix not in (".cpp", ".hpp", ".h") or "build" in path.relative_to(root).parts[:1]:
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            m = re.match(r'\s*#\s*include\s+"([a-z]+)/', line)
            if m and m.group(1) in ALLOWED and m.group(1) not in allowed:
                print(f"{path.relative_to(root)}:{number}: {floor} includes {m.group(1)}: {line.strip()}")
                bad += 1
            inner = INNER.get(floor)
            part = path.relative_to(root / floor).parts[0]
            m2 = re.match(r'\s*#\s*include\s+"' + floor + r'/([a-z]+)/', line)
            if inner and m2 and part in inner and m2.group(1) in inner:
                if inner.index(m2.group(1)) > inner.index(part):
                    print(f"{path.relative_to(root)}:{number}: {floor}/{part} includes {floor}/{m2.group(1)}, "
                          f"a folder above it: {line.strip()}")
                    bad += 1
print(f"include floors: {bad} include(s) against the floors" if bad else "include floors: every include on its floor")
sys.exit(1 if bad else 0)
