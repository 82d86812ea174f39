#!/usr/bin/env python3
"""The documentation's checks (docs/develop/testing.md, "Documentation checks").

  check_docs.py citations [ROOT]
      1. Every .md file a source file cites exists. Source files: *.cpp *.hpp *.h *.py *.m *.sh and
         CMakeLists.txt, tracked or new (git ls-files; outside a git checkout every file), never
         build*/. A citation is a path ending in .md (`docs/theory/ode45.md`, `README.md`); it
         exists relative to the repository root or to the citing file's folder. Files that programs
         write (report.md of `flexmb validate`, bench.md of flexmb_bench) are not in the source tree
         and are not citations.
      2. Every header (*.hpp, *.h) is named in its folder's README.md: its file name or its stem as a
         whole word, case-sensitive (`Statics` or `Statics.hpp`). A folder without a README.md uses
         the nearest one above it (analysis/tests/ -> analysis/README.md), never the top-level
         README.md, which is for users.
      Run by ctest (docs_citations). Prints every miss (file:line) and exits 1 when there is one.

  check_docs.py commands --flexmb PATH [--build-dir DIR] [--root ROOT] [PAGE ...]
      Runs what the pages under docs/ show (default: every page but docs/generated/), page by page,
      each in a fresh scratch folder <build>/docs-run/<page>/ holding a copy of datfiles/ and a link
      `build` to the build folder, with `flexmb` on the PATH:
      - ```console blocks: every line starting with `$ ` is a command (a line ending in `\\`
        continues on the next); lines without `$ ` are output and are not checked. A command must
        exit 0, or N where its line says `# exit N`.
      - ```python blocks: one script per page, run by python3 with PYTHONPATH=<build>/python; skipped
        (with a message) when the module is not built.
      - ```octave blocks: one script per page, run by octave-cli; skipped (with a message) when
        octave-cli or <build>/octave/spacar.mex is missing.
      - a fenced block right after a line `<!-- file: NAME -->` is written to NAME in the scratch
        folder before the page's commands run.
      Pictures a page shows from generated/<page>/PATH are copied there from PATH in its scratch folder
      after its commands ran (docs/generated/ is git-ignored). The top-level README.md runs too: its pictures are
      tracked in docs/images/ (GitHub shows them), refreshed here with a note when they changed.
      Run by tools/docs.sh (ctest docs_site).
"""
import argparse
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

SOURCE_SUFFIXES = {".cpp", ".hpp", ".h", ".py", ".m", ".sh"}
# A path ending in .md, not inside a longer word, a printf pattern (%s/bench.md), a shell variable
# ($page.md, $dir/x.md) or a path assembled at run time ("/report.md").
CITATION = re.compile(r"(?<![\w./%$}-])((?:\.\.?/)*[\w-][\w.-]*(?:/[\w.-]+)*\.md)(?![\w])")
# Written by programs, never in the source tree: flexmb validate's report, flexmb_bench's fragment,
# the main job's tables of tools/bench/guidance_continuum.py and single_run_economics.py.
GENERATED = {"report.md", "bench.md", "guidance_continuum.md", "single_run_economics.md"}


def repo_files(root):
    """Tracked and new (not ignored) files, relative to root; every file outside a git checkout."""
    try:
        out = subprocess.run(["git", "-C", str(root), "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                             check=True, capture_output=True).stdout.decode()
        files = [pathlib.Path(f) for f in out.split("\0") if f]
    except (OSError, subprocess.CalledProcessError):
        files = [p.relative_to(root) for p in root.rglob("*") if p.is_file()]
    keep = []
    for f in files:
        if f.parts[0].startswith("build") or any(part.startswith(".") for part in f.parts[:-1]):
            continue
        if (root / f).is_file():  # deleted but still tracked: gone
            keep.append(f)
    return sorted(set(keep))


def check_citations(root, files):
    misses = 0
    for f in files:
        if f.suffix not in SOURCE_SUFFIXES and f.name != "CMakeLists.txt":
            continue
        text = (root / f).read_text(errors="replace")
        for number, line in enumerate(text.splitlines(), 1):
            for m in CITATION.finditer(line):
                cited = m.group(1)
                if pathlib.PurePosixPath(cited).name in GENERATED:
                    continue
                if (root / cited).is_file() or (root / f.parent / cited).is_file():
                    continue
                print(f"{f}:{number}: cites {cited}, which is neither {cited} nor {f.parent / cited}")
                misses += 1
    return misses


def nearest_readme(root, folder):
    while folder != pathlib.Path("."):
        if (root / folder / "README.md").is_file():
            return folder / "README.md"
        folder = folder.parent
    return None


def check_headers(root, files):
    misses = 0
    readmes = {}
    for f in files:
        if f.suffix not in (".hpp", ".h"):
            continue
        readme = nearest_readme(root, f.parent)
        if readme is None:
            print(f"{f}: no README.md in its folder or a folder above it (below the top level)")
            misses += 1
            continue
        if readme not in readmes:
            readmes[readme] = (root / readme).read_text(errors="replace")
        if not re.search(r"(?<![\w])" + re.escape(f.stem) + r"(?![\w])", readmes[readme]):
            print(f"{f}: not named in {readme} (its name {f.name} or {f.stem})")
            misses += 1
    return misses


def citations(args):
    root = pathlib.Path(args.root).resolve()
    files = repo_files(root)
    cited = check_citations(root, files)
    named = check_headers(root, files)
    print("docs citations: " + ("every cited .md exists" if not cited else f"{cited} citation(s) of missing .md files")
          + "; " + ("every header is named in its folder's README" if not named else f"{named} header(s) not named"))
    return 1 if cited or named else 0


# ---------------------------------------------------------------------------------------------- commands

FENCE = re.compile(r"^(\s*)```\s*([\w+-]*)\s*$")
EXPECT = re.compile(r"#\s*exit\s+(\d+)\b")
FILE_MARK = re.compile(r"^\s*<!--\s*file:\s*([\w.-]+)\s*-->\s*$")


def blocks(text):
    """(language, lines, file) of every fenced block, indentation of its fence removed; file is NAME
    when the line before the fence is `<!-- file: NAME -->`, else None."""
    out, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        named = FILE_MARK.match(lines[i - 1]) if i > 0 else None
        indent, lang, body = len(m.group(1)), m.group(2), []
        i += 1
        while i < len(lines) and not re.match(r"^\s*```\s*$", lines[i]):
            body.append(lines[i][indent:] if not indent or lines[i][:indent].isspace() else lines[i].lstrip())
            i += 1
        out.append((lang, body, named.group(1) if named else None))
        i += 1
    return out


def console_commands(body):
    cmds, current = [], None
    for line in body:
        if current is not None:
            current += "\n" + line
        elif line.startswith("$ "):
            current = line[2:]
        else:
            continue
        if not current.endswith("\\"):
            cmds.append(current)
            current = None
    if current is not None:
        cmds.append(current.rstrip("\\"))
    return cmds


def page_key(rel):
    return str(rel.with_suffix("")).replace(os.sep, "-").replace("/", "-")


def run(cmd, cwd, env, timeout):
    try:
        p = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired as e:
        return None, f"timed out after {timeout} s\n" + str(e.stdout or "") + str(e.stderr or "")


def tail(text, n=25):
    lines = text.rstrip().splitlines()
    return "\n".join("    " + l for l in lines[-n:])


def python_works(python, env):
    return subprocess.run([python, "-c", "import flexmb"], env=env, capture_output=True).returncode == 0


def commands(args):
    root = pathlib.Path(args.root).resolve()
    build = pathlib.Path(args.build_dir).resolve()
    flexmb = pathlib.Path(args.flexmb).resolve()
    if not os.access(flexmb, os.X_OK):
        print(f"check_docs: {flexmb} is not an executable (build it first: cmake --build {build} --target flexmb)")
        return 1
    docs = root / "docs"
    pages = [pathlib.Path(p) for p in args.pages] or [pathlib.Path("../README.md")] + sorted(
        p.relative_to(docs) for p in docs.rglob("*.md") if p.relative_to(docs).parts[0] != "generated")
    runs = build / "docs-run"
    bindir = runs / "bin"
    bindir.mkdir(parents=True, exist_ok=True)
    link = bindir / "flexmb"
    if link.is_symlink() or link.exists():
        link.unlink()
    link.symlink_to(flexmb)
    # Debian's python3 (the one the module is built for, with NumPy) before another one on the PATH.
    python = shutil.which("python3", path="/usr/bin") or shutil.which("python3") or "python3"
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(bindir), str(pathlib.Path(python).parent), env.get("PATH", "")])
    pyenv = dict(env)
    pyenv["PYTHONPATH"] = str(build / "python") + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    octave = shutil.which("octave-cli")
    failures = total = 0
    for rel in pages:
        text = (docs / rel).read_text()
        found = blocks(text)
        cmds = [c for lang, body, _ in found if lang == "console" for c in console_commands(body)]
        py = [body for lang, body, _ in found if lang == "python"]
        oc = [body for lang, body, _ in found if lang == "octave"]
        files = [(name, body) for _, body, name in found if name]
        readme = rel == pathlib.Path("../README.md")
        key = "README" if readme else page_key(rel)
        # The README's pictures are tracked (GitHub shows them): docs/images/, refreshed here.
        shown = r"docs/images/" if readme else r"generated/" + re.escape(key) + r"/"
        pictures = sorted(set(re.findall(shown + r"([\w.-]+(?:/[\w.-]+)*\.(?:svg|png))", text)))
        if not (cmds or py or oc or pictures or files):
            continue
        start = time.time()
        scratch = runs / key
        shutil.rmtree(scratch, ignore_errors=True)
        scratch.mkdir(parents=True)
        shutil.copytree(root / "datfiles", scratch / "datfiles")
        (scratch / "build").symlink_to(build)
        for name, body in files:
            (scratch / name).write_text("\n".join(body) + "\n")
        done, bad, notes = 0, 0, []
        for cmd in cmds:
            m = EXPECT.search(cmd)
            expected = int(m.group(1)) if m else 0
            code, out = run(["bash", "-c", "set -o pipefail\n" + cmd], scratch, env, args.timeout)
            done += 1
            if code != expected:
                bad += 1
                print(f"docs: {rel}: `{cmd}` exited {code}, expected {expected}:\n{tail(out)}")
        if py:
            if python_works(python, pyenv):
                (scratch / "docs_example.py").write_text("\n".join("\n".join(b) for b in py) + "\n")
                code, out = run([python, "docs_example.py"], scratch, pyenv, args.timeout)
                done += 1
                if code != 0:
                    bad += 1
                    print(f"docs: {rel}: its Python example failed (exit {code}):\n{tail(out)}")
            else:
                notes.append(f"Python examples skipped: `import flexmb` fails with PYTHONPATH={build / 'python'} "
                             "(the module is built by a full build: bash tools/setup.sh)")
        if oc:
            if octave and (build / "octave" / "spacar.mex").is_file():
                (scratch / "docs_example.m").write_text("\n".join("\n".join(b) for b in oc) + "\n")
                code, out = run([octave, "--no-gui", "--norc", "--quiet", "docs_example.m"], scratch, env, args.timeout)
                done += 1
                if code != 0:
                    bad += 1
                    print(f"docs: {rel}: its Octave example failed (exit {code}):\n{tail(out)}")
            else:
                notes.append("Octave examples skipped: " + ("no octave-cli" if not octave else
                                                             f"no {build / 'octave' / 'spacar.mex'}"))
        if pictures:
            dest = docs / "images" if readme else docs / "generated" / key
            dest.mkdir(parents=True, exist_ok=True)
            for name in pictures:
                found = scratch / name
                if found.is_file():
                    (dest / name).parent.mkdir(parents=True, exist_ok=True)
                    if readme and (not (dest / name).is_file() or (dest / name).read_bytes() != found.read_bytes()):
                        notes.append(f"updated docs/images/{name}: commit it")
                    shutil.copyfile(found, dest / name)
                else:
                    bad += 1
                    print(f"docs: {rel}: shows generated/{key}/{name}, which its commands did not write")
        total += done
        failures += bad
        status = "ok" if not bad else f"{bad} FAILED"
        print(f"docs: {rel}: {done} command(s) and example(s) {status} ({time.time() - start:.1f} s)"
              + "".join(f"; {n}" for n in notes))
    print(f"docs commands: {total} run, " + ("all as the pages say" if not failures else f"{failures} failed"))
    return 1 if failures else 0


def main():
    here = pathlib.Path(__file__).resolve().parent.parent
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="what", required=True)
    c = sub.add_parser("citations", help="cited .md files exist; headers are named in their README")
    c.add_argument("root", nargs="?", default=str(here))
    r = sub.add_parser("commands", help="run the commands and examples the docs show")
    r.add_argument("--flexmb", required=True)
    r.add_argument("--build-dir", default=str(here / "build"))
    r.add_argument("--root", default=str(here))
    r.add_argument("--timeout", type=int, default=600, help="seconds per command or example")
    r.add_argument("pages", nargs="*", help="pages relative to docs/ (default: all)")
    args = p.parse_args()
    return citations(args) if args.what == "citations" else commands(args)


if __name__ == "__main__":
    sys.exit(main())
