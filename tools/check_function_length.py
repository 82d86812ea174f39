#!/usr/bin/env python3
"""No long procedures (issue 51): at most one function over 150 lines in the project's .cpp/.hpp files
outside tests/ folders and build*/, besides the declaration tables of ALLOWED (data written as code).
A function is a body whose opening brace follows a parameter list `)` (possibly with const, noexcept,
override, a trailing return type or a constructor's initializer list); its lambdas and local classes
count as part of it. Its length runs from the line of its name to its closing brace. The scanner
matches braces after blanking comments, string and character literals and preprocessor lines. Prints
each function over the limit (file:line, name, lines) and exits 1 when more than one is not allowed.
Run by ctest (function_length)."""
import os
import pathlib
import re
import sys

LIMIT = 150
MAX_OVER = 1
# Declaration tables: "path:function" whose length is data, not procedure.
ALLOWED = {
    "core/elements/ElementRegistry.cpp:elementTypes",  # one entry per element type
    "io/formats/KeywordTable.cpp:buildTable",  # one entry per .dat keyword
}
# Procedures still to be split (issue 51 stays open until this is empty): each may not grow past the
# length given, and none may be added to it.
NOT_YET_SPLIT = {}

SCOPE_HEAD = re.compile(r"^(?:template\s*<.*>\s*)?(?:namespace|class|struct|union|enum|extern)\b", re.S)
QUALIFIERS = r"(?:\s|const\b|noexcept\b(?:\s*\([^()]*\))?|override\b|final\b|mutable\b|volatile\b|&)*"
FUNCTION_HEAD = re.compile(r"\)" + QUALIFIERS + r"(?:->[^;{}=]*)?$", re.S)
# A constructor's initializer list: `) : a_(x), b_{y}`; a brace after `: ... name` opens a member's init.
INIT_LIST = re.compile(r"\)" + QUALIFIERS + r":(?!:)", re.S)
NAME = re.compile(r"((?:[\w~]+\s*(?:<[^;{}()]*>)?\s*::\s*)*(?:operator\s*\(\s*\)|operator[^\w(][^(]*|~?\w+))\s*\(")


def blank(text):
    """The text with comments, literals and preprocessor lines turned to spaces (newlines kept)."""
    out = list(text)
    i, n = 0, len(text)
    line_start = True

    def clear(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if c == "\n":
            line_start = True
            i += 1
            continue
        if line_start and c in " \t":
            i += 1
            continue
        if line_start and c == "#":
            j = i
            while j < n and (text[j] != "\n" or text[j - 1] == "\\"):
                j += 1
            clear(i, j)
            i = j
            continue
        line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            clear(i, j)
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            clear(i, j)
            i = j
        elif c == "R" and text.startswith('R"', i) and not re.match(r"\w", text[i - 1:i].replace("8", "")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            clear(i, j)
            i = j
        elif c == '"' or (c == "'" and not re.search(r"\b\d[\w']*$", text[max(0, i - 40):i])):  # not 1'000
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            clear(i, min(j + 1, n))
            i = j + 1
        else:
            i += 1
    return "".join(out)


def closing(code, i):
    """The index of the brace that closes the one at i."""
    depth = 0
    for j in range(i, len(code)):
        if code[j] == "{":
            depth += 1
        elif code[j] == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(code) - 1


def functions(text):
    """(line, name, lines) of every function body in one file's text."""
    code = blank(text)
    line_of = [0] * (len(code) + 1)
    line = 1
    for k, c in enumerate(code):
        line_of[k] = line
        line += c == "\n"
    found = []
    head_start = 0
    i = 0
    while i < len(code):
        c = code[i]
        if c in ";}":
            head_start = i + 1
        elif c == "{":
            head = code[head_start:i].strip()
            end = closing(code, i)
            if SCOPE_HEAD.match(re.sub(r"^(?:\w+\s*:(?!:))+\s*", "", head)):
                head_start = i + 1  # namespace, class, ...: its members are scanned in turn
            elif INIT_LIST.search(head) and not FUNCTION_HEAD.search(head) and re.search(r"[\w>]$", head):
                i = end  # a member's brace initializer; the head goes on
            elif FUNCTION_HEAD.search(head):
                offset = len(code[head_start:i]) - len(code[head_start:i].lstrip())
                signature = re.sub(r"^(?:\w+\s*:(?!:)\s*)+", "", head)
                signature = re.sub(r"^template\s*<[^{;]*?>\s*(?=\w)", "", signature)
                m = NAME.search(signature)
                name = re.sub(r"\s+", "", m.group(1)) if m else "(lambda)"
                if m:
                    start = head_start + offset + head.find(m.group(1)) if m.group(1) in head else i
                else:
                    start = head_start + offset
                found.append((line_of[start], name, line_of[end] - line_of[start] + 1))
                i = end
                head_start = end + 1
            else:
                i = end  # data: an initializer, an array
        i += 1
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    over, allowed, pending = [], [], []
    paths = []
    for folder, subfolders, files in os.walk(root):
        top = folder == str(root)
        subfolders[:] = [d for d in subfolders if d != "tests" and not d.startswith(".")
                         and not (top and d.startswith("build"))]
        paths += [pathlib.Path(folder) / f for f in files if f.endswith((".cpp", ".hpp"))]
    for path in sorted(paths):
        rel = path.relative_to(root)
        for line, name, length in functions(path.read_text(errors="replace")):
            if length > LIMIT:
                key = f"{rel.as_posix()}:{name}"
                if key in ALLOWED:
                    allowed.append((rel.as_posix(), line, name, length))
                elif key in NOT_YET_SPLIT and length <= NOT_YET_SPLIT[key]:
                    pending.append((rel.as_posix(), line, name, length))
                else:
                    over.append((rel.as_posix(), line, name, length))
    for rel, line, name, length in over:
        print(f"{rel}:{line}: {name}: {length} lines")
    for rel, line, name, length in allowed:
        print(f"{rel}:{line}: {name}: {length} lines (a declaration table, allowed)")
    for rel, line, name, length in pending:
        print(f"{rel}:{line}: {name}: {length} lines (still to be split: NOT_YET_SPLIT)")
    print(f"function length: {len(over)} function(s) over {LIMIT} lines, at most {MAX_OVER} allowed")
    return 1 if len(over) > MAX_OVER else 0


if __name__ == "__main__":
    sys.exit(main())
