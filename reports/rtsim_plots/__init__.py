"""The figures of reports/plots.py: one module per mode, what they share in common.py."""
