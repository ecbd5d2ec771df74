#!/usr/bin/env python3
"""scripts/check-sizes.py reads C++ as a compiler does: a digit separator (1'000) is no character
literal, so the braces after it still open and close the function they belong to, and a character
literal's brace ('}') closes nothing.

Usage: check_sizes_test.py SOURCE_DIR"""

import importlib.util
import os
import sys

spec = importlib.util.spec_from_file_location(
    "check_sizes", os.path.join(sys.argv[1], "scripts", "check-sizes.py")
)
sizes = importlib.util.module_from_spec(spec)
spec.loader.exec_module(sizes)

text = (
    "namespace a {\n"
    "int f() {\n"
    "  const long big = 1'000'000'000;  // one function, not a literal to the line's end\n"
    "  if (big > 0xff'ff) {\n"
    "    return '}';\n"
    "  }\n"
    "  return u8'x' + L'y';\n"
    "}\n"
    "int g() { return 2; }\n"
    "}  // namespace a\n"
)
got = sizes.cpp_functions(text)
want = [("f", 2, 8), ("g", 9, 9)]
if got != want:
    print(f"FAIL: functions {got}, expected {want}")
    sys.exit(1)
