"""Building blocks of the benchmarks (benchlib.py); installed as pdtbench."""
