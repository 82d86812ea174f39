#!/usr/bin/env python3
"""No two source files share a name (issue 51): a .hpp, .h, .cpp, .py or .m file's basename is
unique in the tree, so that an include, a comment or a search naming it means one file (README.md,
one per folder by design, is not a source file). Walks the tracked tree: the files git knows or
would add (`git ls-files --cached --others --exclude-standard`, without those deleted), else every
file outside build*/ and .git. Prints each clash with the paths that share the name and exits 1 when
there is one. Run by ctest (file_names)."""
import collections
import pathlib
import subprocess
import sys

ENDINGS = (".hpp", ".h", ".cpp", ".py", ".m")
root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)


def tree_files():
    try:
        git = ["git", "-C", str(root), "ls-files", "-z", "--cached", "--others", "--exclude-standard"]
        listed = subprocess.run(git, capture_output=True, check=True).stdout.decode().split("\0")
        return sorted({p for p in listed if p and (root / p).is_file()})
    except (OSError, subprocess.CalledProcessError):  # not a git checkout (a release tarball)
        return sorted(str(p.relative_to(root)) for p in root.rglob("*")
                      if p.is_file() and not any(part == ".git" or part.startswith("build")
                                                 for part in p.relative_to(root).parts))


def skipped(path):
    return any(part == ".git" or part.startswith("build") for part in pathlib.PurePath(path).parts)


by_name = collections.defaultdict(list)
for path in tree_files():
    if path.endswith(ENDINGS) and not skipped(path):
        by_name[pathlib.PurePath(path).name].append(path)
clashes = {name: paths for name, paths in by_name.items() if len(paths) > 1}
for name, paths in sorted(clashes.items()):
    print(f"{name}: " + ", ".join(paths))
print(f"file names: {len(clashes)} name(s) shared by more than one file" if clashes
      else f"file names: {sum(len(p) for p in by_name.values())} source files, no two with the same name")
sys.exit(1 if clashes else 0)
