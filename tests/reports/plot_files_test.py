#!/usr/bin/env python3
"""The file names the figures read (reports/rtsim_plots/files.py) are the ones the commands write
(reports/output_files.h, namespace output): REPORT_JSON there is kReportJson here, and so on.
Usage: plot_files_test.py SOURCE_DIR"""
import importlib.util
import os
import re
import sys

src = sys.argv[1]
with open(os.path.join(src, "reports", "output_files.h"), encoding="utf-8") as f:
    cpp = dict(re.findall(r'inline constexpr const char\* (k\w+) = "([^"]*)";', f.read()))
spec = importlib.util.spec_from_file_location(
    "files", os.path.join(src, "reports", "rtsim_plots", "files.py")
)
files = importlib.util.module_from_spec(spec)
spec.loader.exec_module(files)
failed = False
for name in (n for n in dir(files) if n.isupper()):
    cpp_name = "k" + "".join(part.capitalize() for part in name.split("_"))
    if cpp.get(cpp_name) != getattr(files, name):
        print(
            f"FAIL: files.{name} = {getattr(files, name)!r}, "
            f"output::{cpp_name} = {cpp.get(cpp_name)!r}"
        )
        failed = True
print("plot files: " + ("differ" if failed else f"{len(cpp)} names, the figures' agree"))
sys.exit(1 if failed else 0)
