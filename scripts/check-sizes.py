#!/usr/bin/env python3
"""Checks that no source file of ours passes 500 lines and no function 80 (the house's limits: a
file is read whole, a function at a glance).

    python3 scripts/check-sizes.py [ROOT] [--max-file 500] [--max-function 80]

Files: the C++ (.h, .cpp), Python and shell files under ROOT, build folders and out/ left out.
A function's lines run from the first line of its signature to its closing brace (C++) or from
its `def` to its last line (Python, by the ast module). C++ functions are found by matching
braces in the text with comments and literals blanked: a brace opens a function body when what
precedes it at namespace or class level ends with a parameter list (or an initializer list), so
a lambda counts as part of the function it is written in. Prints each file or function over its
limit and exits 1 if there is one.
"""
import argparse
import ast
import os
import re
import sys

SKIP_DIRS = {".git", "out", "__pycache__"}
CODE = (".h", ".cpp", ".py", ".sh")


def source_files(root):
    for base, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("build"))
        for f in sorted(files):
            if f.endswith(CODE):
                yield os.path.join(base, f)


def is_digit_separator(text, i):
    """Whether the ' at i separates the digits of a number (1'000'000, 0xff'ff): the word before it
    starts with a digit (u8'x', L'x' and a character after a name are literals)."""
    j = i
    while j > 0 and (text[j - 1].isalnum() or text[j - 1] == "_"):
        j -= 1
    return j < i and text[j].isdigit() and i + 1 < len(text) and text[i + 1].isalnum()


def blank_comments_and_literals(text):
    """The text with comments, string and character literals replaced by spaces (newlines kept)."""
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
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "'" and is_digit_separator(text, i):
            out.append(c)
            i += 1
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(" " * (j - i))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


SCOPE_WORDS = re.compile(r"\b(namespace|class|struct|union|enum|extern)\b")
FUNCTION_HEAD = re.compile(
    r"\)\s*(const|override|final|noexcept|mutable|volatile|&|&&|->\s*[\w:<>,\s*&]+|\s)*$"
)


def cpp_functions(text):
    """(name, first line, last line) of every function body at namespace or class level."""
    code = blank_comments_and_literals(text)
    line_at = [0] * (len(code) + 1)
    line = 1
    for i, c in enumerate(code):
        line_at[i] = line
        if c == "\n":
            line += 1
    stack = []  # kinds of the open braces: "scope", "function" or "other"
    head_start = 0
    found = []
    for i, c in enumerate(code):
        if c == "{":
            head = code[head_start:i]
            in_function = any(k == "function" for k, _, _ in stack)
            stripped = head.strip()
            if in_function:
                kind = "other"
            elif SCOPE_WORDS.search(stripped) and "(" not in stripped.split("{")[0].split(":")[0]:
                kind = "scope"
            elif FUNCTION_HEAD.search(stripped) and not stripped.startswith("="):
                kind = "function"
            else:
                kind = "other"
            if kind == "function":
                start = head_start + (len(head) - len(head.lstrip()))
                name = re.findall(r"([~\w:]+)\s*\(", stripped)
                stack.append(("function", start, name[0] if name else "?"))
            else:
                stack.append((kind, None, None))
            head_start = i + 1
        elif c == "}":
            if stack:
                kind, start, name = stack.pop()
                if kind == "function":
                    found.append((name, line_at[start], line_at[i]))
            head_start = i + 1
        elif c == ";":
            if not any(k == "function" for k, _, _ in stack):
                head_start = i + 1
    return found


def python_functions(text, path):
    try:
        tree = ast.parse(text, path)
    except SyntaxError:
        return []
    return [
        (node.name, node.lineno, node.end_lineno)
        for node in ast.walk(tree)
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
    ]


def main():
    p = argparse.ArgumentParser()
    p.add_argument(
        "root", nargs="?", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    )
    p.add_argument("--max-file", type=int, default=500)
    p.add_argument("--max-function", type=int, default=80)
    args = p.parse_args()
    failures = []
    files = 0
    for path in source_files(args.root):
        files += 1
        with open(path, encoding="utf-8") as f:
            text = f.read()
        rel = os.path.relpath(path, args.root)
        lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        if lines > args.max_file:
            failures.append(f"{rel}: {lines} lines (at most {args.max_file})")
        if path.endswith(".py"):
            functions = python_functions(text, path)
        elif path.endswith((".h", ".cpp")):
            functions = cpp_functions(text)
        else:
            functions = []
        for name, first, last in functions:
            if last - first + 1 > args.max_function:
                failures.append(
                    f"{rel}:{first}: {name} is {last - first + 1} lines "
                    f"(at most {args.max_function})"
                )
    for f in failures:
        print("FAIL:", f)
    print(f"sizes: {files} files, {len(failures)} over the limits")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
