#!/usr/bin/python3
"""The shape rules a newcomer relies on, checked on the source tree.

  check_structure.py [ROOT]

- no source file (.h, .cpp, .comp) over 600 lines;
- no function over 80 lines (signature to closing brace; lambdas count
  with the function that holds them);
- no include circle between modules (the top-level folders and the folders
  under core/);
- no include up the tree: a file includes nothing from a folder above its
  own, but for its top-level folder's basics (core/types.h, cadastre/parcels.h);
- cli/ at most 1,150 lines in all (the options of every command; the work
  stays in the library).

Prints each breach on a line of its own and exits 1 if there is any.
Functions are found by a brace scan of the code with comments and strings
blanked out: a `{` at namespace or class scope whose preceding text holds a
`)` opens a function.
"""
import os
import re
import sys

MAX_FILE_LINES = 600
MAX_FUNCTION_LINES = 80
MAX_CLI_LINES = 1150
SOURCE_DIRS = ["core", "cadastre", "valuation", "ifc_citygml", "cli", "tests", "shaders"]
EXTENSIONS = (".h", ".cpp", ".comp")
SCOPE_RE = re.compile(r"\b(namespace|struct|class|union|enum)\b[^;{}()]*$|extern\s+\"C\"\s*$")


def blank_comments_and_strings(text):
    """The text with comments, string and char literals replaced by spaces,
    newlines kept, so offsets and line numbers stay as they were."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not text[i - 1].isalnum()):
            k = text.find("(", i)
            delim = text[i + 2:k]
            j = text.find(")" + delim + '"', k)
            j = n if j < 0 else j + len(delim) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # digit separator 1'000
                out.append(c)
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j = min(n, j + 1)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def long_functions(path):
    """(first line, lines) of each function of the file longer than the limit."""
    code = blank_comments_and_strings(open(path, encoding="utf-8", errors="replace").read())
    # [ \t], not \s: \s spans newlines, and a directive after blank lines
    # took them with it, shifting every line number after it.
    code = re.sub(r"^[ \t]*#.*$", lambda m: " " * len(m.group(0)), code, flags=re.M)
    stack = []  # per open brace: 'scope', 'function' or 'other'
    last_stop = 0  # offset after the last ; { or }
    starts = {}
    found = []
    for i, c in enumerate(code):
        if c == "{":
            before = code[last_stop:i]
            in_scope = all(k == "scope" for k in stack)
            if SCOPE_RE.search(before.strip()):
                kind = "scope"
            elif in_scope and ")" in before:
                kind = "function"
                head = last_stop + len(before) - len(before.lstrip())
                starts[len(stack)] = code.count("\n", 0, head) + 1
            else:
                kind = "other"
            stack.append(kind)
            last_stop = i + 1
        elif c == "}":
            if stack:
                kind = stack.pop()
                if kind == "function":
                    first = starts[len(stack)]
                    lines = code.count("\n", 0, i) + 1 - first + 1
                    if lines > MAX_FUNCTION_LINES:
                        found.append((first, lines))
            last_stop = i + 1
        elif c == ";":
            last_stop = i + 1
    return found


def module_of(rel):
    parts = rel.split(os.sep)
    if parts[0] == "core" and len(parts) > 2:
        return "/".join(parts[:2])
    return parts[0]


def include_cycles(root, files):
    """Includes (a, b) between modules where b, through any chain, includes a back."""
    edges = {}
    for rel in files:
        a = module_of(rel)
        if a == "tests":
            continue
        for line in open(os.path.join(root, rel), encoding="utf-8", errors="replace"):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if m and os.path.exists(os.path.join(root, m.group(1))):
                b = module_of(m.group(1))
                if b != a:
                    edges.setdefault(a, set()).add(b)

    def reaches(src, dst):
        seen, todo = set(), [src]
        while todo:
            x = todo.pop()
            if x == dst:
                return True
            if x not in seen:
                seen.add(x)
                todo.extend(edges.get(x, ()))
        return False

    return sorted((a, b) for a in edges for b in edges[a] if reaches(b, a))


def includes_up(root, files):
    """(file, header) where the header lies in a folder above the file's own,
    below the top-level folder."""
    found = []
    for rel in files:
        if rel.split(os.sep)[0] == "tests":
            continue
        here = os.path.dirname(rel)
        for line in open(os.path.join(root, rel), encoding="utf-8", errors="replace"):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if not m or not os.path.exists(os.path.join(root, m.group(1))):
                continue
            there = os.path.dirname(m.group(1))
            if there != here and (here + os.sep).startswith(there + os.sep) and os.sep in there:
                found.append((rel, m.group(1)))
    return found


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    files = []
    for d in SOURCE_DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, d)):
            dirnames[:] = [x for x in dirnames if x not in ("node_modules", "build")]
            files += [os.path.relpath(os.path.join(dirpath, f), root) for f in filenames if f.endswith(EXTENSIONS)]
    breaches = []
    cli_lines = 0
    for rel in sorted(files):
        n = sum(1 for _ in open(os.path.join(root, rel), encoding="utf-8", errors="replace"))
        if rel.startswith("cli" + os.sep):
            cli_lines += n
        if n > MAX_FILE_LINES:
            breaches.append(f"{rel}: {n} lines (at most {MAX_FILE_LINES})")
        for first, lines in long_functions(os.path.join(root, rel)):
            breaches.append(f"{rel}:{first}: function of {lines} lines (at most {MAX_FUNCTION_LINES})")
    if cli_lines > MAX_CLI_LINES:
        breaches.append(f"cli/: {cli_lines} lines in all (at most {MAX_CLI_LINES})")
    for a, b in include_cycles(root, files):
        breaches.append(f"include circle: {a} -> {b} -> ... -> {a}")
    for rel, header in includes_up(root, files):
        breaches.append(f"{rel}: includes {header}, from a folder above its own")
    for b in breaches:
        print(b)
    print(f"check_structure: {len(files)} files, {len(breaches)} breaches", file=sys.stderr)
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
