"""The names of the files the figures read, as the commands write them (reports/output_files.h
defines them for the C++ side; tests/reports/plot_files_test.py checks that the two agree)."""

REPORT_JSON = "report.json"
CULLED_NPY = "culled.npy"
SAMPLE_CSV = "sample.csv"
RESULTS_JSON = "results.json"
REPRODUCTION_JSON = "reproduction.json"
FRAMES_CSV = "frames.csv"
HOST_CSV = "host.csv"
POINTS_DIR = "points"
